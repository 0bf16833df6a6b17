// Volume operations of the pipeline (before the model): region of interest,
// Gaussian smoothing and Otsu's threshold. No ITK here: every front end (the
// gdm command, the ITK filter's users, MeshLab, Python) gets the same numbers.
#pragma once

#include "gdm/volume.h"

namespace gdm {

// An inclusive box of voxel indices.
struct VoxelBox {
  Index3 lo{0, 0, 0};  // first voxel on each axis
  Index3 hi{0, 0, 0};  // last voxel on each axis (inclusive)
};

// The voxels of `box`, physical positions kept (the origin moves to the
// box's first voxel). Throws InvalidOption naming "roi" when the box is not
// inside the volume or spans fewer than 2 voxels on an axis.
Volume crop(const Volume& volume, const VoxelBox& box);

// Separable Gaussian smoothing, sigma in mm (per axis sigma / spacing voxels),
// the kernel truncated at 4 sigma and normalised, borders clamped (the edge
// voxel repeats). sigma == 0 returns a copy; a negative or non-finite sigma,
// or one wider (in voxels) than the volume along an axis, throws
// InvalidOption naming "smooth".
Volume gaussian_smooth(const Volume& volume, double sigma_mm);

// Otsu's threshold between the volume's two classes from a `bins`-bin
// histogram over [min, max] (the value at the upper edge of the last bin of
// the lower class). Throws InvalidVolume for a constant volume.
// The same number as ITK 5.2's itk::OtsuThresholdImageFilter on a float
// image with `bins` bins: its histogram spans [min, max + (max - min) / bins
// / 100] with ITK's bin edges, the first maximum of the between-class
// variance wins, and the edge is returned rounded to float as ITK does.
// Where ITK's float bin width would overflow (values near +-FLT_MAX: a span
// beyond FLT_MAX, or a maximum whose margin passes it; ITK then returns inf)
// the same bins are computed in double: the threshold is always finite and
// lies inside [min, max).
// Throws InvalidOption for fewer than 2 bins.
double otsu_threshold(const Volume& volume, int bins = 256);

}  // namespace gdm
