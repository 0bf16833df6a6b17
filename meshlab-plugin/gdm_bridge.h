// The plugin's helper: CMeshO <-> gdm::Mesh conversion and the three filters'
// work, calling the gdm core. No Qt dialogs, no RichParameters: plain options
// in, meshes and log lines out. Errors are thrown (gdm::Error or
// std::runtime_error) with a message meant for the user.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <common/ml_mesh_type.h>

#include "gdm/deformer.h"
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

// What the volume filters share.
struct VolumeParams : ModelParams {
  std::string volume_file;
  bool auto_threshold = false;
  double threshold = 0.0;
  bool object_darker = false;
  bool shrink = false;            // deform_seed_in_volume: the seed encloses the object
  double smoothing_sigma = 0.0;  // mm, 0 = off
  bool subvoxel_fit = true;       // final fit onto the threshold crossing
  double fit_smoothing = 0.5;     // the fit's noise-adaptive smoothing, [0, 5]; 0 = off
  double lod_tolerance = 0.0;     // error-driven level of detail, voxels; 0 = off
};

struct SeedParams {
  bool at_volume_centre = true;
  gdm::Vec3 point = gdm::Vec3::Zero();  // mm
  double radius = 3.0;                   // mm
};

// Filter 1: a model grown from an icosahedron in the volume.
gdm::Mesh model_from_volume(const VolumeParams& v, const SeedParams& s, const Progress& progress, LogLines* log);

// Filter 2: the given seed deformed in the volume: grown from inside the
// object, or shrunk onto it when v.shrink (the seed encloses the object).
gdm::Mesh deform_seed_in_volume(gdm::Mesh seed, const VolumeParams& v, const Progress& progress, LogLines* log);

// Filter 3: the core's gdm::shrink_wrap (gdm/shrink_wrap.h) of a layer's
// triangle soup, its progress mapped onto MeshLab's bar (distance field 0-20%,
// shrinking 20-90%, coverage rounds 91-95%) and its notes logged.
gdm::Mesh shrink_wrap(const std::vector<gdm::Triangle>& soup, gdm::WrapOptions w, const Progress& progress,
                      LogLines* log);

}  // namespace gdm_meshlab
