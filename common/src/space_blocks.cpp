#include "gdm/space_blocks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <utility>

namespace gdm {

namespace {

// A cube's coordinates fit a packed key when each lies within 2^19 of 0.
constexpr std::int64_t kPackedReach = std::int64_t{1} << 19;

}  // namespace

CubeColouring colour_by_cubes(const std::vector<int>& items, const std::vector<Vec3>& points, double width) {
  struct Keyed {
    std::array<std::int64_t, 3> cube;
    int colour;
  };
  std::vector<Keyed> keyed(items.size());
  bool packable = true;
  for (std::size_t k = 0; k < items.size(); ++k) {
    Keyed& e = keyed[k];
    for (std::size_t a = 0; a < 3; ++a) {
      e.cube[a] = static_cast<std::int64_t>(std::floor(points[k][static_cast<Eigen::Index>(a)] / width));
      packable = packable && e.cube[a] > -kPackedReach && e.cube[a] < kPackedReach;
    }
    e.colour = static_cast<int>((e.cube[0] & 1) | ((e.cube[1] & 1) << 1) | ((e.cube[2] & 1) << 2));
  }
  // The items' places in the order of their colour, then their cube's
  // coordinates, then their own place. Sorted as one 64-bit key per item
  // (colour in bits 60 to 62, each coordinate in 20 bits above its offset:
  // the same order) with its place, cheaper than comparing the fields
  // (issue 17: this sort runs on one thread before every round of moves by
  // cubes); by the fields where a coordinate does not fit.
  std::vector<std::size_t> order(items.size());
  if (packable) {
    std::vector<std::pair<std::uint64_t, std::size_t>> packed(keyed.size());
    for (std::size_t k = 0; k < keyed.size(); ++k) {
      std::uint64_t key = static_cast<std::uint64_t>(keyed[k].colour);
      for (std::size_t a = 0; a < 3; ++a) key = (key << 20) | static_cast<std::uint64_t>(keyed[k].cube[a] + kPackedReach);
      packed[k] = {key, k};
    }
    std::sort(packed.begin(), packed.end());
    for (std::size_t j = 0; j < packed.size(); ++j) order[j] = packed[j].second;
  } else {
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(), [&](std::size_t i, std::size_t j) {
      const Keyed& a = keyed[i];
      const Keyed& b = keyed[j];
      if (a.colour != b.colour) return a.colour < b.colour;
      if (a.cube != b.cube) return a.cube < b.cube;
      return i < j;
    });
  }
  CubeColouring out;
  for (std::size_t j = 0; j < order.size(); ++j) {
    const Keyed& e = keyed[order[j]];
    const auto c = static_cast<std::size_t>(e.colour);
    if (j == 0 || keyed[order[j - 1]].cube != e.cube) out.cube_starts[c].push_back(out.items[c].size());
    out.items[c].push_back(items[order[j]]);
  }
  for (std::size_t c = 0; c < 8; ++c) out.cube_starts[c].push_back(out.items[c].size());
  return out;
}

}  // namespace gdm
