// The parallel loops on the process's worker pool (parallel.h): every index
// once, the same results for any thread count, loops inside loops, loops from
// several threads at once, and a task's exception carried to the caller; and
// the moves by cubes of space (space_blocks.h): each colour's cubes on the
// workers, each cube's items in order on one of them.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <stdexcept>
#include <thread>
#include <vector>

#include "gdm/parallel.h"
#include "gdm/space_blocks.h"

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

TEST(SpaceBlocks, a_colour_runs_every_item_once_each_cube_in_order_on_one_worker) {
  // (and the colouring is the same whether its order comes from packed keys
  // or from the fields)
  // Points in a 40 x 40 x 40 box, denser in one corner (cubes of unequal
  // work, as the moves' are), grouped by cubes 4 wide.
  std::vector<int> items;
  std::vector<gdm::Vec3> at;
  unsigned state = 12345u;
  const auto next = [&state] {
    state = state * 1664525u + 1013904223u;
    return static_cast<double>(state >> 8) / static_cast<double>(1u << 24);
  };
  for (int i = 0; i < 6000; ++i) {
    items.push_back(3 * i + 1);  // ascending, not the positions' indices
    const double squeeze = i % 3 == 0 ? 0.25 : 1.0;
    at.emplace_back(40.0 * squeeze * next(), 40.0 * squeeze * next(), 40.0 * squeeze * next());
  }
  const double width = 4.0;
  const gdm::CubeColouring cubes = gdm::colour_by_cubes(items, at, width);
  std::vector<int> position(static_cast<std::size_t>(items.back()) + 1, -1);
  for (std::size_t k = 0; k < items.size(); ++k) position[static_cast<std::size_t>(items[k])] = static_cast<int>(k);
  std::size_t listed = 0;
  for (std::size_t c = 0; c < 8; ++c) listed += cubes.items[c].size();
  ASSERT_EQ(listed, items.size());
  // Two million cubes away (an even number: the same colours), beyond the
  // packed keys' reach: ordered by the fields, the same colouring.
  std::vector<gdm::Vec3> far = at;
  for (gdm::Vec3& p : far) p += gdm::Vec3::Constant(2.0e6 * width);
  const gdm::CubeColouring by_fields = gdm::colour_by_cubes(items, far, width);
  for (std::size_t c = 0; c < 8; ++c) {
    EXPECT_EQ(by_fields.items[c], cubes.items[c]) << "colour " << c;
    EXPECT_EQ(by_fields.cube_starts[c], cubes.cube_starts[c]) << "colour " << c;
  }
  for (std::size_t workers : {1u, 2u, 3u, 4u}) {
    for (std::size_t c = 0; c < 8; ++c) {
      const std::vector<int>& list = cubes.items[c];
      const std::vector<std::size_t>& starts = cubes.cube_starts[c];
      ASSERT_EQ(starts.back(), list.size());
      // Per item: how often it ran, on which worker, and its place in that
      // worker's sequence.
      std::vector<std::atomic<int>> runs(list.size());
      std::vector<int> worker_of(list.size(), -1), step_of(list.size(), -1);
      std::vector<int> steps(workers, 0);
      std::vector<std::atomic<int>> running(workers);
      std::atomic<bool> shared_worker{false}, bad_worker{false};
      std::vector<std::size_t> index_of(static_cast<std::size_t>(items.back()) + 1, 0);
      for (std::size_t j = 0; j < list.size(); ++j) index_of[static_cast<std::size_t>(list[j])] = j;
      gdm::run_colour(list, starts, workers, [&](int item, std::size_t w) {
        if (w >= workers) {
          bad_worker = true;
          return;
        }
        if (running[w].fetch_add(1) != 0) shared_worker = true;  // two runs with one number at once
        const std::size_t j = index_of[static_cast<std::size_t>(item)];
        runs[j].fetch_add(1);
        worker_of[j] = static_cast<int>(w);
        step_of[j] = steps[w]++;
        // Uneven work: the squeezed corner's items cost more.
        volatile double s = 0.0;
        for (int k = 0; k < (position[static_cast<std::size_t>(item)] % 3 == 0 ? 400 : 20); ++k) s = s + std::sqrt(k + 1.0);
        running[w].fetch_sub(1);
      });
      ASSERT_FALSE(bad_worker) << "colour " << c << " workers " << workers;
      EXPECT_FALSE(shared_worker) << "colour " << c << " workers " << workers;
      for (std::size_t j = 0; j < list.size(); ++j) ASSERT_EQ(runs[j].load(), 1) << "colour " << c << " item " << j;
      // Within a cube: one worker, the items in their order, one after the other.
      for (std::size_t cube = 0; cube + 1 < starts.size(); ++cube)
        for (std::size_t j = starts[cube] + 1; j < starts[cube + 1]; ++j) {
          ASSERT_EQ(worker_of[j], worker_of[starts[cube]]) << "colour " << c << " cube " << cube;
          ASSERT_EQ(step_of[j], step_of[j - 1] + 1) << "colour " << c << " cube " << cube;
          ASSERT_LT(list[j - 1], list[j]) << "colour " << c << " cube " << cube;
        }
      // Two cubes of one colour lie at least a cube apart.
      for (std::size_t a = 0; a + 1 < starts.size(); ++a)
        for (std::size_t b = a + 1; b + 1 < starts.size(); ++b) {
          const gdm::Vec3& p = at[static_cast<std::size_t>(position[static_cast<std::size_t>(list[starts[a]])])];
          const gdm::Vec3& q = at[static_cast<std::size_t>(position[static_cast<std::size_t>(list[starts[b]])])];
          bool apart = false;
          for (int k = 0; k < 3; ++k)
            apart = apart || std::abs(std::floor(p[k] / width) - std::floor(q[k] / width)) >= 2.0;
          ASSERT_TRUE(apart) << "colour " << c << " cubes " << a << " and " << b;
        }
    }
  }
}
