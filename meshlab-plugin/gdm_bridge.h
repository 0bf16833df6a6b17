// The plugin's helper: CMeshO <-> gdm::Mesh conversion and the three filters'
// work, calling the gdm core. No Qt dialogs, no RichParameters: plain options
// in, meshes and log lines out. Errors are thrown (gdm::Error or
// std::runtime_error) with a message meant for the user.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <common/ml_mesh_type.h>

#include "gdm/pipeline.h"
#include "gdm/mesh.h"
#include "gdm/shrink_wrap.h"
#include "gdm/triangle_locator.h"
#include "plugin_support.h"

namespace gdm_meshlab {

// The closed 2-manifold triangle mesh of a MeshLab layer (deleted elements
// skipped, coincident vertices kept apart). Throws gdm::InvalidSeed with the
// reason when the layer is empty, open, non-manifold or not finite. An
// inward-oriented mesh is reversed (noted in `log`).
gdm::Mesh to_gdm_seed(const CMeshO& m, LogLines* log);

// Replaces `out` by `mesh`; the per-vertex generation goes to vertex quality.
void to_meshlab(const gdm::Mesh& mesh, CMeshO& out);

// The triangles of a layer as a soup; a layer without faces gives its vertices
// as degenerate triangles (a point cloud can be wrapped too).
std::vector<gdm::Triangle> triangle_soup(const CMeshO& m);

// Filters 1 and 2: the core's pipeline (gdm::prepare_model + gdm::run_model,
// gdm/pipeline.h) on a volume file read by gdm::read_volume: the code path of
// the gdm command, so the same volume and options give the same mesh. The
// seed is options.seed (automatic, a point, or the current layer as a mesh).
// Throws gdm::Error with the reason, also when the model leaked or failed.
gdm::Mesh model_from_volume(const std::string& volume_file, const gdm::PipelineOptions& options,
                            const Progress& progress, LogLines* log);

// Filter 3: the core's gdm::shrink_wrap (gdm/shrink_wrap.h) of a layer's
// triangle soup, its progress mapped onto MeshLab's bar (distance field 0-20%,
// shrinking 20-90%, coverage rounds 91-95%) and its notes logged.
gdm::Mesh shrink_wrap(const std::vector<gdm::Triangle>& soup, gdm::WrapOptions w, const Progress& progress,
                      LogLines* log);

}  // namespace gdm_meshlab
