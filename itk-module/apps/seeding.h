// Seeds from the image: --seed auto (the deepest point of the largest
// connected object region), the shrink-mode box, and checks of given seeds.
#pragma once

#include <array>
#include <cstddef>

#include "image_input.h"
#include "surface_mesh.h"

namespace gdm_cli {

struct AutoSeed {
  std::array<double, 3> center{0, 0, 0};  // mm
  std::array<long, 3> index{0, 0, 0};     // voxel of the centre
  double depth = 0.0;                     // distance from the centre to the region's boundary, mm
  double radius = 0.0;                    // half the depth: the sphere lies inside the region
  std::size_t region_voxels = 0;          // size of the largest region
  std::size_t regions = 0;                // connected regions on the object side of T
};

// The centre of the largest 6-connected region on the object side of T
// (above T for object_darker = false), taken as the region voxel farthest
// from the region's boundary and from the volume's border (a concave region's
// centroid may lie outside it). Throws UsageError when no voxel is on the
// object side of T.
AutoSeed find_auto_seed(const Image* image, double threshold, bool object_darker);

// True when the physical point lies inside the volume's voxel-centre grid.
bool inside_volume(const Image* image, const std::array<double, 3>& point);

// Trilinear value at a physical point inside the volume.
double value_at(const Image* image, const std::array<double, 3>& point);

// Physical point of a voxel index.
std::array<double, 3> index_to_point(const Image* image, const std::array<long, 3>& index);

// A closed box one voxel inside the volume's border, outward oriented: the
// seed of --mode shrink --seed auto.
SurfaceMesh volume_box(const Image* image);

// The smallest spacing (the core's "voxel").
double voxel_size(const Image* image);

}  // namespace gdm_cli
