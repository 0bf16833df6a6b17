// Reading the input volume: a DICOM series folder, a single DICOM file or an
// image file ITK can read (.mha/.mhd, .nrrd/.nhdr, .nii/.nii.gz, .vtk), any
// scalar pixel type, as float with spacing, origin and direction kept.
#pragma once

#include <array>
#include <cstdint>
#include <ostream>
#include <string>

#include "gdm/volume.h"

#include "run_record.h"

namespace gdm_cli {

// Reads `path`; `series_uid` selects a DICOM series (empty: the one with most
// slices). Throws InputError naming the problem, UsageError for an unknown
// series UID. Progress notes (which series) go to `log`.
// `memory_limit` (bytes of float voxels, 0 = none): a larger volume is an
// InputError naming the limit as --memory-limit.
gdm::Volume read_input(const std::string& path, const std::string& series_uid, std::uint64_t memory_limit,
                       InputInfo& info, std::ostream& log);

}  // namespace gdm_cli
