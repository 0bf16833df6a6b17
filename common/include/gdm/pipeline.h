// The pipeline every front end runs (the gdm command, the ITK filter, the
// MeshLab filters, Python): preprocess (region of interest, Gaussian), choose
// the threshold (given or Otsu's), seed (automatic, a point, a voxel, a box
// for shrink, or a user's mesh), deform, and measure. No ITK and no Qt here:
// the same volume and options give the same mesh, bit for bit, from every
// front end.
//
//   gdm::PipelineOptions options;               // every field has its default
//   options.deform.polarity = gdm::Polarity::object_darker;
//   gdm::PipelineResult r = gdm::extract_surface(volume, options);
//   gdm::require_success(r);                    // throws ModelFailed on a leak
#pragma once

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "gdm/border_contact.h"
#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/option_catalogue.h"
#include "gdm/self_contact.h"
#include "gdm/seeding.h"
#include "gdm/volume_ops.h"

namespace gdm {

// The model ran but its result is not the object (it leaked to the volume's
// border or past the face limit) or breaks a guarantee.
class ModelFailed : public Error {
 public:
  using Error::Error;
};

enum class SeedKind {
  automatic,  // grow: the deepest point of the largest object region; shrink: a sphere around the object's voxels (seeding.h)
  point,      // a sphere around `point` (mm)
  index,      // a sphere around the centre of voxel `index` (of the volume before the roi)
  mesh        // the user's closed mesh `mesh`
};

struct SeedOptions {
  SeedKind kind = SeedKind::automatic;  // how the seed is chosen
  Vec3 point = Vec3::Zero();            // sphere centre, mm (SeedKind::point)
  Index3 index{0, 0, 0};                // sphere centre as a voxel index (SeedKind::index)
  double radius = 0.0;                  // sphere radius, mm; 0 = half the depth (automatic) or 2 voxels
  int level = 1;                        // subdivisions of the icosahedron (20 * 4^level faces)
  Mesh mesh;                            // the seed mesh (SeedKind::mesh), in mm
};

struct PipelineOptions {
  bool use_roi = false;      // crop to `roi` before anything else
  VoxelBox roi;              // inclusive voxel box of the input volume
  double smooth = 0.0;       // Gaussian sigma before the model, mm; 0 = none
  bool threshold_otsu = true;  // T by Otsu's method (256 bins) on the preprocessed volume, else `threshold`
  double threshold = std::numeric_limits<double>::quiet_NaN();  // T of eq. 2 when not Otsu's, image units
  SeedOptions seed;          // where the model starts
  DeformOptions deform;      // the model (its threshold is set from the above)
  bool allow_border = false; // accept a model that reached the volume's border (the object is cut by the scan)
  double time_limit = 0.0;   // seconds the model may run; 0 = no limit (a stopped model is a failure)
};

// The pipeline's own options (smooth, seed_radius, seed_level, allow_border)
// and the model's, lifted from DeformOptions: what front ends list.
const std::vector<OptionEntry<PipelineOptions>>& pipeline_option_catalogue();

// The catalogue as a Markdown table per group (name, command-line flag, unit,
// default, range, help): docs/options.md, which the README links to.
std::string options_markdown();

// Checks every option against the catalogue and the seed's own fields;
// throws InvalidOption naming the option (before any work is done).
void validate(const PipelineOptions& options);

// What the pipeline chose, for reports.
struct PipelineChoices {
  double threshold = 0.0;          // T used
  std::string threshold_source;    // "otsu" or "given"
  std::string seed_source;         // "auto", "sphere" (shrink), "point", "index" or "mesh"
  Vec3 seed_center = Vec3::Zero(); // sphere seeds
  double seed_radius = 0.0;        // sphere seeds, mm
  std::size_t seed_faces = 0;      // faces of the seed mesh
  bool seed_reversed = false;      // a user's inward seed mesh was reversed
  AutoSeed auto_seed;              // seed_source == "auto"
  BorderContact border;            // where the seed's region meets the border (grow mode without allow_border)
  bool cut_by_scan = false;        // that region is an object the scan cuts: the border is allowed
};

// The preprocessed volume, the options with T set and the seed: everything
// the model needs, ready to run (a front end may print the choices first).
struct PreparedModel {
  std::shared_ptr<const Volume> volume;  // the input itself when neither cropped nor smoothed
  DeformOptions deform;
  Mesh seed;
  PipelineChoices choices;
  bool allow_border = false;
  double time_limit = 0.0;  // seconds; 0 = none
};

// Steps 1 to 3: preprocess, threshold, seed. Throws InvalidOption (bad
// option, threshold outside the value range), InvalidVolume (empty or
// constant volume) or InvalidSeed (seed outside the volume or the object,
// unusable seed mesh). A run whose level of detail would need more than
// max_faces faces to cover the volume's box (a tiny lod_face_area, or extreme
// anisotropy: one voxel is the smallest spacing) is refused up front. `volume` must outlive the result when neither roi nor
// smoothing is used.
PreparedModel prepare_model(const Volume& volume, const PipelineOptions& options);

// The choices as log lines: "threshold 125 (otsu), object brighter, mode
// grow", then the seed ("seed: auto, centre (...) mm (voxel ...), radius ...").
std::vector<std::string> describe_choices(const PreparedModel& prepared);

// Progress of a run: the cycle just done and an estimate of the fraction of
// the work done, in [0, 1), monotone.
struct PipelineProgress {
  CycleReport cycle;
  double fraction = 0.0;
};
// Returns false to cancel.
using PipelineObserver = std::function<bool(const PipelineProgress&)>;

// The one progress estimator: each stage (the first convergence and every
// global refinement) gets an equal share, approached exponentially with its
// cycles, never less than the fraction of the cycle budget used.
class ProgressEstimator {
 public:
  ProgressEstimator(int global_refinements, int max_cycles);
  double update(const CycleReport& cycle);

 private:
  double stages_;
  double max_cycles_;
  int stage_ = -1;
  int stage_start_ = 1;
  double fraction_ = 0.0;
};

struct PipelineResult {
  Mesh mesh;                  // the model (compacted; "v:generation" on its vertices)
  DeformResult deform;        // cycles, stop reason, counts
  MeshReport report;          // closed, manifold, genus, self-intersections, volume, ...
  PipelineChoices choices;    // threshold and seed used
  ContactReport contacts;     // where the model meets itself (closer than a voxel; self_contact.h)
  std::string failure;        // empty when the model is the object; else why not (a leak, the face limit, ...)
  double seconds = 0.0;       // wall time of the model and the checks
  double check_seconds = 0.0; // of it, the checks (measure(): self-intersections, genus, ...; self-contacts)
};

// Step 4: deforms the prepared seed, measures the result against every
// guarantee and says in `failure` why the model is not the object, if so.
PipelineResult run_model(const PreparedModel& prepared, const PipelineObserver& observer = {});

// All steps.
PipelineResult extract_surface(const Volume& volume, const PipelineOptions& options,
                               const PipelineObserver& observer = {});

// Throws ModelFailed(result.failure) when the result is not usable.
void require_success(const PipelineResult& result);

}  // namespace gdm
