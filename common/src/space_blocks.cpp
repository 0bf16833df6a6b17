#include "gdm/space_blocks.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <cstdint>

namespace gdm {

namespace {

// A cube's coordinates fit a packed key when each lies within 2^19 of 0.
constexpr std::int64_t kPackedReach = std::int64_t{1} << 19;

}  // namespace

CubeColouring colour_by_cubes(const std::vector<int>& items, const std::vector<Vec3>& points, double width) {
  struct Keyed {
    std::array<std::int64_t, 3> cube;
    int colour;
    std::size_t order;  // the item's place in `items`
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
    e.order = k;
  }
  // Colour, then the cube's coordinates, then the item's order. Sorted as
  // one 64-bit key per item (colour in bits 60 to 62, each coordinate in 20
  // bits above its offset: the same order) with its place, cheaper than
  // comparing the fields (issue 17: this sort runs on one thread before
  // every round of moves by cubes).
  if (packable) {
    std::vector<std::pair<std::uint64_t, std::size_t>> packed(keyed.size());
    for (std::size_t k = 0; k < keyed.size(); ++k) {
      const Keyed& e = keyed[k];
      std::uint64_t key = static_cast<std::uint64_t>(e.colour);
      for (std::size_t a = 0; a < 3; ++a) key = (key << 20) | static_cast<std::uint64_t>(e.cube[a] + kPackedReach);
      packed[k] = {key, k};
    }
    std::sort(packed.begin(), packed.end());
    std::vector<Keyed> sorted(keyed.size());
    for (std::size_t j = 0; j < packed.size(); ++j) sorted[j] = keyed[packed[j].second];
    keyed.swap(sorted);
  } else {
    std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
      if (a.colour != b.colour) return a.colour < b.colour;
      if (a.cube != b.cube) return a.cube < b.cube;
      return a.order < b.order;
    });
  }
  CubeColouring out;
  for (std::size_t j = 0; j < keyed.size(); ++j) {
    const auto c = static_cast<std::size_t>(keyed[j].colour);
    if (j == 0 || keyed[j - 1].cube != keyed[j].cube) out.cube_starts[c].push_back(out.items[c].size());
    out.items[c].push_back(items[keyed[j].order]);
  }
  for (std::size_t c = 0; c < 8; ++c) out.cube_starts[c].push_back(out.items[c].size());
  return out;
}

}  // namespace gdm
