// A priority queue of (key, index) pairs that pops the largest pair first,
// in exactly the order std::priority_queue<std::pair<std::uint64_t,
// std::size_t>> pops them, for the voxel growths of cavities.h (the
// handles' membranes and cuts: millions of pops on a head scan, where the
// binary heap's sift-down missed the cache at nearly every level; issue 17,
// perf on the T1 head: the heap was about half of cap_handles).
//
// A radix heap (Ahuja, Mehlhorn, Orlin and Tarjan 1990) on the complemented
// keys: bucket b holds the keys whose highest bit differing from the last
// key popped is bit b - 1 (bucket 0: equal to it), so a pop only scans and
// splits the lowest non-empty bucket, and each pair moves down a bucket at a
// time. A radix heap needs every key pushed to be no larger (here) than the
// last popped; a growth may queue a larger one (a voxel refused earlier
// whose neighbourhood changed): those wait in a small binary heap and go
// first, as they are larger than every key in the buckets. Pairs of equal key
// pop largest index first, as the pair's order has it.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <queue>
#include <utility>
#include <vector>

namespace gdm {

class LargestFirstQueue {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }

  void push(std::uint64_t key, std::size_t index) {
    ++size_;
    const std::uint64_t k = ~key;  // smallest first
    if (k < last_)
      early_.push({key, index});
    else
      buckets_[bucket_of(k)].push_back({k, index});
  }

  // The largest pair's index (the queue must not be empty), removed.
  std::size_t pop() {
    --size_;
    if (!early_.empty()) {
      const std::size_t index = early_.top().second;
      early_.pop();
      return index;
    }
    if (buckets_[0].empty()) refill();
    std::vector<Entry>& equal = buckets_[0];  // every key here is last_
    std::size_t best = 0;
    for (std::size_t i = 1; i < equal.size(); ++i)
      if (equal[i].index > equal[best].index) best = i;
    const std::size_t index = equal[best].index;
    equal[best] = equal.back();
    equal.pop_back();
    return index;
  }

 private:
  struct Entry {
    std::uint64_t key;  // complemented
    std::size_t index;
  };

  std::size_t bucket_of(std::uint64_t k) const {
    return k == last_ ? 0 : static_cast<std::size_t>(64 - __builtin_clzll(k ^ last_));
  }

  // The lowest non-empty bucket's smallest key becomes last_, and the
  // bucket's pairs go to the buckets below it.
  void refill() {
    std::size_t b = 1;
    while (buckets_[b].empty()) ++b;
    std::vector<Entry>& from = buckets_[b];
    std::uint64_t least = from.front().key;
    for (const Entry& e : from) least = std::min(least, e.key);
    last_ = least;
    for (const Entry& e : from) buckets_[bucket_of(e.key)].push_back(e);
    from.clear();
  }

  std::array<std::vector<Entry>, 65> buckets_;
  std::priority_queue<std::pair<std::uint64_t, std::size_t>> early_;  // keys above the last popped
  std::uint64_t last_ = 0;  // the complement of the last key popped from the buckets
  std::size_t size_ = 0;
};

}  // namespace gdm
