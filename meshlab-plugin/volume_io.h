// Reading volume files for the MeshLab plugin: a thin layer over
// gdm::read_volume (itk-module/io, gdm/image_io.h), the reader the gdm command
// line uses. No ITK here: ITK stays inside gdm::image_io.
#pragma once

#include <string>

#include "gdm/volume.h"

namespace gdm_meshlab {

// Reads a scalar volume: a file ITK can read (.mha, .mhd, .nrrd, .nhdr, .nii,
// .nii.gz, .vtk) or a directory holding DICOM series (the one with most
// slices). Throws std::runtime_error for an empty or missing path,
// gdm::InvalidInput (a std::runtime_error) naming the file and the problem
// (unreadable, not 3D, truncated, a lying header, bad spacing, non-finite
// values, DICOM slices duplicated, missing or tilted, ...) and
// gdm::InvalidVolume for grids gdm cannot use. `description` receives one
// line about what was read.
gdm::Volume read_volume(const std::string& path, std::string* description = nullptr);

}  // namespace gdm_meshlab
