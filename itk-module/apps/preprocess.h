// Preprocessing before the model: region of interest, Gaussian smoothing,
// Otsu's threshold.
#pragma once

#include <array>

#include "image_input.h"

namespace gdm_cli {

// The inclusive voxel box i0,j0,k0,i1,j1,k1 of `image`, physical positions
// kept. Throws UsageError when the box is not inside the image.
Image::Pointer crop(const Image* image, const std::array<long, 6>& box);

// Gaussian smoothing with sigma in mm (itk::SmoothingRecursiveGaussianImageFilter).
Image::Pointer smooth(const Image* image, double sigma_mm);

// Otsu's threshold (256-bin histogram) between the image's two classes.
double otsu_threshold(const Image* image);

}  // namespace gdm_cli
