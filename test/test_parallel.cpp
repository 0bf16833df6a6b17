// The parallel loops on the process's worker pool (parallel.h): every index
// once, the same results for any thread count, loops inside loops, loops from
// several threads at once, and a task's exception carried to the caller.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <vector>

#include "gdm/parallel.h"

namespace {

// Uneven work per index (as the vertices' is): index i costs i % 97 steps.
double uneven(std::size_t i) {
  double s = 0.0;
  for (std::size_t k = 0; k < i % 97; ++k) s += std::sqrt(static_cast<double>(i + k));
  return s;
}

std::vector<double> computed(std::size_t n, int threads) {
  std::vector<double> out(n, -1.0);
  gdm::parallel_for(n, threads, [&](std::size_t i) { out[i] = uneven(i); });
  return out;
}

}  // namespace

TEST(Parallel, every_index_once_and_the_same_for_any_thread_count) {
  for (std::size_t n : {0u, 1u, 255u, 256u, 257u, 1000u, 12345u}) {
    std::vector<std::atomic<int>> visits(n);
    gdm::parallel_for(n, 3, [&](std::size_t i) { visits[i].fetch_add(1); });
    for (std::size_t i = 0; i < n; ++i) ASSERT_EQ(visits[i].load(), 1) << "n " << n << " index " << i;
    const std::vector<double> one = computed(n, 1);
    for (int threads : {2, 3, 4, 8}) EXPECT_EQ(computed(n, threads), one) << "n " << n << " threads " << threads;
  }
}

TEST(Parallel, chunks_cover_the_range_with_distinct_workers) {
  const std::size_t n = 5000;
  for (int threads : {1, 2, 4}) {
    std::vector<int> owner(n, -1);
    std::vector<std::atomic<int>> running(static_cast<std::size_t>(threads));
    std::atomic<bool> shared_worker{false};
    gdm::parallel_chunks(n, threads, [&](std::size_t begin, std::size_t end, std::size_t worker) {
      ASSERT_LT(worker, static_cast<std::size_t>(threads));
      if (running[worker].fetch_add(1) != 0) shared_worker = true;  // two chunks with one number at once
      for (std::size_t i = begin; i < end; ++i) owner[i] = static_cast<int>(worker);
      running[worker].fetch_sub(1);
    });
    EXPECT_FALSE(shared_worker);
    for (std::size_t i = 0; i < n; ++i) ASSERT_GE(owner[i], 0) << "index " << i << " threads " << threads;
    // Contiguous chunks in worker order.
    for (std::size_t i = 1; i < n; ++i) ASSERT_GE(owner[i], owner[i - 1]);
  }
}

TEST(Parallel, a_loop_inside_a_loop_and_loops_from_several_threads) {
  // The inner loops find the pool busy and start threads of their own.
  std::vector<double> sums(600, 0.0);
  gdm::parallel_for(sums.size(), 2, [&](std::size_t i) {
    const std::vector<double> inner = computed(300, 2);
    double s = 0.0;
    for (double x : inner) s += x;
    sums[i] = s + static_cast<double>(i);
  });
  double expected = 0.0;
  for (double x : computed(300, 1)) expected += x;
  for (std::size_t i = 0; i < sums.size(); ++i) ASSERT_EQ(sums[i], expected + static_cast<double>(i));

  std::vector<std::vector<double>> results(4);
  std::vector<std::thread> callers;
  for (std::size_t t = 0; t < results.size(); ++t)
    callers.emplace_back([&, t] {
      for (int rep = 0; rep < 20; ++rep) results[t] = computed(3000 + t, 2);
    });
  for (auto& c : callers) c.join();
  for (std::size_t t = 0; t < results.size(); ++t) EXPECT_EQ(results[t], computed(3000 + t, 1));
}

TEST(Parallel, a_task_exception_reaches_the_caller_after_the_other_tasks_ran) {
  std::vector<std::atomic<int>> visits(4000);
  EXPECT_THROW(gdm::parallel_for(visits.size(), 2,
                                 [&](std::size_t i) {
                                   visits[i].fetch_add(1);
                                   if (i == 1234) throw std::runtime_error("task 1234 failed");
                                 }),
               std::runtime_error);
  // Each index at most once; only the rest of the failed task's block (at
  // most a sixteenth of the range on two threads) is left out.
  int total = 0;
  for (std::size_t i = 0; i < visits.size(); ++i) {
    ASSERT_LE(visits[i].load(), 1) << i;
    total += visits[i].load();
  }
  EXPECT_GE(total, static_cast<int>(visits.size() - visits.size() / 16));
  EXPECT_EQ(visits.front().load(), 1);
  EXPECT_EQ(visits.back().load(), 1);
  // The pool serves the next loop as before.
  EXPECT_EQ(computed(2000, 2), computed(2000, 1));
}
