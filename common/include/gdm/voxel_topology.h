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

#include <array>
#include <cstddef>
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

// Index offsets of the 27 voxels of a 3 x 3 x 3 neighbourhood on an n[0] x
// n[1] x n[2] grid (x fastest): slot (dx + 1) + 3 (dy + 1) + 9 (dz + 1),
// the centre is slot 13.
std::array<std::ptrdiff_t, 27> neighbour_offsets(const Index3& n);

// Whether a voxel may join a growing set without changing the topology of
// either side (a simple point, Bertrand and Malandain 1994). `reached` holds
// the set's voxels among the 27 of its neighbourhood as bits, slot (dx + 1)
// + 3 (dy + 1) + 9 (dz + 1) (the centre's bit, 13, is ignored). The same test
// says whether a voxel of the set may leave it.
class SimplePointTest {
 public:
  static constexpr int kCentre = 13;
  SimplePointTest();
  // A set taken with 6-adjacency, its complement with 26 (the background
  // grown from outside): one 6-component of the set in the 18-neighbourhood
  // 6-adjacent to the voxel, and one 26-component of the rest in its
  // 26-neighbourhood.
  bool simple_for_background(std::uint32_t reached) const {
    return components(reached & n18_, adjacent6_, faces_) == 1 && components(~reached & n26_, adjacent26_, n26_) == 1;
  }
  // A set taken with 26-adjacency, its complement with 6 (the object grown
  // from inside): one 26-component of the set in the 26-neighbourhood, and
  // one 6-component of the rest in the 18-neighbourhood 6-adjacent to the voxel.
  bool simple_for_object(std::uint32_t reached) const {
    return components(reached & n26_, adjacent26_, n26_) == 1 && components(~reached & n18_, adjacent6_, faces_) == 1;
  }

 private:
  // Components of `set` (a mask) under `adjacency`, counting only those that
  // meet `must_meet`.
  static int components(std::uint32_t set, const std::array<std::uint32_t, 27>& adjacency, std::uint32_t must_meet);

  std::array<std::uint32_t, 27> adjacent6_{}, adjacent26_{};
  std::uint32_t faces_ = 0, n18_ = 0, n26_ = 0;
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
