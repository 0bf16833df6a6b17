// Reading volume files for the MeshLab plugin through ITK's readers. The only
// header of the plugin that names ITK's work; ITK itself stays in volume_io.cpp.
#pragma once

#include <string>

#include "gdm/volume.h"

namespace gdm_meshlab {

// Reads a scalar volume: a file ITK can read (.mha, .mhd, .nrrd, .nhdr, .nii,
// .nii.gz) or a directory holding one DICOM series. Throws std::runtime_error
// with a message naming the path and the problem (missing, unreadable, not 3D,
// a directory without DICOM series) and gdm::InvalidVolume for grids gdm cannot
// use. `description` receives one line about what was read.
gdm::Volume read_volume(const std::string& path, std::string* description = nullptr);

}  // namespace gdm_meshlab
