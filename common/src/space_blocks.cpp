#include "gdm/space_blocks.h"

#include <cmath>
#include <cstdint>

namespace gdm {

CubeColouring colour_by_cubes(const std::vector<int>& items, const std::vector<Vec3>& points, double width) {
  struct Keyed {
    std::array<std::int64_t, 3> cube;
    int colour;
    std::size_t order;  // the item's place in `items`
  };
  std::vector<Keyed> keyed(items.size());
  for (std::size_t k = 0; k < items.size(); ++k) {
    Keyed& e = keyed[k];
    for (std::size_t a = 0; a < 3; ++a)
      e.cube[a] = static_cast<std::int64_t>(std::floor(points[k][static_cast<Eigen::Index>(a)] / width));
    e.colour = static_cast<int>((e.cube[0] & 1) | ((e.cube[1] & 1) << 1) | ((e.cube[2] & 1) << 2));
    e.order = k;
  }
  std::sort(keyed.begin(), keyed.end(), [](const Keyed& a, const Keyed& b) {
    if (a.colour != b.colour) return a.colour < b.colour;
    if (a.cube != b.cube) return a.cube < b.cube;
    return a.order < b.order;
  });
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
