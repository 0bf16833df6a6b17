// A seed with the object's own shape at the voxel's scale (beyond the paper,
// issues 16 and 17). Section 7: the seed's size and shape change only the
// time. A model grown from a small seed pays for every voxel its front
// crosses, and where the object is a thin shell reached through one place
// (a scalp over a dark skull layer, reached from the brain through a few
// bridges) its front spreads round the shell and meets itself: the
// genus-0 model cannot merge two fronts, so it keeps two sheets pressed
// together across the object (the seams of self_contact.h, a third of the
// T1 head's model).
//
// Here the object's voxels are taken first, from the seed's deepest voxel,
// the deepest first (largest distance to the background), each one only
// when it is a simple point (26-adjacency for the set, 6 for the rest;
// Bertrand and Malandain 1994): the set stays a topological ball, and a
// place the growth reaches from two sides is taken as soon as taking it
// no longer closes a loop, so no crack is left where fronts meet unless
// the object itself has a handle there (the cavity fill caps handles
// first). Every step also keeps the set well-composed (Latecki 1997: no two
// voxels of the set, nor two of the rest, meet only along an edge or at a
// corner), taking up to eight neighbours with it, background voxels too,
// where that is what keeps it so; its boundary faces (the cuberille) are
// then a closed 2-manifold, genus 0, without self-intersection. They are
// collapsed, least quadric error first, to about the level of detail's
// faces (face_budget.h's reduction, every collapse guarded), and the model
// starts from there: its vertices travel the last voxel.
#pragma once

#include <cstddef>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace gdm {

struct VoxelSeedOptions {
  double threshold = 0.0;        // T of eq. 2
  bool object_brighter = true;   // the object lies above T
  double face_area = 2.5;        // voxel^2: the faces the reduction aims at, about (the level of detail's)
  bool reduce = true;            // false: the voxels' faces as they are (two triangles per voxel face)
  int threads = 0;               // workers for the distance transform and the reduction's checks (0 = all
                                 // cores); the seed does not depend on it
  bool crop = true;              // grow the ball in a crop of the grid around the object's region (the
                                 // same ball: the crop is used only where it gives the whole grid's);
                                 // false = on the whole grid
};

// The ball of voxels grown from one voxel (what make_voxel_seed meshes).
struct VoxelBall {
  Index3 dims{0, 0, 0};          // its box of the volume's grid (the whole grid, or a crop)
  Index3 offset{0, 0, 0};        // the box's first voxel in the volume's grid
  std::vector<char> inside;      // 1 for the ball's voxels, x fastest (over dims)
  std::vector<char> region;      // 1 for the start's 6-connected object region it grew in, x fastest (over dims)
  std::size_t voxels = 0;        // the ball's voxels
  std::size_t background_voxels = 0;  // of them, voxels on the background's side of T: in slits and
                                      // canals narrower than two voxels, or taken to keep it well-composed
  std::size_t left_out = 0;      // object voxels next to the ball it could not take (each would close a
                                 // loop round a handle, or break well-composedness)
};

// Grows the ball from voxel `start` (on the object's side of T, at least one
// voxel from the grid's border; the ball never reaches the border's voxels)
// in the start's 6-connected region of the object (the cavity fill's "object
// the model grows in"; other object voxels count as background).
// Deterministic; work: a priority queue and a 27-voxel test per voxel of the
// object it reaches, plus a distance transform of the grid.
VoxelBall grow_voxel_ball(const Volume& volume, const VoxelSeedOptions& options, const Index3& start);

// Whether the set (x fastest on an n grid) is well-composed: no 2 x 2 square
// of voxels in an axis plane holding a diagonal pair of the set and the other
// pair outside it, no 2 x 2 x 2 cube holding exactly two opposite corners of
// the set, or all but two opposite corners. Counts the offending windows.
std::size_t critical_configurations(const std::vector<char>& set, const Index3& n);

// The faces between the ball's voxels and the rest, two triangles each,
// outward, with vertices at the voxels' corners (in physical space):
// closed, 2-manifold and free of self-intersection when the set is
// well-composed and a ball.
Mesh voxel_surface(const VoxelBall& ball, const Volume& volume);

// The vertices of a voxel surface (voxel_surface's, on `volume`'s grid)
// inside a flat patch of voxel faces, or on a straight crease between two
// such patches, removed by halfedge collapses that leave the surface the
// same point set: each moved face keeps its plane and its orientation
// there, which the corners' integer coordinates decide exactly. The faces
// of a patch then tile the same polygon, so nothing can come to intersect
// and no guard is asked. No new angle below `min_angle` degrees (or below
// the face's own smallest, when lower). Returns the vertices removed (0,
// the mesh untouched, when a vertex is not at a voxel corner);
// garbage-collects the mesh. Before the reduction (issue 17): on the T1
// head a fifth of the cuberille's vertices are inside flat patches and a
// third on straight creases; the guarded reduction spent 25 us a collapse.
std::size_t remove_flat_vertices(Mesh& mesh, const Volume& volume, double min_angle);

struct VoxelSeed {
  bool applied = false;          // false: no seed point lies on the object's side of T inside the grid
  Mesh mesh;                     // the seed (closed, 2-manifold, genus 0, no self-intersection)
  std::size_t voxels = 0;        // VoxelBall's counts
  std::size_t background_voxels = 0;
  std::size_t left_out = 0;
  std::size_t surface_faces = 0;  // faces of voxel_surface before the reduction
  bool cropped = false;           // the ball was grown in a crop of the grid (VoxelSeedOptions::crop)
  Volume grow_in;                // what the model grows in: the volume given, its object voxels outside
                                 // the ball's region (other objects, specks not 6-connected to it)
                                 // mirrored across T (outside_region_mirrored); empty when there is
                                 // none: the model grows in the volume given
};

// `volume` with its object voxels outside `region` (x fastest) mirrored
// across T (v -> 2T - v).
Volume outside_region_mirrored(const Volume& volume, const VoxelSeedOptions& options, const std::vector<char>& region);

// The ball grown from the deepest of `seed_points` (mm) on the object's side,
// its surface, reduced to about options.face_area per face of the object's
// area (the cuberille's area over 1.5, the mean L1 norm of a unit normal).
VoxelSeed make_voxel_seed(const Volume& volume, const VoxelSeedOptions& options, const std::vector<Vec3>& seed_points);

}  // namespace gdm
