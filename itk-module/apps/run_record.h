// What a run did: the input, the choices made (threshold, seed), the core's
// record of the model and its checks. Printed as the human
// summary and written as the JSON report (report.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "gdm/deformer.h"
#include "gdm/mesh_checks.h"
#include "gdm/self_contact.h"

namespace gdm_cli {

struct InputInfo {
  std::string path;                 // as given
  std::string format;               // "DICOM series", "DICOM file", "MetaImage", "NIfTI", ...
  std::string series_uid;           // DICOM only
  std::size_t files = 1;            // DICOM slices read
  std::size_t series_count = 0;     // DICOM series found in the folder
  std::string pixel_type;           // as stored, e.g. "short", "unsigned char"
  std::array<std::size_t, 3> size{0, 0, 0};
  std::array<double, 3> spacing{0, 0, 0};    // mm
  std::array<double, 3> origin{0, 0, 0};     // mm
  std::array<double, 9> direction{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  double minimum = 0.0, maximum = 0.0;       // value range after rescaling
};

struct RunRecord {
  InputInfo input;
  double threshold = 0.0;
  std::string threshold_source;     // "given", "otsu", "phantom default"
  std::string seed_source;          // "auto", "point", "index", "mesh", "sphere"
  std::array<double, 3> seed_center{0, 0, 0};
  double seed_radius = 0.0;
  double seed_depth = 0.0;          // --seed auto: distance to the region's boundary, mm
  std::size_t seed_region_voxels = 0;
  std::size_t seed_regions = 0;
  bool cut_by_scan = false;         // the seed's region is an object the scan cuts: the border was allowed
  double border_fraction = 0.0;     // of the border's voxels, the share the seed's region covers
  std::string border_sides;         // the sides it touches ("-z (1234 voxels)")
  gdm::DeformResult model;          // how the model ran (cycles, stop reason, counts)
  double model_seconds = 0.0;       // wall time of the model and its checks
  double check_seconds = 0.0;       // of it, the checks
  gdm::MeshReport mesh;             // the result's checks and measures
  gdm::ContactReport contacts;      // where the model meets itself (closer than a voxel)
  bool voxel_seed_possible = false; // the model grew (no obstacle): --voxel-seed would have applied
  std::array<double, 3> low{0, 0, 0}, high{0, 0, 0};  // bounding box, mm
  int max_generation = 0;           // the youngest vertex's generation
  std::string output;               // mesh file written ("" when none)
  double total_seconds = 0.0;
  double peak_memory_mb = 0.0;      // the process's largest resident set so far (getrusage), MiB
  int exit_code = 0;
  std::string status;               // "ok" or the error
};

}  // namespace gdm_cli
