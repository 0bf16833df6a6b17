// What the plugin's filters share besides the gdm pipeline: progress and log
// plumbing towards MeshLab.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gdm/pipeline.h"

namespace gdm_meshlab {

// percent in [0, 100] and a short text; returns false to cancel.
using Progress = std::function<bool(int, const char*)>;
using LogLines = std::vector<std::string>;

// A number with four significant digits, for the log lines.
std::string fmt(double v);

// The outcome of a pipeline run as log lines: how the model stopped, the
// checks of the result (closed, manifold, genus, self-intersections, volume),
// where it meets itself, and, when it could have started from the object's
// voxels (`voxel_seed_possible`: it grew) but did not and left seams, a hint to.
void log_result(const gdm::PipelineResult& r, bool voxel_seed_possible, LogLines* log);

}  // namespace gdm_meshlab
