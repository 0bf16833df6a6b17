// The run report: mesh measurements (with the core's checks), the human
// summary on stdout and the JSON report of --report.
#pragma once

#include <string>

#include "cli_options.h"
#include "run_record.h"
#include "gdm/mesh_checks.h"

namespace gdm_cli {

// Records the model's bounding box and largest vertex generation.
void record_extent(const gdm::Mesh& mesh, RunRecord& record);

// The input lines printed after reading (dimensions, spacing, value range).
std::string input_text(const InputInfo& input);

// The summary's hint to start from the object's voxels, and whether a run
// gets it: it grew, not from its voxels, and left seams where its fronts met
// (gdm::seams_worth_a_voxel_seed).
extern const char* const kVoxelSeedHint;
bool seams_worth_a_voxel_seed(const RunRecord& record);

// The summary printed at the end of a run.
std::string summary_text(const RunRecord& record);

// The JSON report: version, status, input, threshold, seed, model, mesh,
// timings and every parameter (so the run can be reproduced).
std::string report_json(const RunRecord& record, const Options& options);

}  // namespace gdm_cli
