// Single-precision output without losing the guarantees. MeshLab, STL, binary
// PLY and itk::Mesh<float> store float coordinates; rounding a mesh whose
// sheets come within a float's spacing of each other can make faces cross.
// snap_to_float moves every vertex to a float-representable point, each move
// checked by the exact-predicate guard, so the rounded mesh is the mesh.
#pragma once

#include <cstddef>

#include "gdm/mesh.h"

namespace gdm {

struct FloatSnapResult {
  std::size_t snapped = 0;   // vertices moved onto a float-representable point (or already on one)
  std::size_t refused = 0;   // vertices left in double precision: every nearby float point was unsafe
  double largest_move = 0.0; // mm
};

// Tries, per vertex, the nearest float point, then the other corners of the
// float cell around it, then the float points up to five floats from the
// nearest along each axis, nearest first; keeps the first one the guard
// accepts. The mesh must be free of self-intersections on entry; it stays so.
// `refused` is 0 in practice; when not, those vertices still round
// (unchecked) when stored as float.
// `threads`: for the guard's checks (0 = all hardware threads); the result is
// the same for any count.
FloatSnapResult snap_to_float(Mesh& mesh, int threads = 1);

// x rounded to the nearest float, as a double. Use this, not an element-wise
// `p[i] = static_cast<float>(p[i])` loop: GCC 12.2 at -O2 vectorises such a
// loop over three doubles and drops the round trip of the first two (seen
// here, Debian's 12.2.0-14: only the third element is converted).
double round_to_float(double x);

// The point with every coordinate rounded to the nearest float.
Vec3 round_to_float(const Vec3& p);

// True when every coordinate of every vertex is exactly a float.
bool is_float_exact(const Mesh& mesh);

// The self-intersecting face pairs of the mesh with every vertex rounded to
// float, as a float format stores it (0 without a copy when the mesh is
// float-exact). What a run checks when snap_to_float refused vertices.
std::size_t pairs_crossing_when_rounded(const Mesh& mesh, int threads = 0);

}  // namespace gdm
