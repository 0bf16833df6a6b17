// A floating-point filter for the self-intersection guard's exact triangle
// test (predicates.h): a separating axis (Gottschalk's theorem for convex
// polytopes) among the in-plane edge normals and the edge-edge cross
// products, tested with a margin far above rounding error, proves that two
// triangles meet at most in a shared vertex. The guard meets many coplanar
// neighbours (the flat faces of a cube after the fit), where the triangles'
// own planes separate nothing and the exact code was most of its time
// (issue 17).
#pragma once

#include <array>

#include "gdm/mesh.h"

namespace gdm {

// 0: provably no improper contact (disjoint, or meeting only in their one
// shared vertex); -1: cannot tell (the exact code decides). Triangles with
// two or more shared vertices, repeated ids, a shared id at different
// coordinates, or nearly degenerate ones always give -1.
int separated_by_an_axis(const std::array<Vec3, 3>& t1, const std::array<int, 3>& ids1,
                         const std::array<Vec3, 3>& t2, const std::array<int, 3>& ids2);

}  // namespace gdm
