// The topology of a set of voxels, cheaply: its Euler characteristic, its
// connected pieces and the pockets of the complement it encloses, hence its
// number of handles (genus). The cavity fill (cavities.h) asks it whether the
// object's region has any handle before it grows the outside voxel by voxel
// to cap handles: a region without one needs no growth (issue 17).
//
// A voxel is a closed unit cube: the set's pieces are its 26-connected
// components and the complement's its 6-connected ones, the pairing the
// handle growth's simple-point test uses (Bertrand and Malandain 1994).
#pragma once

#include <cstdint>
#include <vector>

#include "gdm/volume.h"

namespace gdm {

struct VoxelTopology {
  std::int64_t euler = 0;      // chi = pieces - handles + cavities
  std::int64_t pieces = 0;     // 26-connected components of the set
  std::int64_t cavities = 0;   // 6-connected components of the complement that do not touch the grid's border
  std::int64_t handles() const { return pieces + cavities - euler; }  // the first Betti number
};

// Euler characteristic of the union of the closed cubes of the voxels set in
// `set` (an n[0] x n[1] x n[2] grid, x fastest): vertices - edges + faces -
// cubes of that cubical complex, counted in one pass over the 2 x 2 x 2
// windows of the grid. Work: one pass over the grid.
std::int64_t euler_characteristic(const std::vector<char>& set, const Index3& n);

// Euler characteristic, pieces and enclosed pockets of the set: a few
// passes over the grid (two floods).
VoxelTopology voxel_topology(const std::vector<char>& set, const Index3& n);

}  // namespace gdm
