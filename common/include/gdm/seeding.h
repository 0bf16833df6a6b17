// Seeds from the image (paper section 4: the seed only changes the time, not
// the result): the automatic seed, the shrink-mode sphere (and box), and the checks a seed
// mesh given by a user must pass before it is deformed.
#pragma once

#include <cstddef>

#include "gdm/cost_terms.h"  // Polarity
#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace gdm {

// The smallest seed sphere that grows, in voxels (the volume's smallest
// spacing): the optimiser's steps are a quarter of a voxel to one voxel
// (section 3.2), and a sphere of half a voxel took none of them (measured on
// noisy balls and shells: radius 0.5 voxel ended "converged" at its seed's
// size, 0.625 and 0.75 grew to the object).
constexpr double kMinGrowingSeedRadius = 0.75;

struct AutoSeed {
  Vec3 center = Vec3::Zero();      // mm
  Index3 index{0, 0, 0};           // voxel of the centre
  double depth = 0.0;              // distance from the centre to the region's boundary, mm
  double radius = 0.0;             // half the depth, at least kMinGrowingSeedRadius voxels when the
                                   // depth is that much: the sphere lies inside the region
  std::size_t region_voxels = 0;   // size of the largest region
  std::size_t regions = 0;         // 6-connected regions on the object side of T
};

// The centre of the largest 6-connected region strictly on the object side of
// T (above T for Polarity::object_brighter), taken as the region voxel
// farthest (Euclidean, in mm) from the region's boundary and from the
// volume's border; the first in raster order on ties. Throws InvalidSeed when
// no voxel is on the object side or the region has no interior voxel.
// As ITK's SignedMaurerDistanceMapImageFilter measures it, the region's
// boundary is its contour: the region voxels with a voxel outside the region
// among their 26 neighbours (inside the image); contour voxels are never the
// centre, and the volume's border counts as (index + 0.5) * spacing. Ties
// between equally large regions go to the one whose first voxel comes first
// in raster order. Throws InvalidOption for a non-finite threshold.
AutoSeed find_auto_seed(const Volume& volume, double threshold, Polarity polarity);

// A closed box `inset_voxels` voxels inside the volume's border, outward
// oriented in physical space (12 faces): the seed of shrink mode.
// Throws InvalidOption when the inset is negative, not finite, or leaves no
// box (2 * inset >= dims - 1 on an axis).
Mesh make_volume_box(const Volume& volume, double inset_voxels = 1.0);

// The seed of shrink mode: the sphere through the corners of the box around
// the object's voxels (those on the object's side of T, by `polarity`) grown
// by `margin_voxels`, a geodesic sphere of `level` subdivisions, outward.
// It may extend past the volume, where shrink mode counts the outside as
// background. A box's edges and corners fold into fins as they shrink (on a
// sphere phantom, half the model's surface lay against itself), and so do
// the ends of an elongated ellipsoid; a sphere shrinks into itself without
// creases until it meets the object. Without object voxels, the whole
// volume's box is used. Throws InvalidOption for a non-finite threshold.
Mesh make_enclosing_sphere(const Volume& volume, double threshold, Polarity polarity, int level = 3,
                           double margin_voxels = 2.0);

// Makes a user's seed mesh safe to deform: throws InvalidSeed (naming the
// problem) unless it is non-empty, finite, closed, 2-manifold, free of
// self-intersections and encloses a positive volume once oriented; a mesh
// whose faces point inwards is reversed (`reversed` set when given).
Mesh prepare_seed_mesh(const Mesh& mesh, bool* reversed = nullptr);

}  // namespace gdm
