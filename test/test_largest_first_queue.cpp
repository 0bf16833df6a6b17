// The radix queue of the cavity fill's growths (largest_first_queue.h)
// against std::priority_queue of the same pairs: the same indices in the same
// order, for pushes below and above the last key popped, keys drawn from a
// few values (ties settled by the index), from the whole 64-bit range, and
// keys as the growths make them (a float's bits above a hash).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <queue>
#include <random>
#include <utility>
#include <vector>

#include "gdm/largest_first_queue.h"

namespace gdm {
namespace {

// Runs `steps` random pushes and pops on both queues, each index in a queue
// at most once at a time (as in the growths), and counts the pops in which
// they disagree. `draw` gives a push's key.
template <typename Draw>
int disagreements(std::uint32_t seed, int steps, double push_share, Draw&& draw) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  LargestFirstQueue ours;
  std::priority_queue<std::pair<std::uint64_t, std::size_t>> reference;
  std::vector<char> queued(4096, 0);
  std::uniform_int_distribution<std::size_t> pick(0, queued.size() - 1);
  int wrong = 0;
  for (int step = 0; step < steps; ++step) {
    if (!reference.empty() && coin(random) > push_share) {
      const std::size_t expected = reference.top().second;
      reference.pop();
      const std::size_t got = ours.pop();
      wrong += got != expected;
      queued[expected] = 0;
      continue;
    }
    const std::size_t index = pick(random);
    if (queued[index]) continue;
    queued[index] = 1;
    const std::uint64_t key = draw(random);
    ours.push(key, index);
    reference.push({key, index});
    EXPECT_EQ(ours.size(), reference.size());
  }
  while (!reference.empty()) {
    wrong += ours.pop() != reference.top().second;
    reference.pop();
  }
  EXPECT_TRUE(ours.empty());
  return wrong;
}

TEST(LargestFirstQueue, pops_as_a_binary_heap_with_keys_from_the_whole_range) {
  for (std::uint32_t seed = 1; seed <= 20; ++seed)
    for (double push_share : {0.3, 0.5, 0.7})
      EXPECT_EQ(disagreements(seed, 20000, push_share, [](std::mt19937_64& r) { return r(); }), 0)
          << "seed " << seed << ", push share " << push_share;
}

TEST(LargestFirstQueue, pops_ties_largest_index_first) {
  // Eight key values: most pushes tie with queued pairs, and many are above
  // the last key popped.
  for (std::uint32_t seed = 1; seed <= 20; ++seed)
    EXPECT_EQ(disagreements(seed, 20000, 0.55, [](std::mt19937_64& r) { return (r() % 8) * 1000; }), 0)
        << "seed " << seed;
}

TEST(LargestFirstQueue, pops_as_a_binary_heap_with_the_growths_keys) {
  // Squared distances between voxel centres on an anisotropic grid above a
  // 32-bit hash, as growth_key (cavities.cpp) makes them; keys pushed near
  // the last popped one, as a growth front does, some larger.
  for (std::uint32_t seed = 1; seed <= 20; ++seed) {
    std::uint64_t hash = seed;
    EXPECT_EQ(disagreements(seed, 30000, 0.5,
                            [&](std::mt19937_64& r) {
                              const float h[3] = {0.9375f, 0.9375f, 1.5f};
                              float d2 = 0.0f;
                              for (float s : h) {
                                const float k = static_cast<float>(r() % 12);
                                d2 += (k * s) * (k * s);
                              }
                              std::uint32_t bits = 0;
                              std::memcpy(&bits, &d2, sizeof bits);
                              hash = hash * 6364136223846793005ull + 1442695040888963407ull;
                              return (static_cast<std::uint64_t>(bits) << 32) | (hash >> 32);
                            }),
              0)
        << "seed " << seed;
  }
}

}  // namespace
}  // namespace gdm
