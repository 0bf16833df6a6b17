// A grid of voxels (x fastest) as the voxel passes walk it: a voxel's index
// and place, the grid's border, a walk in index order. The cavity fill
// (cavities.h) and the voxel seed (voxel_seed.h) work on it.
#pragma once

#include <cstddef>

#include "gdm/volume.h"

namespace gdm {

struct VoxelGrid {
  Index3 n{0, 0, 0};
  std::size_t count() const {
    return static_cast<std::size_t>(n[0]) * static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(n[2]);
  }
  std::size_t index(int i, int j, int k) const {
    return static_cast<std::size_t>(i) +
           static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k));
  }
  // The place of index c: three integer divisions (loops over the whole
  // grid use for_each_voxel instead).
  Index3 voxel(std::size_t c) const {
    const std::size_t nx = static_cast<std::size_t>(n[0]), ny = static_cast<std::size_t>(n[1]);
    return {static_cast<int>(c % nx), static_cast<int>((c / nx) % ny), static_cast<int>(c / (nx * ny))};
  }
  bool on_border(const Index3& v) const {
    return v[0] == 0 || v[1] == 0 || v[2] == 0 || v[0] == n[0] - 1 || v[1] == n[1] - 1 || v[2] == n[2] - 1;
  }
  // Calls f(index, voxel) for every voxel in index order (issue 17: each
  // voxel's place without the divisions).
  template <typename F>
  void for_each_voxel(F&& f) const {
    std::size_t c = 0;
    Index3 v;
    for (v[2] = 0; v[2] < n[2]; ++v[2])
      for (v[1] = 0; v[1] < n[1]; ++v[1])
        for (v[0] = 0; v[0] < n[0]; ++v[0], ++c) f(c, static_cast<const Index3&>(v));
  }
};

}  // namespace gdm
