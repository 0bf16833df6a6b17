// A minimal deterministic parallel loop: the range is cut into fixed chunks,
// each index written by exactly one thread, so results never depend on the
// thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <thread>
#include <vector>

namespace gdm {

// Number of threads to use for `requested` (0 = all hardware threads).
inline int resolve_thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw > 0 ? static_cast<int>(hw) : 1;
}

// Calls body(i) for i in [0, n) on up to `threads` threads.
template <class Body>
void parallel_for(std::size_t n, int threads, Body&& body) {
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)),
                                                    (n + 255) / 256);
  if (workers <= 1) {
    for (std::size_t i = 0; i < n; ++i) body(i);
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  const std::size_t chunk = (n + workers - 1) / workers;
  for (std::size_t w = 1; w < workers; ++w) {
    pool.emplace_back([&, w] {
      const std::size_t end = std::min(n, (w + 1) * chunk);
      for (std::size_t i = w * chunk; i < end; ++i) body(i);
    });
  }
  for (std::size_t i = 0; i < std::min(n, chunk); ++i) body(i);
  for (auto& t : pool) t.join();
}

// Calls body(begin, end, worker) for up to `threads` contiguous chunks of
// [0, n), worker numbering them from 0: for loops whose iterations share a
// per-thread scratch. What each index computes must not depend on the chunk.
template <class Body>
void parallel_chunks(std::size_t n, int threads, Body&& body) {
  const std::size_t workers = std::min<std::size_t>(static_cast<std::size_t>(std::max(1, threads)),
                                                    (n + 255) / 256);
  if (workers <= 1) {
    body(std::size_t{0}, n, std::size_t{0});
    return;
  }
  std::vector<std::thread> pool;
  pool.reserve(workers - 1);
  const std::size_t chunk = (n + workers - 1) / workers;
  for (std::size_t w = 1; w < workers; ++w)
    pool.emplace_back([&, w] { body(std::min(n, w * chunk), std::min(n, (w + 1) * chunk), w); });
  body(std::size_t{0}, std::min(n, chunk), std::size_t{0});
  for (auto& t : pool) t.join();
}

}  // namespace gdm
