// The volume filters' optional Gaussian pre-smoothing. Stays in the plugin
// until the core's gdm::gaussian_smooth (gdm/volume_ops.h) replaces it.
#pragma once

#include "gdm/volume.h"

namespace gdm_meshlab {

// Separable Gaussian smoothing of a volume, sigma in mm (per axis in voxels
// sigma / spacing); sigma <= 0 returns the volume unchanged.
gdm::Volume smooth_volume(const gdm::Volume& volume, double sigma_mm);

}  // namespace gdm_meshlab
