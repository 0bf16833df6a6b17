// The three terms of the vertex cost C = a0 D + a1 I + a2 T (paper eq. 1).
// Each term is a small unit with its weight and its cost at a candidate
// position, in the spirit of OpenMesh's decimater modules.
#pragma once

#include <limits>

#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace gdm {

// Grow: the model starts inside the object and expands (paper's balloon).
// Shrink: the model starts around the object and collapses onto it.
enum class Mode { grow, shrink };

// Which side of the threshold T is the object.
enum class Polarity { object_brighter, object_darker };

// What a cost term needs to know about the vertex being moved; computed once
// per vertex and cycle from the model as it stood at the start of the cycle.
struct VertexNeighbourhood {
  Vec3 position = Vec3::Zero();        // current vertex position x_i (mm)
  Vec3 normal = Vec3::UnitZ();         // unit outward normal, enlarged neighbourhood (section 7)
  double sense = 1.0;                  // +1 deform along the normal, -1 against it (section 5)
  Vec3 ring_centroid = Vec3::Zero();   // centroid of the 1-ring neighbours (eq. 3)
  double ring_extent = 1.0;            // largest distance between two 1-ring neighbours (eq. 3)
  bool refined = false;                // the model refined itself here to enter a channel the image shows
                                       // (deformer.h, gap): TopologyTerm's hard limit is raised
};

// D, the deformation potential by normal tracking (section 3.1.1): the vertex
// is attracted to the point `reach` voxels from it along sense * normal. The
// cost is the distance to that point in voxels, so it falls by one per voxel
// of progress.
class DeformationPotential {
 public:
  DeformationPotential(double weight, double reach_voxels, double voxel_size);
  double weight() const { return weight_; }
  Vec3 target(const VertexNeighbourhood& n) const;
  double cost(const VertexNeighbourhood& n, const Vec3& x) const;

 private:
  double weight_;
  double reach_;       // mm
  double voxel_size_;  // mm
};

// I, the image event (section 3.1.2, eq. 2): the shifted threshold (X - T)^+
// on the trilinear value X, oriented so that it is zero in the region the
// model deforms through and grows with the depth into the other region:
//   grow,   object brighter: (T - X)^+     grow,   object darker: (X - T)^+
//   shrink, object brighter: (X - T)^+     shrink, object darker: (T - X)^+
// (Table 1's duality). The excess is divided by `intensity_scale` so that
// weights are independent of the scanner's units. Outside the grid the cost
// is infinite: no vertex may leave the volume.
class ImageEvent {
 public:
  ImageEvent(double weight, const Volume& volume, double threshold, Polarity polarity, Mode mode,
             double intensity_scale);
  double weight() const { return weight_; }
  // Signed depth into the blocked region, in scaled intensity units (> 0: blocked).
  double excess(const Vec3& x) const;
  bool is_blocked(const Vec3& x) const { return excess(x) > 0.0; }
  double cost(const Vec3& x) const;

 private:
  double weight_;
  const Volume* volume_;
  double threshold_;
  double sign_;  // +1 when the blocked region is brighter than T
  double inv_scale_;
  bool outside_is_free_ = false;  // shrinking: outside the volume is background
};

// T, the topology (curvature) term (section 3.1.3, eq. 3): the distance from
// the vertex to the centroid of its neighbours over the largest distance
// between two neighbours. Pulls towards a locally flat, contained
// configuration.
//
// Beyond the paper: eq. 3 is scale invariant in value but not in force: its
// pull is a2 / extent per mm, so once the faces are refined below the level
// of detail (after a global 1-to-4 resampling) it overpowers the deformation
// potential and the model shrinks away from every convex part. The extent is
// therefore never taken below `min_extent` (mm), the neighbour separation of
// faces at the level of detail; min_extent = 0 gives eq. 3 exactly.
//
// Section 3.1.3 asks this term to keep vertices from leaking out of holes; a
// cost that grows linearly cannot stop a vertex that the deformation
// potential pulls harder. So the constraint is also made hard: a position
// whose eq. 3 ratio exceeds `max_ratio` costs infinity unless it lowers the
// ratio of the current position. A finger thinner than about one edge length
// (a leak through a hole smaller than the level of detail) needs ratios near
// 0.5 at its tip; cube corners and tubes wider than two edges stay below 0.45.
// Where the model refined itself to follow a channel the image shows
// (VertexNeighbourhood::refined), the limit is raised to kRefinedMaxRatio: a
// finger two of its edges wide (a channel two voxels wide at the finest
// faces) passes; whether to pass is then the gap size's decision
// (passage.h), not the face size's.
class TopologyTerm {
 public:
  static constexpr double kRefinedMaxRatio = 0.7;
  explicit TopologyTerm(double weight, double min_extent = 0.0,
                        double max_ratio = std::numeric_limits<double>::infinity())
      : weight_(weight), min_extent_(min_extent), max_ratio_(max_ratio) {}
  double weight() const { return weight_; }
  // Eq. 3 as written: |x - centroid| / largest neighbour separation.
  static double ratio(const VertexNeighbourhood& n, const Vec3& x) {
    return (x - n.ring_centroid).norm() / n.ring_extent;
  }
  double cost(const VertexNeighbourhood& n, const Vec3& x) const;

 private:
  double weight_;
  double min_extent_;
  double max_ratio_;
};

// C = a0 D + a1 I + a2 T (eq. 1), each term already weighted.
struct CostFunction {
  DeformationPotential deformation;
  ImageEvent image;
  TopologyTerm topology;

  double operator()(const VertexNeighbourhood& n, const Vec3& x) const {
    return deformation.cost(n, x) + image.cost(x) + topology.cost(n, x);
  }
};

}  // namespace gdm
