// Vertices and faces renumbered so that elements near each other in space
// are near each other in memory (issue 17: "data laid out for the cache").
// A deforming model appends every vertex a split makes at the end of the
// arrays, so after a growth and a 1-to-4 resampling the neighbours of a
// vertex lie scattered over the whole mesh; on the T1 head's 370,000-face
// model the cycles' neighbourhood gathers waited on cache misses for a tenth
// of the run. Sorted along a Z-order (Morton) curve, the walks over a
// vertex's rings, the guard's face lookups and the volume's samples for
// consecutive vertices touch the same cache lines.
#pragma once

#include <vector>

#include "gdm/mesh.h"

namespace gdm {

// Renumbers the vertices of `mesh` along the Z-order curve of the grid of
// cubes of edge `cell` (mm; > 0) that holds them, ties by the old index,
// and the faces by their smallest new vertex index (then the old index), so
// edges and halfedges follow. Each face keeps its orientation, each vertex
// its point and generation ("v:generation", when present); other properties
// and the status flags are not carried over (call it between passes).
// Deleted elements are dropped. Deterministic: the order depends only on
// the points and the old order. Returns the new index of each old vertex
// (-1: deleted). A mesh OpenMesh cannot rebuild face by face (not a
// 2-manifold) is left as it is, and the indices returned are its own.
std::vector<int> sort_spatially(Mesh& mesh, double cell);

}  // namespace gdm
