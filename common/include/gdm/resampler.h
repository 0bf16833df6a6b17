// Resampling of the model (paper section 4): local splitting of faces larger
// than the level of detail, the global 1-to-4 refinement, and edge flips that
// keep triangles well shaped.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

#include "gdm/mesh.h"

namespace gdm {

// Local resampling: the longest edge of every face whose area exceeds
// `max_face_area` (mm^2) is split at its midpoint, together with the face on
// the other side, so all faces stay triangles and the mesh stays conforming
// (no T-junction). One pass; faces still too large are split again on the next
// call. New vertices get `generation`. Returns the number of edges split.
// The new triangles lie inside the old ones, so no split can create an
// intersection.
std::size_t split_large_faces(Mesh& mesh, double max_face_area, int generation);

// The mechanism under split_large_faces (and the error-driven level of
// detail's splits): in one pass, the longest edge of every face that
// `select(face, longest halfedge)` accepts is split at its midpoint (each edge
// at most once; new vertices get `generation`). Returns the number of splits.
// With `only_faces`, faces whose flag is 0 (or beyond its end) are not asked
// (the caller knows select refuses them): the same splits in the same order
// for a pass proportional to the faces that changed.
using SplitSelect = std::function<bool(Mesh::FaceHandle, Mesh::HalfedgeHandle)>;
std::size_t split_longest_edges(Mesh& mesh, int generation, const SplitSelect& select,
                                const std::vector<char>* only_faces = nullptr);

// Global resampling (Fig. 5): every face becomes four by joining the edge
// midpoints. V, E, F become V + E, 2E + 3F, 4F. New vertices get `generation`.
void subdivide_all(Mesh& mesh, int generation);

// Edge flips that make the triangulation closer to Delaunay on nearly flat
// regions (the dihedral angle across the edge within `max_dihedral_deg` of
// flat). `allow(edge, quad)` is asked before each flip; the flip would create
// the triangles (quad[0], quad[1], quad[3]) and (quad[2], quad[3], quad[1]);
// returning false vetoes it (used by the self-intersection guard). Returns the
// number of flips.
// With `dirty` (one flag per edge, grown to the edges by the call), only the
// flagged edges are considered, in edge order: the caller flags every edge of
// every face around a vertex that moved or whose faces changed since the last
// pass. The call clears the flag of each edge it looked at, sets it again on
// an edge `allow` vetoed (its neighbourhood may change without its own quad),
// and flags every edge of the faces around the four vertices of each flip
// (their quads, valences and links changed), so later edges of the same pass
// see them as a full pass would: the same flips as a pass over every edge.
using FlipVeto = std::function<bool(Mesh::EdgeHandle, const Mesh::VertexHandle (&)[4])>;
std::size_t flip_to_improve(Mesh& mesh, double max_dihedral_deg, const FlipVeto& allow,
                            std::vector<char>* dirty = nullptr);

// Fairing: each of `vertices`, in order (the same result for any thread
// count), moves `fraction` of the way toward the centroid of its neighbours,
// at most `max_move` (mm) a pass, where `accept(vertex, new position)` allows
// it (the caller's self-intersection guard, region and obstacle checks);
// `before_pass` runs before every pass (the guard's rebuild). Stops after
// `passes` passes or when no move exceeded a hundredth of `max_move`.
// Returns the moves made. Used for the caps over openings (the gap, the wrap).
using MoveCheck = std::function<bool(Mesh::VertexHandle, const Vec3&)>;
std::size_t relax_toward_neighbours(Mesh& mesh, const std::vector<Mesh::VertexHandle>& vertices, double fraction,
                                    double max_move, int passes, const std::function<void()>& before_pass,
                                    const MoveCheck& accept);

// The vertices with an edge whose two faces turn by more than
// `max_dihedral_deg` (or meet in a degenerate face): one flag per vertex.
std::vector<char> crease_vertices(const Mesh& mesh, double max_dihedral_deg);

// Tangential relaxation (beyond the paper, issue 16): each vertex not `held`
// (one flag per vertex; boundary vertices stay too), in vertex order (the
// same result for any thread count), moves `fraction` of the way toward the
// centroid of its neighbours within the plane of its area-weighted normal,
// at most `max_move` (mm) a pass, where `accept(vertex, new position)`
// allows it; `before_pass` runs before every pass. The triangles' angles
// and sizes grow more even while the surface keeps its shape to second order
// (a move of t along a surface of curvature k leaves it by about k t^2 / 2,
// which a fit along the normal takes back). Stops after `passes` passes or
// when no move exceeded a hundredth of `max_move`. Returns the moves made.
std::size_t relax_tangentially(Mesh& mesh, const std::vector<char>& held, double fraction, double max_move, int passes,
                               const std::function<void()>& before_pass, const MoveCheck& accept);

}  // namespace gdm
