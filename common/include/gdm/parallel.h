// A minimal deterministic parallel loop: each index is computed by exactly
// one thread and what it computes does not depend on which, so results never
// depend on the thread count.
//
// The loops run on a process-wide pool of workers started on first use and
// kept (issue 17): a deformation calls these loops thousands of times (every
// cycle, every fit pass), and starting threads for each call, with fresh
// thread_local scratch each time, cost 5 % of the T1 head's run. Indices are
// handed out in small blocks on demand, so a thread whose block was cheap
// takes the next one (the vertices' work differs a lot).
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <thread>

namespace gdm {

// Number of threads to use for `requested` (0 = all hardware threads).
inline int resolve_thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 1;
}

namespace detail {

// Calls task(k) once for every k in [0, tasks) on up to `threads` threads,
// the caller's among them, and returns when all have returned. On the pool
// when it is free; when it is busy (a loop inside a loop's task, or another
// thread's loop) on threads started for this call. The first exception a task
// throws is rethrown here once every task has run.
void run_tasks(std::size_t tasks, int threads, const std::function<void(std::size_t)>& task);

// Blocks per thread for parallel_for: enough to even out uneven work.
constexpr std::size_t kBlocksPerThread = 8;

}  // namespace detail

// Calls body(i) for i in [0, n) on up to `threads` threads.
template <class Body>
void parallel_for(std::size_t n, int threads, Body&& body) {
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)),
                                                    (n + 255) / 256);
  if (workers <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  const std::size_t size = std::max<std::size_t>(64, (n + workers * detail::kBlocksPerThread - 1) /
                                                         (workers * detail::kBlocksPerThread));
  detail::run_tasks((n + size - 1) / size, static_cast<int>(workers), [&](std::size_t block) {
    const std::size_t end = std::min(n, (block + 1) * size);
    for (std::size_t i = block * size; i < end; ++i) body(i);
  });
}

// Calls body(begin, end, worker) for up to `threads` contiguous chunks of
// [0, n), worker numbering them from 0 (no two chunks with the same number
// run at once): for loops whose iterations share a per-worker scratch. What
// each index computes must not depend on the chunk.
template <class Body>
void parallel_chunks(std::size_t n, int threads, Body&& body) {
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)),
                                                    (n + 255) / 256);
  if (workers <= 1) {
    body(std::size_t{0}, n, std::size_t{0});
    return;
  }
  const std::size_t chunk = (n + workers - 1) / workers;
  detail::run_tasks(workers, static_cast<int>(workers), [&](std::size_t w) {
    body(std::min(n, w * chunk), std::min(n, (w + 1) * chunk), w);
  });
}

}  // namespace gdm
