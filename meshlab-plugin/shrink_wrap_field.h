// The field a shrink-wrap collapses onto: the unsigned distance to a triangle
// soup sampled on a regular grid, for gdm::deform in Mode::shrink. No MeshLab
// and no ITK here: triangles in, gdm::Volume out.
#pragma once

#include <array>
#include <functional>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/triangle_locator.h"
#include "gdm/volume.h"

namespace gdm_meshlab {

using Triangle = gdm::Triangle;

struct WrapFieldOptions {
  double cell_size = 1.0;    // grid spacing, mm
  double offset = 1.0;       // the wrap settles on the surface at this distance from the input, mm
  double padding = 0.0;      // extra room around `lo`..`hi`, mm (the seed sphere must fit)
};

// The grid covers [lo - padding, hi + padding] plus two cells on each side.
// Values are the unsigned distance to the nearest triangle, clamped at
// offset + 3 cells (the far field only needs to be "free"). The object is
// where the value is below `offset`: pass threshold = offset and
// Polarity::object_darker to gdm::deform. `progress(fraction)` may return false
// to cancel (then an empty volume is returned).
gdm::Volume make_wrap_field(const std::vector<Triangle>& triangles, const gdm::Vec3& lo, const gdm::Vec3& hi,
                            const WrapFieldOptions& options,
                            const std::function<bool(double)>& progress = {});

}  // namespace gdm_meshlab

namespace gdm_meshlab {

// Separable Gaussian smoothing of a volume, sigma in mm (per axis in voxels
// sigma / spacing); sigma <= 0 returns the volume unchanged.
gdm::Volume smooth_volume(const gdm::Volume& volume, double sigma_mm);

}  // namespace gdm_meshlab
