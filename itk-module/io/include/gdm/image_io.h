// Reading volumes: the one image reader of gdm (the command line, the MeshLab
// plugin and the ITK example all read through it). ITK does the decoding, but
// no ITK type appears here: ITK stays in image_io.cxx.
//
// Input: a DICOM series folder (the series with most slices, or the one named
// by ReadOptions::series_uid), a single file ITK can read (.mha/.mhd,
// .nrrd/.nhdr, .nii/.nii.gz, .vtk, a DICOM file), any scalar pixel type,
// converted to float (DICOM rescale slope/intercept applied), with spacing,
// origin and direction cosines kept.
//
// Checked before anything large is allocated, and refused with
// gdm::InvalidInput naming the file and the problem:
//  - a missing path, a FIFO, device or socket (never opened, so never blocks);
//  - an unreadable or self-contradicting header; 2D images, vectors;
//  - a header that claims more voxel data than the file (or its data file)
//    holds: truncated MetaImage / NRRD / NIfTI / legacy VTK, cut or header-only
//    .nii.gz;
//  - a spacing that is 0, negative, NaN or infinite in the header itself
//    (ITK silently turns some of these into 1 or drops the sign);
//  - more float voxels than ReadOptions::memory_limit bytes;
//  - DICOM series geometry: a duplicated slice (same file or same position),
//    missing slices or uneven steps, mixed orientations, gantry tilt;
//    the slice spacing is the median step of the slice positions;
//  - NaN or infinite voxel values.
// gdm::InvalidVolume: a grid gdm cannot use (constant values, ...).
// gdm::InvalidOption: ReadOptions::series_uid names no series of the folder.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "gdm/errors.h"
#include "gdm/volume.h"

namespace gdm {

struct ReadOptions {
  // DICOM folder: the series to read (a full UID or a prefix of one); empty:
  // the series with most slices.
  std::string series_uid;
  // Largest volume accepted, in bytes of float voxels (4 per voxel); 0: no limit.
  std::uint64_t memory_limit = std::uint64_t{8} << 30;  // 8 GiB
};

// What was read.
struct ImageInfo {
  std::string path;                 // as given
  std::string format;               // "DICOM series", "DICOM file", "MetaImage", "NRRD", "NIfTI", "VTK image"
  std::string pixel_type;           // as stored, e.g. "short", "unsigned char"
  std::array<std::size_t, 3> dims{0, 0, 0};
  std::array<double, 3> spacing{0, 0, 0};                       // mm
  std::array<double, 3> origin{0, 0, 0};                        // mm
  std::array<double, 9> direction{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major; column k: axis k
  double minimum = 0.0, maximum = 0.0;                          // after rescaling to float
  std::string series_uid;           // DICOM series only
  std::size_t series_count = 0;     // DICOM series in the folder (0 for a file)
  std::size_t slices = 1;           // files read (DICOM series: its slices)
  std::vector<std::string> warnings;  // things read but doubtful (no slice positions, a small tilt, ...)
};

// Reads `path` (see above). Throws InvalidInput, InvalidVolume or
// InvalidOption with a message naming the file and the problem.
Volume read_volume(const std::string& path, const ReadOptions& options = {}, ImageInfo* info = nullptr);

}  // namespace gdm
