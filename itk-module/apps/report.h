// The run report: mesh measurements (with the core's checks), the human
// summary on stdout and the JSON report of --report.
#pragma once

#include <string>

#include "cli_options.h"
#include "run_record.h"
#include "gdm/mesh_checks.h"

namespace gdm_cli {

// The figures of the report: gdm::measure()'s (closed, manifold, genus,
// components, self-intersections, volume, area), the bounding box and the
// largest vertex generation.
MeshFigures mesh_figures(const gdm::Mesh& mesh, const gdm::MeshReport& measured);

// The input lines printed after reading (dimensions, spacing, value range).
std::string input_text(const InputInfo& input);

// The summary printed at the end of a run.
std::string summary_text(const RunRecord& record);

// The JSON report: version, status, input, threshold, seed, model, mesh,
// timings and every parameter (so the run can be reproduced).
std::string report_json(const RunRecord& record, const Options& options);

}  // namespace gdm_cli
