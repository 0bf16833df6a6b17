// What a run did, without ITK types: the input, the choices made (threshold,
// seed), the model's statistics and the measured mesh. Printed as the human
// summary and written as the JSON report (report.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <string>

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

struct ModelStats {
  std::string stop_reason;        // gdm::to_string(StopReason): "converged", ...
  std::size_t cycles = 0;
  std::size_t refinements = 0;    // global 1-to-4 resamplings performed
  std::size_t rejected_moves = 0; // moves vetoed by the self-intersection guard
  std::size_t flips = 0;          // edge flips
  std::size_t border_vertices = 0;  // vertices within a voxel of the volume border (a leak)
  std::size_t fit_moves = 0;      // vertex moves of the sub-voxel fit (and of the error-driven LOD)
  std::size_t lod_splits = 0;     // edges split by the error-driven level of detail
  std::size_t lod_collapses = 0;  // edges collapsed by the error-driven level of detail
  std::size_t float_refused = 0;  // vertices --float-exact could not move onto a float point
  double seconds = 0.0;           // wall time of the model
};

struct MeshFigures {
  std::size_t vertices = 0, faces = 0, edges = 0;
  bool closed = false, manifold = false;
  int euler = 0, genus = 0, components = 0;
  std::size_t self_intersections = 0;
  double volume_mm3 = 0.0, area_mm2 = 0.0, min_angle_deg = 0.0;
  std::array<double, 3> low{0, 0, 0}, high{0, 0, 0};  // bounding box, mm
  int max_generation = 0;
};

struct RunRecord {
  InputInfo input;
  double threshold = 0.0;
  std::string threshold_source;     // "given", "otsu", "phantom default"
  std::string seed_source;          // "auto", "point", "index", "mesh", "box"
  std::array<double, 3> seed_center{0, 0, 0};
  double seed_radius = 0.0;
  double seed_depth = 0.0;          // --seed auto: distance to the region's boundary, mm
  std::size_t seed_region_voxels = 0;
  std::size_t seed_regions = 0;
  ModelStats model;
  MeshFigures mesh;
  std::string output;               // mesh file written ("" when none)
  double total_seconds = 0.0;
  int exit_code = 0;
  std::string status;               // "ok" or the error
};

}  // namespace gdm_cli
