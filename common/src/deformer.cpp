#include "gdm/deformer.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>
#include <type_traits>
#include <vector>

#include "gdm/cavities.h"
#include "gdm/channel_width.h"
#include "gdm/creases.h"
#include "gdm/error_lod.h"
#include "gdm/errors.h"
#include "gdm/face_budget.h"
#include "gdm/triangle_locator.h"
#include "gdm/float_snap.h"
#include "gdm/intersection_guard.h"
#include "gdm/mesh_checks.h"
#include "gdm/mesh_order.h"
#include "gdm/option_catalogue.h"
#include "gdm/parallel.h"
#include "gdm/passage.h"
#include "gdm/resampler.h"
#include "gdm/self_contact.h"
#include "gdm/space_blocks.h"
#include "gdm/seed.h"
#include "gdm/surface_fit.h"
#include "gdm/text.h"
#include "gdm/triangle_quality.h"
#include "gdm/voxel_seed.h"

namespace gdm {

std::string to_string(StopReason reason) {
  switch (reason) {
    case StopReason::converged: return "converged";
    case StopReason::max_cycles: return "reached the maximum number of cycles";
    case StopReason::face_limit: return "reached the face limit";
    case StopReason::cancelled: return "cancelled";
    case StopReason::border: return "reached the volume border";
  }
  return "unknown";
}

namespace {

std::string point_text(const Vec3& p) {
  return "(" + format_number(p[0], 4) + ", " + format_number(p[1], 4) + ", " + format_number(p[2], 4) + ") mm";
}

// The summaries name the largest regions of a kind only: a whole-head scan
// fills dozens of pockets and caps dozens of handles, and one log line
// listing them all ran to ten thousand characters. The rest are counted
// (every one is in the report's JSON and in DeformResult::filled_regions).
constexpr std::size_t kRegionsNamed = 5;

void more_regions(std::ostringstream& s, std::size_t listed, std::size_t total) {
  if (total > listed) s << "; and " << (total - listed) << " smaller";
}

}  // namespace

std::string cavity_summary(const DeformResult& r) {
  if (r.cavities == 0 && r.cavity_specks == 0) return {};
  std::ostringstream s;
  s << "cavities: ";
  if (r.cavities == 0) {
    s << "none";
  } else {
    const std::size_t enclosed = r.cavities - r.cavities_behind_openings;
    if (enclosed > 0) s << enclosed << " enclosed region" << (enclosed == 1 ? "" : "s");
    if (enclosed > 0 && r.cavities_behind_openings > 0) s << " and ";
    if (r.cavities_behind_openings > 0)
      s << r.cavities_behind_openings << " pocket" << (r.cavities_behind_openings == 1 ? "" : "s")
        << " joined to the outside only through openings narrower than " << format_number(r.cavity_opening_width, 3)
        << " mm";
    s << " of background filled (" << r.cavity_voxels << " voxels, " << format_number(r.cavity_volume, 4)
      << " mm^3; the largest around " << point_text(r.largest_cavity_centre) << ")";
    // Where each pocket behind narrow openings meets the outside: what a
    // user who wants that canal open looks for (--cavity-opening, issue 15).
    std::size_t listed = 0;
    for (const Cavity& c : r.filled_regions) {
      if (c.kind != CavityKind::narrow_openings || listed == kRegionsNamed) continue;
      ++listed;
      s << "; the pocket around " << point_text(c.centre) << " (" << c.voxels << " voxels) has " << c.openings
        << " opening" << (c.openings == 1 ? "" : "s") << ", the largest at " << point_text(c.opening_centre);
    }
    more_regions(s, listed, r.cavities_behind_openings);
    s << ": the model is the object's outer surface";
  }
  if (r.cavity_specks > 0)
    s << "; " << r.cavity_specks << " speck" << (r.cavity_specks == 1 ? "" : "s") << " (under "
      << kCavitySpeckVoxels << " voxels: noise, voxel-sized handles of a rough surface) filled too";
  return s.str();
}

std::string handle_summary(const DeformResult& r) {
  if (r.handles == 0) return {};
  std::ostringstream s;
  const bool cut = r.handle_repair == HandleRepair::cut;
  s << "handles: " << r.handles
    << (cut ? " cut across the body at its thinnest place (" : " capped by a membrane across the hole at its narrowest place (")
    << r.handle_voxels << " voxels; the model stays genus 0)";
  std::size_t listed = 0;
  for (const Cavity& c : r.filled_regions) {
    if ((c.kind != CavityKind::handle && c.kind != CavityKind::cut) || listed == kRegionsNamed) continue;
    ++listed;
    s << "; at " << point_text(c.centre) << (cut ? ", the body " : ", the hole ") << format_number(c.width, 3)
      << " mm across, " << c.voxels << " voxels";
  }
  more_regions(s, listed, r.handles);
  return s.str();
}

std::string voxel_seed_summary(const DeformResult& r) {
  if (!r.voxel_seed) return {};
  std::ostringstream s;
  s << "voxel seed: " << r.voxel_seed_voxels << " voxels (" << r.voxel_seed_background
    << " of them background: slits narrower than two voxels, or taken to keep it well-composed; "
    << r.voxel_seed_left_out
    << " object voxels next to it left out), its surface's " << r.voxel_seed_surface_faces
    << " faces reduced to the level of detail before the model ran";
  return s.str();
}

std::string budget_summary(const DeformResult& r) {
  if (r.face_budget == 0) return {};
  return "face budget: " + std::to_string(r.face_budget) + " faces requested, " + std::to_string(r.faces) +
         " obtained (" + std::to_string(r.budget_subdivisions) + " subdivision" +
         (r.budget_subdivisions == 1 ? "" : "s") + ", " + std::to_string(r.budget_collapses) + " collapses" +
         (r.budget_splits > 0 ? ", " + std::to_string(r.budget_splits) + " splits" : std::string()) +
         (r.budget_relax_moves > 0 ? ", faces evened out by " + std::to_string(r.budget_relax_moves) + " moves"
                                   : std::string()) +
         ")";
}

std::string gap_summary(const DeformResult& r) {
  if (r.gap_closed_voxels == 0 && r.gap_reachable_voxels == 0) return {};
  return "gap: " + std::to_string(r.gap_closed_voxels) +
         " free voxels beyond openings or channels narrower than the gap closed (" +
         std::to_string(r.gap_reachable_voxels) + " reachable); caps over bridged openings: " +
         std::to_string(r.bridge_vertices) + " vertices";
}

namespace {

// Wall seconds since construction, added to a stage's figure by add_to().
class Stopwatch {
 public:
  Stopwatch() : start_(std::chrono::steady_clock::now()) {}
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }
  void add_to(double& total) {
    const auto now = std::chrono::steady_clock::now();
    total += std::chrono::duration<double>(now - start_).count();
    start_ = now;
  }

 private:
  std::chrono::steady_clock::time_point start_;
};

void require(bool ok, const std::string& message) {
  if (!ok) throw InvalidOption(message);
}

std::string num(double v) { return format_number(v); }

double effective_intensity_scale(const DeformOptions& o, const Volume& v) {
  return o.intensity_scale > 0.0 ? o.intensity_scale : 0.01 * (v.max_value() - v.min_value());
}

// The largest neighbour separation in a regular ring of equilateral faces of
// the level-of-detail area A: edge sqrt(4 A / sqrt 3), ring diameter twice that.
double lod_edge_length(const DeformOptions& o, double voxel) {
  return std::sqrt(4.0 * o.lod_face_area / std::sqrt(3.0)) * voxel;
}

double lod_ring_extent(const DeformOptions& o, double voxel) { return 2.0 * lod_edge_length(o, voxel); }

// Eq. 3's pull on a vertex is a2 / extent per mm, D's is a0 per voxel: where
// the first reaches the second the model cannot grow (or shrink) at all.
// With a2 = 5 that happens below a level of detail of about 3 voxel^2 (a
// ring of 5.3 voxels): a ball grown from a seed of radius 3 voxels at
// lod_face_area 2 stopped at 80 faces, smaller than its seed. So the floor
// of the extent (TopologyTerm's min_extent) is also never below the extent at
// which T pulls kTopologyPull times as hard as D: 9.1 voxels for the paper's
// gains, under the default level of detail's 9.6 (defaults unchanged).
constexpr double kTopologyPull = 0.55;

double topology_extent_floor(const DeformOptions& o, double voxel) {
  const double balance = o.a0 > 0.0 ? o.a2 / (kTopologyPull * o.a0) * voxel : 0.0;
  return std::max(lod_ring_extent(o, voxel), balance);
}

// A vertex whose move the guard refused tries again the next cycle up to
// this many times in a row, then at intervals doubling up to
// kMaxRetryInterval cycles (sooner when a move nearby wakes it). Most
// refusals are of vertices pressed against another part of the model (a
// seam), refused again at every try: with 3 tries and intervals up to 16
// cycles the CT series' guard refused 1,976,199 moves, with 1 and 64
// 1,039,056, the run 44.4 -> 39.0 s (means of three alternated runs, stop
// 65); the T1 head the same time, the phantoms' models unchanged.
constexpr int kRetriesWhenRefused = 1;
constexpr int kMaxRetryInterval = 64;
// smooth_pleats: rounds per stage, rings around the faces in contact, passes.
constexpr int kPleatRounds = 8;
constexpr int kPleatRings = 2;
constexpr int kPleatPasses = 20;
constexpr double kPleatEdge = 0.25;  // voxels: shorter edges are a crumple's
// refine_where_blocked: faces ask for smaller faces while larger than this
// times the finest local size (a face at most twice the finest used to keep
// its size, and the front inside a channel two voxels wide, faces of about
// 0.8 voxel^2, stopped there; a quarter of such a face is clamped to the
// finest size).
constexpr double kAskAboveFinest = 1.2;

// How far a flip or a collapse of the triangle-quality pass may move the surface, voxels.
constexpr double kQualityMaxError = 0.1;
// The triangle-quality pass removes spikes whose ring lies within this radius, voxels.
constexpr double kSpikeRadius = 0.75;

// The face budget: the fitted model has at least this many times the budget's
// faces before it is reduced: more faces to choose from, fitted with more
// smoothing (refine_for_budget). Measured, mean distance at the default run's
// own face count: noisy ellipsoid on 0.5 x 0.5 x 2 mm voxels 0.074 voxel
// (default run 0.084), noisy branching tube 0.060 (0.067), noisy C tube 0.032
// (0.037), clean branching tube 0.047 (0.055); with 1 (reduce what the
// deformation gave, subdivide only below the budget) they were the default's.
// 3.5 rather than 4: a budget just above the default's count (the tooth's
// 5,892 faces, asked 6,000) takes one subdivision, not two (14 s against 6 s).
constexpr double kBudgetSourceFactor = 3.5;
constexpr double kBudgetSlack = 0.02;
// The shortest edge a growing model's move may make, voxels (piles_onto_a_neighbour).
constexpr double kPileUpEdge = 0.1;
// The fine fit's bound beyond the coarse faces' sagitta, voxels
// (subdivision_fit_bounds; measured on the study's salt-and-pepper ellipsoid).
constexpr double kBudgetBoundFloor = 0.05;
// The reduced model's faces evened out before its last fit (even_out_faces).
// Measured (README, stop 61) on the study's faces sweep (30 cells, noise
// sigma 20, then 5 and 12 with other seeds) and on 60 held-out runs; tried
// and not kept there: the flips after the relaxation, 6 and 10 passes, a
// crease bound of 20 degrees, flips up to 20 degrees (the tubes' faces
// grow isotropic, farther), neighbours weighed by their faces' size.
constexpr double kBudgetFlipDihedral = 10.0;    // degrees
constexpr double kBudgetCreaseDihedral = 30.0;  // degrees: vertices at sharper edges stay
constexpr double kBudgetRelaxFraction = 0.5;
constexpr int kBudgetRelaxPasses = 3;
// The sub-voxel fit's over-relaxation (FitOptions::over_relaxation) for the
// model's fit and the face budget's last one. A vertex's offset is averaged
// with its ring's, so a pass corrects only part of what a vertex alone is
// off, and moves under FitOptions::still end the creep short of the fixed
// point. Measured (README, stop 57) over six phantoms, noise 0 to 10 % of the
// contrast, two noise seeds (geometric means): mean distance 5.5 % lower at
// the defaults (14 plain passes instead of 8 gain 0.6 %), 3.4 % lower at face
// budgets of 5, 10 and 20 % of marching cubes' faces; 2.0 overshoots on the
// clean cube and branching shape. Not in the budget's subdivided fits (with
// them the budget's gain was 0.6 %) nor in the level of detail's rounds (the
// 25-degree bound's cost on the branching tube rose from 0.016 to 0.029 voxel).
constexpr double kFitOverRelaxation = 1.6;

}  // namespace

void validate(const DeformOptions& o, const Volume& volume) {
  // Every range is the catalogue's (option_catalogue.h); what follows it ties options together.
  for (const auto& option : deform_option_catalogue()) check_option(option, option.get(o));
  require(std::isfinite(o.threshold), "the threshold T must be set to a finite value");
  require(o.optimizer.min_step <= o.optimizer.max_step,
          "steps must satisfy min_step <= max_step, got [" + num(o.optimizer.min_step) + ", " +
              num(o.optimizer.max_step) + "]");
  require(!o.obstacle || (!o.subvoxel_fit && o.lod_tolerance == 0.0),
          "an obstacle needs subvoxel_fit off and lod_tolerance 0 (the fit and the error-driven level of detail "
          "do not check obstacles)");
  require(o.face_budget == 0 || o.face_budget <= o.max_faces,
          "face_budget " + std::to_string(o.face_budget) + " is above max_faces " + std::to_string(o.max_faces) +
              ": raise max_faces or ask for fewer faces");
  require(o.face_budget == 0 || o.lod_tolerance == 0.0,
          "face_budget and lod_tolerance both choose the number of faces: set one of them (lod_tolerance 0 or "
          "face_budget 0)");
  require(o.face_budget == 0 || !o.obstacle,
          "an obstacle needs face_budget 0 (the budget's collapses do not check obstacles)");

  require(o.topology == Topology::solid || o.fill_cavities,
          "topology exact needs fill_cavities on (the cavities it models are those the fill finds)");
  require(o.handle_repair == HandleRepair::membrane || (o.mode == Mode::grow && o.topology == Topology::solid),
          "handle_repair cut needs mode grow and topology solid (a shrinking model, and the exact topology's "
          "tubes, go through the membranes)");

  if (volume.voxel_count() == 0) throw InvalidVolume("the volume is empty");
  if (!(volume.max_value() > volume.min_value()))
    throw InvalidVolume("the volume is constant (every voxel is " + num(volume.min_value()) +
                        "): there is no boundary to find");
  require(o.threshold > volume.min_value() && o.threshold < volume.max_value(),
          "threshold " + num(o.threshold) + " lies outside the volume's value range (" +
              num(volume.min_value()) + ", " + num(volume.max_value()) + "): no voxel crosses it");
}

namespace {

// One deformation run. Each step of a cycle is a small method.
class Deformer {
 public:
  // `volume` is what the model sees (the input, or the gap gate's crop of it);
  // `input` is the caller's volume: its border is where a leak ends.
  Deformer(Mesh& mesh, const Volume& volume, const Volume& input, const DeformOptions& options,
           const DeformObserver& observer)
      : mesh_(mesh),
        volume_(volume),
        input_(input),
        o_(options),
        observer_(observer),
        voxel_(volume.voxel_size()),
        threads_(resolve_thread_count(options.threads)),
        cost_{DeformationPotential(options.a0, options.reach, voxel_),
              ImageEvent(options.a1, volume, options.threshold, options.polarity, options.mode,
                         effective_intensity_scale(options, input)),
              TopologyTerm(options.a2, options.lod_topology_extent ? topology_extent_floor(options, voxel_) : 0.0,
                           options.max_topology_ratio)},
        input_image_(1.0, input, options.threshold, options.polarity, options.mode, 1.0) {
    max_travel_ = options.refinement_travel * lod_edge_length(options, voxel_);
  }

  void check_seed() const;
  // Numbers the cycles from first_cycle + 1 (cycles already run at coarser
  // levels count toward max_cycles and the observer sees one sequence).
  DeformResult run(int first_cycle = 0);

 private:
  bool run_cycle(int cycle);
  void compute_face_normals();
  VertexNeighbourhood neighbourhood(Mesh::VertexHandle v) const;
  std::vector<int> evaluate_active(std::vector<StepResult>& steps);
  std::size_t apply_moves(const std::vector<int>& candidates, const std::vector<StepResult>& steps,
                          int cycle);
  std::size_t resample(int cycle);
  void activate_around(Mesh::VertexHandle v);
  static constexpr int kNoWake = std::numeric_limits<int>::min();
  bool wake(int event);
  void touch(Mesh::VertexHandle v) { touched_[static_cast<std::size_t>(v.idx())] = touch_clock_; }
  bool untouched_since(int v, int clock) const { return touched_[static_cast<std::size_t>(v)] < clock; }
  // The vertices of face f ({-1, -1, -1} for f < 0): what a refusal keeps of the face it met.
  std::array<int, 3> corners_of(int f) const;
  bool guard_allows(Mesh::VertexHandle v, const Vec3& p, IntersectionGuard::Checker& checker);
  int make_move(int i, const StepResult& r, int cycle, IntersectionGuard::Checker& checker);
  bool piles_onto_a_neighbour(Mesh::VertexHandle v, const Vec3& p) const;
  bool refusal_holds(Mesh::VertexHandle v, const Vec3& p) const;
  bool flip_allowed(Mesh::EdgeHandle e, const Mesh::VertexHandle (&quad)[4]);
  bool flip_refusal_holds(std::size_t edge, const Mesh::VertexHandle (&quad)[4]) const;
  // Per face: whether a corner, or a vertex within `rings` rings of one, was
  // touched since the mark `seen` (0: every face), which becomes now.
  void faces_touched_since(int& seen, std::vector<char>& faces, int rings = 0);
  void grow_per_vertex_state();
  bool converged(int cycle) const;
  void start_stage(int cycle);
  std::size_t count_border_vertices() const;
  void finish(int cycle, DeformResult& result);
  void release_cycle_state();
  bool held_by_gate(Mesh::VertexHandle v) const;
  std::size_t coarsen_shrunk_faces();
  bool object_ahead(Mesh::FaceHandle f, std::vector<Vec3>* free_points = nullptr) const;
  double room_ahead(const std::vector<Vec3>& free_points) const;
  double room_ahead_of(const Vec3& p, const Vec3& ahead) const;
  double room_ahead_of_centre(Mesh::FaceHandle f) const;
  double room_ahead_of_held_vertex(Mesh::VertexHandle v) const;
  void ask_around_held_vertices(double finest, std::vector<char>& at_mouth, std::vector<double>& floor_area) const;
  bool at_wall(Mesh::VertexHandle v) const;
  bool in_the_open(const Vec3& p) const;
  double width_area(Mesh::VertexHandle v) const;
  double face_area_for_room(const Vec3& p, const Vec3& normal) const;
  ChannelWidthOptions width_options() const;
  std::size_t refine_where_blocked(int cycle);
  std::size_t relax_bridges();
  std::size_t even_out_faces();
  void fit_reduced(const FitOptions& fit, DeformResult& result);
  std::size_t smooth_pleats(int cycle);
  std::size_t collapse_edges(const CollapseOptions& c);
  struct PleatMasks {
    std::vector<char> flaps;  // flaps and needles, by vertex
    std::vector<char> all;    // those and the faces in contact across background
  };
  PleatMasks find_pleats() const;
  Vec3 face_normal_of(Mesh::FaceHandle f) const;
  std::vector<char> in_background(const std::vector<char>& flagged) const;
  Vec3 face_centroid(Mesh::FaceHandle f) const;
  std::vector<char> edges_between(const std::vector<char>& flagged) const;
  void restart_stage(int cycle);
  void improve_quality(DeformResult& result);
  bool subdivide_safely(int cycle);
  void refine_for_budget(int cycle, const FitOptions& fit, std::vector<Vec3>& origin, DeformResult& result);
  void reduce_to_budget(const FitOptions& fit, DeformResult& result);
  void sharpen_edges(const FitOptions& fit, DeformResult& result);
  // What the voxels' noise around the model makes of a crossing, mm
  // (estimate_edge_noise over the model's box).
  double image_edge_noise() const;
  void use_image_noise(FitOptions& fit, double edge) const;
  void settle_budget(DeformResult& result);

  Mesh& mesh_;
  const Volume& volume_;
  const Volume& input_;
  const DeformOptions& o_;
  const DeformObserver& observer_;
  double voxel_;
  int threads_;
  CostFunction cost_;
  ImageEvent input_image_;  // the image event on the caller's volume (the gap gate's caps)
  std::unique_ptr<IntersectionGuard> guard_;
  std::vector<IntersectionGuard::Checker> checkers_;  // per thread, for apply_moves()
  std::size_t rejected_earlier_stages_ = 0;
  double max_travel_ = 0.0;  // mm, after a global refinement

  // Per-vertex state, indexed by vertex handle.
  std::vector<double> step_;          // adaptive step, voxels
  std::vector<double> cost_value_;    // last evaluated cost
  std::vector<char> active_;          // evaluate next cycle
  std::vector<char> settled_;         // crossed back from the blocked region this stage
  std::vector<int> refused_;          // moves refused in a row by the guard or the obstacle
  std::vector<int> retry_at_;         // cycle at which a vertex refused again and again tries again (0: none)
  // The guard's last refusal of a vertex's move, while the faces it decided
  // on stay as they were (issue 17: on the T1 head 390,000 of the 546,000
  // refusals in the cycles were the same move refused again, a vertex pressed
  // against another part of the model that had not moved).
  struct Refusal {
    Vec3 to = Vec3::Zero();                 // the refused position
    int clock = -1;                         // touch_clock_ then (-1: none)
    std::array<int, 3> blocker{-1, -1, -1};  // the vertices of the face it would have cut (-1: its own fan)
    int face = -1;                           // that face (-1: its own fan), the guard's first test next time
  };
  std::vector<Refusal> refusal_;
  // The guard's last refusal of an edge's flip, while the quad and the face
  // a new face would cut stay as they were: a refused flip's edge is asked
  // again every cycle (flip_to_improve), and on the T1 head those checks,
  // the same flips refused again, were a third of the time of the cycles
  // in which a stage converges (perf). The answer is the guard's: the two
  // new faces and that face are the same triangles.
  struct FlipRefusal {
    int clock = -1;                          // touch_clock_ then (-1: none)
    std::array<int, 4> quad{-1, -1, -1, -1};  // the flip's quad then
    std::array<int, 3> blocker{-1, -1, -1};   // the vertices of the face a new face cut (-1: none)
  };
  std::vector<FlipRefusal> flip_refusal_;  // per edge index
  std::vector<Vec3> anchor_;          // position when last counted as moving
  std::vector<Vec3> stage_start_;     // position when the stage began or the vertex was created
  std::vector<int> last_change_;      // cycle the vertex last moved beyond the tolerance
  std::vector<double> local_area_;    // faces around the vertex are split above this area, mm^2
                                      // (the level of detail, or finer where refine_where_blocked asked)
  int local_rounds_ = 0;              // rounds of refine_where_blocked so far
  std::vector<Vec3> round_start_;     // where each vertex was when the last round of refine_where_blocked asked
  int idle_rounds_ = 0;               // rounds in a row after which no vertex moved a voxel
  // refine_where_blocked's per-face verdict (before the held vertices and the
  // contacts), kept between rounds: it reads the face's corners, their
  // 1-rings' normals and the image only, so a face none of whose corners or
  // their neighbours was touched since the last round has the same one.
  std::vector<char> mouth_verdict_;   // per face: it spans a channel's mouth narrower than itself
  std::vector<double> floor_verdict_;  // per face: the area the room ahead asks for
  int verdicts_seen_ = 0;             // the last round's mark (0: every face again)
  int pleat_rounds_ = 0;              // rounds of smooth_pleats in this stage
  std::vector<Vec3> face_normal_;     // unnormalised, per face, for the cycle
  // Work proportional to what changed (issue 17: on the CT series, passes
  // over every face and edge each cycle were a sixth of the run while a few
  // hundred vertices moved in the stages' long tails). A vertex is touched
  // when it moves, is made, or its faces change (a split or flip next to
  // it); each pass that keeps per-face results (the normals, the splits, the
  // flips) looks again only at the faces around vertices touched since it
  // last ran (touched_[v] >= its mark), with the same results as a pass over
  // everything.
  std::vector<int> touched_;          // per vertex: touch_clock_ when last touched
  int touch_clock_ = 1;
  int normals_seen_ = 0, splits_seen_ = 0, flips_seen_ = 0;  // each pass's mark (0: everything)
  std::vector<char> face_flags_;      // scratch: faces to look at
  std::vector<int> wake_frontier_, wake_next_;  // scratch of activate_around()
  std::vector<char> edge_dirty_;      // edges the next flip pass looks at (flip_to_improve)
  int last_split_cycle_ = 0;
  std::size_t flips_ = 0;
  CycleReport report_;
};

void Deformer::check_seed() const {
  check_seed_mesh(mesh_);
  std::size_t free = 0;
  Vec3 centroid = Vec3::Zero();
  for (auto v : mesh_.vertices()) {
    const Vec3 p = to_eigen(mesh_.point(v));
    if (!volume_.contains(p) && o_.mode == Mode::grow) {  // shrinking, the outside is background
      std::ostringstream s;
      s << "seed vertex " << v.idx() << " at (" << p.x() << ", " << p.y() << ", " << p.z()
        << ") mm lies outside the volume";
      throw InvalidSeed(s.str());
    }
    centroid += p;
    if (!cost_.image.is_blocked(p)) ++free;
  }
  centroid /= static_cast<double>(mesh_.n_vertices());
  if (free == 0 && cost_.image.is_blocked(centroid)) {
    throw InvalidSeed(o_.mode == Mode::grow
                          ? "the seed lies entirely outside the object: no seed vertex is on the object's "
                            "side of the threshold (check the seed point, the threshold and the polarity)"
                          : "the seed lies entirely inside the object: shrink mode needs a seed around it "
                            "(check the seed, the threshold and the polarity)");
  }
}

void Deformer::grow_per_vertex_state() {
  const std::size_t n = mesh_.n_vertices();
  const std::size_t old = step_.size();
  if (old >= n) return;
  step_.resize(n, o_.optimizer.max_step);
  cost_value_.resize(n, 0.0);
  active_.resize(n, 1);
  settled_.resize(n, 0);
  refused_.resize(n, 0);
  retry_at_.resize(n, 0);
  refusal_.resize(n);
  anchor_.resize(n);
  stage_start_.resize(n);
  last_change_.resize(n, 0);
  touched_.resize(n, touch_clock_);
  const double coarse = o_.lod_face_area * voxel_ * voxel_;
  local_area_.resize(n, coarse);
  for (std::size_t i = old; i < n; ++i) {
    // A vertex made by a split (at the midpoint of two of its neighbours) is
    // as fine as the coarser end of the split edge: fineness does not spread.
    const Mesh::VertexHandle m(static_cast<int>(i));
    const Vec3 pm = to_eigen(mesh_.point(m));
    std::vector<Mesh::VertexHandle> ring(mesh_.vv_begin(m), mesh_.vv_end(m));
    for (std::size_t x = 0; x < ring.size(); ++x)
      for (std::size_t y = x + 1; y < ring.size(); ++y)
        if (static_cast<std::size_t>(ring[x].idx()) < old && static_cast<std::size_t>(ring[y].idx()) < old &&
            (0.5 * (to_eigen(mesh_.point(ring[x])) + to_eigen(mesh_.point(ring[y]))) - pm).squaredNorm() <
                1e-12 * voxel_ * voxel_)
          local_area_[i] = std::max(local_area_[ring[x].idx()], local_area_[ring[y].idx()]);
    // Out of the channel (free room half an edge of the level of detail away
    // on every axis), the faces grow back to the level of detail.
    if (local_area_[i] < coarse && in_the_open(pm)) local_area_[i] = coarse;
    // Inside, the faces follow the width of the room (channel_width.h): a
    // sheet or a wide room behind a narrow mouth is not lined with the mouth's.
    else if (local_area_[i] < coarse) local_area_[i] = std::max(local_area_[i], width_area(m));
    anchor_[i] = to_eigen(mesh_.point(Mesh::VertexHandle(static_cast<int>(i))));
    stage_start_[i] = anchor_[i];
    last_change_[i] = report_.cycle;
  }
}

void Deformer::start_stage(int cycle) {
  grow_per_vertex_state();
  std::fill(active_.begin(), active_.end(), 1);
  std::fill(settled_.begin(), settled_.end(), 0);
  std::fill(last_change_.begin(), last_change_.end(), cycle);
  last_split_cycle_ = cycle;
  std::fill(touched_.begin(), touched_.end(), touch_clock_);
  normals_seen_ = splits_seen_ = flips_seen_ = verdicts_seen_ = 0;
  edge_dirty_.clear();
  flip_refusal_.clear();  // the guard's answers of this stage only
  if (guard_) rejected_earlier_stages_ += guard_->statistics().rejected_moves;
  guard_ = std::make_unique<IntersectionGuard>(mesh_, o_.optimizer.max_step * voxel_, 1e-6 * voxel_ * voxel_);
}

void Deformer::faces_touched_since(int& seen, std::vector<char>& faces, int rings) {
  const int since = seen;
  seen = ++touch_clock_;
  faces.assign(mesh_.n_faces(), since == 0 ? 1 : 0);
  if (since == 0) return;
  const auto mark_faces_around = [&](std::size_t i) {
    for (auto f : mesh_.vf_range(Mesh::VertexHandle(static_cast<int>(i)))) faces[static_cast<std::size_t>(f.idx())] = 1;
  };
  if (rings == 0) {  // every cycle, three times: one pass over the marks
    for (std::size_t i = 0; i < touched_.size(); ++i)
      if (touched_[i] >= since) mark_faces_around(i);
    return;
  }
  std::vector<char> near(touched_.size(), 0);
  for (std::size_t i = 0; i < touched_.size(); ++i) near[i] = touched_[i] >= since;
  near = grow_by_rings(mesh_, std::move(near), rings);
  for (std::size_t i = 0; i < near.size(); ++i)
    if (near[i]) mark_faces_around(i);
}

void Deformer::compute_face_normals() {
  // Only faces around touched vertices, and new faces, changed since.
  const std::size_t old = face_normal_.size();
  faces_touched_since(normals_seen_, face_flags_);
  face_normal_.resize(mesh_.n_faces());
  std::vector<int> faces;
  for (std::size_t i = 0; i < face_flags_.size(); ++i)
    if (face_flags_[i] || i >= old) faces.push_back(static_cast<int>(i));
  parallel_for(faces.size(), threads_, [&](std::size_t k) {
    const auto i = static_cast<std::size_t>(faces[k]);
    face_normal_[i] = face_area_normal(mesh_, Mesh::FaceHandle(static_cast<int>(i)));
  });
}

VertexNeighbourhood Deformer::neighbourhood(Mesh::VertexHandle v) const {
  VertexNeighbourhood n;
  n.position = to_eigen(mesh_.point(v));

  // Normal over the faces within `normal_rings` rings: the faces around v and,
  // for 2 rings, the faces adjacent to them (section 7: a larger neighbourhood
  // is more stable; too large is inaccurate).
  // Per-thread scratch: no allocation per vertex and cycle. The sum runs in
  // face order as before.
  thread_local std::vector<int> near_vertices, near_faces;
  vertices_within(mesh_, v, o_.normal_rings - 1, near_vertices);
  faces_around(mesh_, near_vertices, near_faces);
  Vec3 normal = Vec3::Zero();
  for (int f : near_faces) normal += face_normal_[f];
  const double len = normal.norm();
  n.normal = len > 0.0 ? Vec3(normal / len) : Vec3::UnitZ();

  // Eq. 3: centroid of the neighbours and their largest separation.
  thread_local std::vector<Vec3> ring;
  ring.clear();
  for (auto w : mesh_.vv_range(v)) ring.push_back(to_eigen(mesh_.point(w)));
  Vec3 centroid = Vec3::Zero();
  for (const auto& p : ring) centroid += p;
  n.ring_centroid = centroid / static_cast<double>(ring.size());
  double extent2 = 0.0;
  for (std::size_t j = 0; j < ring.size(); ++j)
    for (std::size_t k = j + 1; k < ring.size(); ++k) extent2 = std::max(extent2, (ring[j] - ring[k]).squaredNorm());
  n.ring_extent = extent2 > 0.0 ? std::sqrt(extent2) : voxel_;
  n.refined = v.idx() < static_cast<int>(local_area_.size()) &&
              local_area_[v.idx()] < o_.lod_face_area * voxel_ * voxel_;

  // Section 5: grow moves along the outward normal, shrink against it; a vertex
  // lying in the region the model must not enter reverses its sense locally.
  n.sense = o_.mode == Mode::grow ? 1.0 : -1.0;
  if (o_.local_flip && cost_.image.is_blocked(n.position)) n.sense = -n.sense;
  return n;
}

std::vector<int> Deformer::evaluate_active(std::vector<StepResult>& steps) {
  std::vector<int> active;
  for (std::size_t i = 0; i < active_.size(); ++i) {
    if (retry_at_[i] != 0 && retry_at_[i] <= report_.cycle) {
      active_[i] = 1;
      retry_at_[i] = 0;
    }
    if (active_[i]) active.push_back(static_cast<int>(i));
  }
  steps.assign(active.size(), StepResult{});
  parallel_for(active.size(), threads_, [&](std::size_t k) {
    const Mesh::VertexHandle v(active[k]);
    const VertexNeighbourhood n = neighbourhood(v);
    StepResult r = steepest_descent_step(cost_, n, step_[v.idx()], voxel_, o_.optimizer);
    if (r.moved) {
      // A vertex that came back from the blocked region does not cross into
      // it again this stage: it would only oscillate around the boundary.
      const bool recrosses =
          settled_[v.idx()] && cost_.image.is_blocked(r.position) && !cost_.image.is_blocked(n.position);
      // After a global refinement the model only refines what it found: a
      // vertex may not travel far (a leak through a hole the finer mesh could
      // now pass).
      const bool travels_too_far = report_.stage > 0 && !n.refined && (r.position - stage_start_[v.idx()]).norm() > max_travel_;
      if (recrosses || travels_too_far) {
        r.moved = false;
        r.position = n.position;
        r.cost = cost_(n, n.position);
        r.next_step = o_.optimizer.min_step;
      }
    }
    steps[k] = r;
  });
  return active;
}

// Beyond the paper (issue 17): a growing model's edges lengthen, except
// where vertices pile up. At the tip of a spike of the object (seen on the
// CT head phantom's 5 mm slices) the image drew every vertex the local
// resampling made there to the same point: each one split the long edge
// from the pile again, the new vertex moved to the pile too, and the model
// went on splitting and moving one vertex at a time (17 vertices within
// 0.01 mm of each other at one place; the series' last stage ran 921 cycles
// instead of 624, most of them with one or two vertices moving). A move
// that would bring a vertex within kPileUpEdge voxels of a neighbour it is
// farther from is not made: such an edge adds nothing to the model (the
// triangle-quality pass collapses it anyway). Nor within kPileUpEdge of a
// neighbour's neighbour (stop 65): on the T1 head from its voxels a strip
// between two vertices of high valence zigzagged sixteen times, each vertex
// split off the strip's long edge moving onto the point where the vertex
// two before it sat; the layers ended 1e-9 mm apart, folded flat, and no
// float point could keep them apart in a PLY. Shrinking, edges shorten as
// the surface contracts; its pleats have their own pass (smooth_pleats).
bool Deformer::piles_onto_a_neighbour(Mesh::VertexHandle v, const Vec3& p) const {
  if (o_.mode != Mode::grow) return false;
  const double limit2 = kPileUpEdge * kPileUpEdge * voxel_ * voxel_;
  const Vec3 from = to_eigen(mesh_.point(v));
  const auto piles_onto = [&](Mesh::VertexHandle w) {
    const Vec3 q = to_eigen(mesh_.point(w));
    return w != v && (p - q).squaredNorm() < limit2 && (from - q).squaredNorm() >= limit2;
  };
  for (auto w : mesh_.vv_range(v)) {
    if (piles_onto(w)) return true;
    for (auto u : mesh_.vv_range(w))
      if (piles_onto(u)) return true;
  }
  return false;
}

// Whether the guard allows moving v to p. A move refused before is refused
// again without a check when it goes to the same point and neither v, its
// neighbours nor the face it would have cut were touched since (moved, split
// or flipped: touch()): the guard would decide on the same triangles. Its
// answer is a yes or no over them, so the outcome is the guard's own.
bool Deformer::guard_allows(Mesh::VertexHandle v, const Vec3& p, IntersectionGuard::Checker& checker) {
  const auto i = static_cast<std::size_t>(v.idx());
  if (refusal_holds(v, p)) {
    ++checker.rejected;
    return false;
  }
  if (guard_->move_is_safe(v, p, refusal_[i].face, checker)) {
    refusal_[i].clock = -1;
    refusal_[i].face = -1;
    return true;
  }
  Refusal& r = refusal_[i];
  r.to = p;
  r.clock = touch_clock_;
  r.face = checker.last_blocking_face;
  r.blocker = corners_of(r.face);
  return false;
}

std::array<int, 3> Deformer::corners_of(int f) const {
  std::array<int, 3> corners{-1, -1, -1};
  if (f < 0) return corners;
  std::size_t k = 0;
  for (auto w : mesh_.fv_range(Mesh::FaceHandle(f))) corners[k++] = w.idx();
  return corners;
}

bool Deformer::flip_allowed(Mesh::EdgeHandle e, const Mesh::VertexHandle (&quad)[4]) {
  const auto i = static_cast<std::size_t>(e.idx());
  if (flip_refusal_.size() <= i) flip_refusal_.resize(mesh_.n_edges());
  if (flip_refusal_holds(i, quad)) {
    guard_->count_rejected_flip();
    return false;
  }
  FlipRefusal& r = flip_refusal_[i];
  if (guard_->flip_is_safe(e, quad)) {
    r.clock = -1;
    return true;
  }
  r.clock = touch_clock_;
  for (std::size_t k = 0; k < 4; ++k) r.quad[k] = quad[k].idx();
  r.blocker = corners_of(guard_->last_blocking_face());
  return false;
}

bool Deformer::flip_refusal_holds(std::size_t edge, const Mesh::VertexHandle (&quad)[4]) const {
  const FlipRefusal& r = flip_refusal_[edge];
  if (r.clock < 0) return false;
  for (std::size_t k = 0; k < 4; ++k)
    if (r.quad[k] != quad[k].idx()) return false;
  for (int w : r.quad)
    if (!untouched_since(w, r.clock)) return false;
  for (int w : r.blocker)
    if (w >= 0 && !untouched_since(w, r.clock)) return false;
  return true;
}

bool Deformer::refusal_holds(Mesh::VertexHandle v, const Vec3& p) const {
  const Refusal& r = refusal_[static_cast<std::size_t>(v.idx())];
  if (r.clock < 0 || !(r.to.array() == p.array()).all()) return false;
  if (!untouched_since(v.idx(), r.clock)) return false;
  for (auto w : mesh_.vv_range(v))
    if (!untouched_since(w.idx(), r.clock)) return false;
  for (int w : r.blocker)
    if (w >= 0 && !untouched_since(w, r.clock)) return false;
  return true;
}

std::size_t Deformer::apply_moves(const std::vector<int>& candidates, const std::vector<StepResult>& steps,
                                  int cycle) {
  std::fill(active_.begin(), active_.end(), 0);
  // Every vertex moves at most one step this cycle: boxes inflated by the
  // largest step stay valid until the next rebuild.
  if (o_.prevent_self_intersection) guard_->prepare_moves();
  std::vector<int> movers;  // indices into candidates
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const int i = candidates[k];
    cost_value_[i] = steps[k].cost;
    step_[i] = steps[k].next_step;
    if (steps[k].moved) movers.push_back(static_cast<int>(k));
  }
  checkers_.resize(static_cast<std::size_t>(std::max(1, threads_)));
  std::size_t moved = 0;
  // One at a time, each accepted move seen by the checks after it, in an
  // order that depends on the positions only: the outcome does not depend
  // on the thread count. With the guard (and no obstacle) and many moves,
  // the moves go by cubes of space in eight colours (space_blocks.h; issue
  // 17: the guard's one-at-a-time checks were a fifth of the CT series'
  // time): cubes of one colour are further apart than any check reaches,
  // so they run on the threads at once, each cube's moves in vertex order.
  // Under kMovesByCubes moves, vertex order: the whole tooth at the
  // defaults, whose cycles move at most about a thousand vertices, met
  // itself across its pocket (355 mm^2) with every cycle by cubes; where two
  // fronts meet, the order decides which moves first.
  if (!o_.prevent_self_intersection || o_.obstacle || movers.size() < kMovesByCubes) {
    IntersectionGuard::Checker& checker = checkers_.front();
    for (int k : movers) {
      const auto j = static_cast<std::size_t>(k);
      moved += wake(make_move(candidates[j], steps[j], cycle, checker));
    }
  } else {
    // Per move, what it asks to wake (make_move()), woken after the
    // colour's moves in the colour's order of the moves, whichever thread
    // made each: the flags come out as in a pass in that order on one
    // thread (nothing reads them before the next cycle; a wake spreads only
    // through vertices it wakes itself, so the order decides which).
    std::vector<int> woken(candidates.size(), kNoWake);
    // Cubes wider than a check reads: a vertex within reach of a check may
    // have moved a step into it.
    std::vector<Vec3> at;
    at.reserve(movers.size());
    for (int k : movers)
      at.push_back(to_eigen(mesh_.point(Mesh::VertexHandle(candidates[static_cast<std::size_t>(k)]))));
    const CubeColouring cubes =
        colour_by_cubes(movers, at, std::max(guard_->reach() + 2.0 * o_.optimizer.max_step * voxel_, voxel_));
    for (std::size_t c = 0; c < 8; ++c) {
      run_colour(cubes.items[c], cubes.cube_starts[c], checkers_.size(), [&](int k, std::size_t w) {
        const auto j = static_cast<std::size_t>(k);
        woken[j] = make_move(candidates[j], steps[j], cycle, checkers_[w]);
      });
      for (int k : cubes.items[c]) moved += wake(woken[static_cast<std::size_t>(k)]);
    }
  }
  if (o_.prevent_self_intersection)
    for (auto& checker : checkers_) guard_->absorb(checker);
  return moved;
}

// What make_move() asks: i >= 0 moved (its surroundings wake), ~i refused
// (it wakes itself), kNoWake neither. Returns whether a vertex moved.
bool Deformer::wake(int event) {
  if (event == kNoWake) return false;
  if (event < 0) {
    active_[static_cast<std::size_t>(~event)] = 1;
    return false;
  }
  activate_around(Mesh::VertexHandle(event));
  return true;
}

// One move of apply_moves(): made unless it piles onto a neighbour, the
// guard or the obstacle refuses it. Writes only v's position and state;
// reads v's neighbours and what the guard's check reads. Returns what to
// wake (wake()), which it leaves to the caller.
int Deformer::make_move(int i, const StepResult& r, int cycle, IntersectionGuard::Checker& checker) {
  const Mesh::VertexHandle v(i);
  if (piles_onto_a_neighbour(v, r.position)) {
    step_[i] = o_.optimizer.min_step;
    return kNoWake;
  }
  if ((o_.prevent_self_intersection && !guard_allows(v, r.position, checker)) ||
      (o_.obstacle && o_.obstacle->blocks_move(mesh_, v, r.position))) {
    step_[i] = o_.optimizer.min_step;
    // Its neighbours may move out of the way: it tries again next cycle;
    // after kRetriesWhenRefused refusals in a row, at doubling intervals
    // (or when a move nearby wakes it). A vertex pressed against another
    // part of the model (the two sides of a thin sheet of object) was
    // otherwise evaluated and refused every cycle until the model
    // converged: most of the time of the study's CT head and MRI skin
    // (920,000 refusals on the MRI skin at the defaults, 2.7 million with
    // refine_channels, where the guard's checks took
    // 40 % of the CT head's time).
    // With an obstacle (the shrink-wrap's input, which the wrap hugs)
    // every cycle as before: its faces below min_angle doubled without.
    const int n = ++refused_[i];
    if (n <= kRetriesWhenRefused || o_.obstacle) return ~i;
    retry_at_[i] = cycle + std::min(kMaxRetryInterval, 1 << std::min(n - kRetriesWhenRefused, 8));
    return kNoWake;
  }
  const bool was_blocked = cost_.image.is_blocked(to_eigen(mesh_.point(v)));
  mesh_.set_point(v, to_point(r.position));
  touch(v);
  refused_[i] = 0;
  retry_at_[i] = 0;
  if (was_blocked && !cost_.image.is_blocked(r.position)) settled_[i] = 1;
  if ((r.position - anchor_[i]).norm() > o_.convergence_tolerance * voxel_) {
    anchor_[i] = r.position;
    last_change_[i] = cycle;
  }
  return i;
}

void Deformer::activate_around(Mesh::VertexHandle v) {
  // A vertex's cost depends on the faces within normal_rings rings (normal)
  // and on its 1-ring (eq. 3): wake every vertex that close.
  // (Called for every move, split and flip, one thread at a time: the
  // rings' lists are the deformer's, not allocated per call.)
  std::vector<int>& frontier = wake_frontier_;
  std::vector<int>& next = wake_next_;
  frontier.assign(1, v.idx());
  active_[v.idx()] = 1;
  for (int r = 0; r < std::max(1, o_.normal_rings); ++r) {
    next.clear();
    for (int u : frontier)
      for (auto w : mesh_.vv_range(Mesh::VertexHandle(u))) {
        if (!active_[w.idx()]) next.push_back(w.idx());
        active_[w.idx()] = 1;
      }
    frontier.swap(next);
  }
}

std::size_t Deformer::resample(int cycle) {
  const std::size_t before = mesh_.n_vertices();
  // A face none of whose corners was touched since the last pass kept its
  // area and its corners' limits: it was not split then, nor is it now.
  faces_touched_since(splits_seen_, face_flags_);
  const std::size_t splits = split_longest_edges(
      mesh_, cycle,
      [&](Mesh::FaceHandle f, Mesh::HalfedgeHandle) {
        double target = 0.0;  // fine only where all three corners are
        for (auto v : mesh_.fv_range(f)) target = std::max(target, local_area_[v.idx()]);
        return gdm::face_area(mesh_, f) > target;
      },
      &face_flags_);
  grow_per_vertex_state();
  for (std::size_t i = before; i < mesh_.n_vertices(); ++i) {
    // A split's midpoint, and its neighbours (their valences changed).
    const Mesh::VertexHandle m(static_cast<int>(i));
    activate_around(m);
    touch(m);
    for (auto w : mesh_.vv_range(m)) touch(w);
  }
  if (splits > 0) last_split_cycle_ = cycle;
  if (splits > 0 && o_.prevent_self_intersection) guard_->note_new_faces();
  if (o_.improve_triangles) {
    const auto flipped_triangle = [&](Mesh::VertexHandle a, Mesh::VertexHandle b, Mesh::VertexHandle c) {
      return Obstacle::Triangle{to_eigen(mesh_.point(a)), to_eigen(mesh_.point(b)), to_eigen(mesh_.point(c))};
    };
    const FlipVeto veto = [&](Mesh::EdgeHandle e, const Mesh::VertexHandle (&quad)[4]) {
      if (o_.prevent_self_intersection && !flip_allowed(e, quad)) return false;
      if (o_.obstacle && (o_.obstacle->blocks(flipped_triangle(quad[0], quad[1], quad[3])) ||
                          o_.obstacle->blocks(flipped_triangle(quad[2], quad[3], quad[1]))))
        return false;
      for (auto q : quad) {
        activate_around(q);
        touch(q);
      }
      return true;
    };
    // Every edge of the faces around a vertex touched since the last pass
    // (its quad, valences or link may have changed); the edges vetoed then
    // stay flagged (flip_to_improve).
    faces_touched_since(flips_seen_, face_flags_);
    edge_dirty_.resize(mesh_.n_edges(), 1);
    for (std::size_t f = 0; f < face_flags_.size(); ++f)
      if (face_flags_[f])
        for (auto e : mesh_.fe_range(Mesh::FaceHandle(static_cast<int>(f)))) edge_dirty_[static_cast<std::size_t>(e.idx())] = 1;
    flips_ += flip_to_improve(mesh_, o_.flip_max_dihedral, veto, &edge_dirty_);
  }
  return splits;
}

// Whether face f spans the mouth of a channel narrower than itself: at some
// of the points of the face (a grid about half a voxel apart), but at most
// half of them, the image is on the free side one and two voxels ahead along
// the face's normal (the sense of deformation). Faces that converged on the
// object's boundary see the blocked region ahead everywhere; faces that see
// free room over most of their area are not too large for what lies ahead
// (held by noise or by the model's own smoothness, not by their size).
bool Deformer::object_ahead(Mesh::FaceHandle f, std::vector<Vec3>* free_points) const {
  auto it = mesh_.cfv_iter(f);
  const Vec3 a = to_eigen(mesh_.point(*it)), b = to_eigen(mesh_.point(*++it)), c = to_eigen(mesh_.point(*++it));
  const Vec3 cross = (b - a).cross(c - a);
  const double len = cross.norm();
  if (!(len > 0.0)) return false;
  // One voxel along the normal, in that direction's spacing: on anisotropic
  // grids "two voxels deep" means two slices, not twice the finest spacing
  // (a speck of salt one 2 mm slice thick on a 1x1x2 mm grid otherwise
  // passed for a channel's mouth, and the model followed it).
  const Vec3 unit = cross / len;
  const double along = 1.0 / unit.cwiseQuotient(volume_.spacing()).norm();  // mm
  const Vec3 ahead = ((o_.mode == Mode::grow ? 1.0 : -1.0) * along) * unit;
  // Points about half a voxel apart, in voxels of the grid (along a coarse
  // axis, finer points see nothing new: the CT series' 5 mm slices were
  // sampled every 0.23 mm). Isotropic grids: as before.
  const Vec3& spacing = volume_.spacing();
  const double longest = std::max({(b - a).cwiseQuotient(spacing).norm(), (c - b).cwiseQuotient(spacing).norm(),
                                   (a - c).cwiseQuotient(spacing).norm()});
  const int k = std::max(2, static_cast<int>(std::ceil(longest / 0.5)));
  // Across the channel, 0.7 voxel to each side of its axis is free too: a
  // channel at least two voxels wide (the default gap), not a crack.
  const Vec3 u = (0.7 * voxel_) * ahead.normalized().unitOrthogonal();
  const Vec3 w = ahead.normalized().cross(u);
  const auto is_free = [&](const Vec3& q) { return !cost_.image.is_blocked(q); };
  const int points = (k + 1) * (k + 2) / 2;
  int free = 0;
  if (free_points) free_points->clear();
  for (int i = 0; i <= k; ++i)
    for (int j = 0; i + j <= k; ++j) {
      const Vec3 p = a + (static_cast<double>(i) / k) * (b - a) + (static_cast<double>(j) / k) * (c - a);
      const Vec3 q = p + 1.5 * ahead;
      if (is_free(p + ahead) && is_free(p + 2.0 * ahead) && is_free(q + u) && is_free(q - u) && is_free(q + w) &&
          is_free(q - w)) {
        if (2 * ++free > points) return false;  // free room over most of it: not held by its size
        // Where the width of the room it sees is measured (room_ahead).
        if (free_points) free_points->push_back(q);
      }
    }
  return free > 0;
}

// The width of the room seen from the points object_ahead found free
// (channel_width.h), the widest of them.
double Deformer::room_ahead(const std::vector<Vec3>& free_points) const {
  double room = 0.0;
  const ChannelWidthOptions w = width_options();
  for (const Vec3& q : free_points) room = std::max(room, narrowest_chord(cost_.image, q, w));
  return room;
}

// Room ahead of the model counts for local refinement only when it reaches
// this deep (grid spacings along the normal) ahead of the point half a voxel
// in front: a channel or a sheet does, a speck of impulse noise (one or two
// voxels, the salt-and-pepper ellipsoid of test_face_budget_targets) does not.
constexpr double kRoomDepth = 3.0;

// The width of the room half a voxel ahead of a face's centre looks into
// (room_width, channel_width.h), along the face's normal in that direction's
// spacing; -1 when the image is blocked there or the room is a speck. The
// front of a model inside a channel about two voxels wide has tilted faces
// whose corners stand on the channel's sides: one and two voxels along their
// normals is the side wall (object_ahead sees nothing free), half a voxel
// ahead of the centre is still the channel. The room's width, not the chord
// at that point: at the rounded rim of a sheet the chord is short, the sheet
// is not.
double Deformer::room_ahead_of_centre(Mesh::FaceHandle f) const {
  auto it = mesh_.cfv_iter(f);
  const Vec3 a = to_eigen(mesh_.point(*it)), b = to_eigen(mesh_.point(*++it)), c = to_eigen(mesh_.point(*++it));
  const Vec3 cross = (b - a).cross(c - a);
  if (!(cross.norm() > 0.0)) return -1.0;
  const Vec3 ahead = (o_.mode == Mode::grow ? 1.0 : -1.0) * cross.normalized();
  return room_ahead_of((a + b + c) / 3.0, ahead);
}

// The same for a point p of the model and its sense of deformation `ahead`
// (unit).
double Deformer::room_ahead_of(const Vec3& p, const Vec3& ahead) const {
  const double along = 1.0 / ahead.cwiseQuotient(volume_.spacing()).norm();  // mm
  const Vec3 front = p + (0.5 * along) * ahead;
  if (cost_.image.is_blocked(front) ||
      !free_room_reaches(cost_.image, front, ahead, kRoomDepth * along, volume_.spacing()))
    return -1.0;
  return room_width(cost_.image, p, ahead, width_options());
}

// A vertex held back from room ahead of it by eq. 3's hard limit (the
// topology term): a step of half a voxel along its normal breaks the limit,
// and the image half a voxel ahead is free. This is the tip of a front in a
// channel, whose neighbours stand on the channel's sides: only smaller faces
// let it on. Or held by the travel limit after a global refinement (a vertex
// not refined may travel refinement_travel edges from where the stage found
// it): the tip of a front that reached a channel's mouth late, free of the
// image and of eq. 3, that stopped there (a sweep over seeds: 3 of the
// two-voxel channel's 12 misses in 174 runs). Refined, it may travel on.
// Returns the width of the room it looks into (room_ahead_of), -1 when it is
// not held so. (Held in a wide room, it asks nothing: the room's
// width gives faces of the level of detail.) A vertex held by the image on a
// side, in a concave corner, is not held by the limit and asks nothing (the
// slit of test_cavities was lined with fine faces that met).
double Deformer::room_ahead_of_held_vertex(Mesh::VertexHandle v) const {
  // The image half a voxel ahead along the 1-ring normal must be free
  // (room_ahead_of): tested first, as most vertices of a converged model
  // stand at a wall and the neighbourhood below is the costlier part.
  Vec3 normal = Vec3::Zero();
  for (auto f : mesh_.vf_range(v)) normal += face_normal_[f.idx()];
  if (!(normal.norm() > 0.0)) return -1.0;
  const Vec3 ahead = (o_.mode == Mode::grow ? 1.0 : -1.0) * normal.normalized();
  const Vec3 p = to_eigen(mesh_.point(v));
  const double along = 1.0 / ahead.cwiseQuotient(volume_.spacing()).norm();  // mm, as room_ahead_of
  if (cost_.image.is_blocked(p + (0.5 * along) * ahead)) return -1.0;
  const VertexNeighbourhood n = neighbourhood(v);
  const double limit =
      n.refined ? std::max(o_.max_topology_ratio, TopologyTerm::kRefinedMaxRatio) : o_.max_topology_ratio;
  const bool by_the_limit = TopologyTerm::ratio(n, n.position + (n.sense * 0.5 * voxel_) * n.normal) > limit;
  const bool by_the_travel = report_.stage > 0 && !n.refined &&
                             (n.position - stage_start_[v.idx()]).norm() > max_travel_ - 0.5 * voxel_;
  if (!by_the_limit && !by_the_travel) return -1.0;
  return room_ahead_of(p, ahead);
}

// The faces around held vertices larger than the room ahead of the vertex
// asks for (channel_width.h) ask too, with that room's face size as their
// floor. A face already asking keeps the smaller of the two floors.
void Deformer::ask_around_held_vertices(double finest, std::vector<char>& at_mouth,
                                        std::vector<double>& floor_area) const {
  const double coarse = o_.lod_face_area * voxel_ * voxel_;
  const ChannelWidthOptions w = width_options();
  // The room's width per vertex, in parallel (read-only); -1: not held.
  std::vector<double> room(mesh_.n_vertices(), -1.0);
  parallel_for(mesh_.n_vertices(), threads_, [&](std::size_t i) {
    const Mesh::VertexHandle v(static_cast<int>(i));
    if ((mesh_.has_vertex_status() && mesh_.status(v).deleted()) || mesh_.is_isolated(v)) return;
    room[i] = room_ahead_of_held_vertex(v);
  });
  // Merged in vertex order: the same asking faces for any thread count.
  for (auto v : mesh_.vertices()) {
    const double width = room[static_cast<std::size_t>(v.idx())];
    if (width < 0.0) continue;
    const double floor = area_for_width(width, w, finest, coarse);
    for (auto f : mesh_.vf_range(v)) {
      const std::size_t i = static_cast<std::size_t>(f.idx());
      const double area = gdm::face_area(mesh_, f);
      if (!(area > kAskAboveFinest * finest) || !(area > floor)) continue;
      floor_area[i] = at_mouth[i] ? std::min(floor_area[i], floor) : floor;
      at_mouth[i] = 1;
    }
  }
}

// Free room half an edge of the level of detail away along every axis: no
// channel here, faces of the level of detail fit.
bool Deformer::in_the_open(const Vec3& p) const {
  const double r = 0.5 * lod_edge_length(o_, voxel_);
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) {
      Vec3 q = p;
      q[axis] += sign * r;
      if (cost_.image.is_blocked(q)) return false;
    }
  return true;
}

// The face area that follows the width of the room a new vertex is in or
// looks into (channel_width.h), between the finest local size and the level
// of detail's.
double Deformer::width_area(Mesh::VertexHandle v) const {
  const Vec3 normal = vertex_area_normal(mesh_, v);
  // Only a vertex that looks into free room ahead (the model's front in a
  // channel or a sheet): one made against a wall, at a mouth's rim say,
  // keeps the faces the mouth asked for, or the mouth is never entered.
  const Vec3 p = to_eigen(mesh_.point(v));
  if (!(normal.norm() > 0.0) ||
      cost_.image.is_blocked(p + ((o_.mode == Mode::grow ? 1.0 : -1.0) * voxel_ / normal.norm()) * normal))
    return 0.0;
  return face_area_for_room(p, normal);
}

// Widths are measured up to the one whose faces are the level of detail's.
ChannelWidthOptions Deformer::width_options() const {
  ChannelWidthOptions w;
  w.voxel = voxel_;
  w.cap = lod_edge_length(o_, voxel_) / w.edge_per_width;
  return w;
}

// The same for a point p of the model with (unnormalised) outward normal.
double Deformer::face_area_for_room(const Vec3& p, const Vec3& normal) const {
  const double coarse = o_.lod_face_area * voxel_ * voxel_;
  if (!(normal.norm() > 0.0)) return coarse;
  const ChannelWidthOptions w = width_options();
  const Vec3 ahead = (o_.mode == Mode::grow ? 1.0 : -1.0) * normal.normalized();
  const double finest = std::min(0.5, o_.lod_face_area) * voxel_ * voxel_;
  return area_for_width(room_width(cost_.image, p, ahead, w), w, finest, coarse);
}

// A vertex that stands against a wall: the blocked region starts within a
// voxel ahead of it and is still there three voxels ahead (not a noise
// speck, not the object's boundary seen from a voxel or two inside).
bool Deformer::at_wall(Mesh::VertexHandle v) const {
  Vec3 normal = Vec3::Zero();
  for (auto f : mesh_.vf_range(v)) normal += face_normal_[f.idx()];
  if (!(normal.norm() > 0.0)) return false;
  const Vec3 step = ((o_.mode == Mode::grow ? 1.0 : -1.0) * voxel_ / normal.norm()) * normal;
  const Vec3 p = to_eigen(mesh_.point(v));
  if (!cost_.image.is_blocked(p + 0.5 * step) && !cost_.image.is_blocked(p + step)) return false;
  for (const double d : {2.0, 2.5, 3.0})
    if (!cost_.image.is_blocked(p + d * step)) return false;
  return true;
}

// Beyond the paper (issue 14): the level of detail sets face sizes, not where
// the model may go. After a convergence, faces larger than the finest size
// behind which the image still shows free room (a channel's mouth narrower
// than the faces) ask for smaller faces around them, locally: their vertices'
// area limit drops to a quarter of the face, never below one voxel^2 (faces
// of about 1.5 voxels, enough for a channel two voxels wide). Returns the
// faces that asked.
std::size_t Deformer::refine_where_blocked(int cycle) {
  compute_face_normals();
  const double finest = std::min(0.5, o_.lod_face_area) * voxel_ * voxel_;
  std::vector<int> asking;
  // Refinement stops where it makes no progress: after two rounds in a row
  // after which no vertex moved more than a voxel (from where the round found
  // it, or where it was made), the model is as far in as local faces take it.
  if (local_rounds_ > 0) {
    bool progress = false;
    for (auto v : mesh_.vertices()) {
      const std::size_t i = static_cast<std::size_t>(v.idx());
      const Vec3& from = i < round_start_.size() ? round_start_[i] : stage_start_[i];
      progress = progress || (to_eigen(mesh_.point(v)) - from).norm() > voxel_;
    }
    idle_rounds_ = progress ? 0 : idle_rounds_ + 1;
    if (idle_rounds_ >= 2) return 0;
  }
  round_start_.resize(mesh_.n_vertices());
  for (auto v : mesh_.vertices()) round_start_[static_cast<std::size_t>(v.idx())] = to_eigen(mesh_.point(v));
  // Each face's tests read the mesh and the image only: in parallel, each
  // face's verdict written by its own iteration. The contact search, the
  // costliest, runs last and only for the faces that passed the others.
  // Only faces near what changed since the last round are tested again
  // (on the benchmark's cube every face was, in each of three rounds: a
  // seventh of its run).
  const std::size_t n_faces = mesh_.n_faces();
  const double coarse = o_.lod_face_area * voxel_ * voxel_;
  const ChannelWidthOptions w = width_options();
  std::vector<char> redo;
  faces_touched_since(verdicts_seen_, redo, 1);
  const std::size_t known = std::min(mouth_verdict_.size(), n_faces);  // faces beyond: new, tested
  mouth_verdict_.resize(n_faces, 0);
  floor_verdict_.resize(n_faces, finest);
  parallel_for(n_faces, threads_, [&](std::size_t i) {
    if (!redo[i] && i < known) return;
    mouth_verdict_[i] = 0;
    floor_verdict_[i] = finest;
    const Mesh::FaceHandle f(static_cast<int>(i));
    if (mesh_.has_face_status() && mesh_.status(f).deleted()) return;
    const double area = gdm::face_area(mesh_, f);
    thread_local std::vector<Vec3> free_points;
    if (!(area > kAskAboveFinest * finest)) return;
    // The face spans the mouth of a channel: its corners stand on the wall
    // around it, its middle sees into the channel.
    int walled = 0;
    for (auto v : mesh_.fv_range(f)) walled += at_wall(v) ? 1 : 0;
    if (walled < 2) return;
    // Refinement stops where the faces are as small as the room ahead asks
    // (channel_width.h): still blocked there, a finer face makes no progress.
    // (Measured last: the chords were a quarter of the CT series' run when
    // every free point of every face had them.)
    double room = -1.0;
    if (object_ahead(f, &free_points)) room = room_ahead(free_points);
    else if ((room = room_ahead_of_centre(f)) < 0.0) return;
    floor_verdict_[i] = area_for_width(room, w, finest, coarse);
    mouth_verdict_[i] = area > floor_verdict_[i];
  });
  std::vector<char> at_mouth = mouth_verdict_;
  std::vector<double> floor_area = floor_verdict_;
  ask_around_held_vertices(finest, at_mouth, floor_area);
  // Room ahead that the model itself fills (two fronts that met) is no channel.
  const std::vector<char> met = contact_faces(mesh_, 2.5 * voxel_, nullptr, threads_, &at_mouth);
  for (std::size_t i = 0; i < n_faces; ++i)
    if (at_mouth[i] && !met[i]) asking.push_back(static_cast<int>(i));
  // The model converged: only the region around the asking faces moves on
  // (the rest wakes up only if a move reaches it).
  if (!asking.empty()) std::fill(active_.begin(), active_.end(), 0);
  for (int i : asking) {
    const Mesh::FaceHandle f(i);
    const double target = std::max(floor_area[static_cast<std::size_t>(i)], 0.25 * gdm::face_area(mesh_, f));
    for (auto v : mesh_.fv_range(f)) {
      local_area_[v.idx()] = std::min(local_area_[v.idx()], target);
      activate_around(v);
      touch(v);  // its faces may be split now
    }
  }
  if (!asking.empty()) last_split_cycle_ = cycle;
  return asking.size();
}

bool Deformer::converged(int cycle) const {
  if (cycle - last_split_cycle_ < o_.convergence_window) return false;
  const int newest = *std::max_element(last_change_.begin(), last_change_.end());
  return cycle - newest >= o_.convergence_window;
}

bool Deformer::run_cycle(int cycle) {
  report_.cycle = cycle;
  compute_face_normals();
  std::vector<StepResult> steps;
  const std::vector<int> candidates = evaluate_active(steps);
  report_.evaluated = candidates.size();
  report_.moved = apply_moves(candidates, steps, cycle);
  report_.splits = resample(cycle);
  report_.vertices = mesh_.n_vertices();
  report_.faces = mesh_.n_faces();
  double sum = 0.0;
  for (double c : cost_value_) sum += std::isfinite(c) ? c : 0.0;
  report_.mean_cost = cost_value_.empty() ? 0.0 : sum / static_cast<double>(cost_value_.size());
  return !observer_ || observer_(report_);
}

std::size_t Deformer::count_border_vertices() const {
  std::size_t n = 0;
  for (auto v : mesh_.vertices())
    if (!input_.contains(to_eigen(mesh_.point(v)), 1.0)) ++n;
  return n;
}

// What only the deformation cycles read: the guard and the per-vertex and
// per-face state, freed before the fit and what follows build their own
// (issue 17's peak memory: on the T1 head at the defaults the peak came at
// the end, with the cycles' guard and state still held beside the fit's,
// the creases' and the quality pass's; after finish() sorts the mesh, no
// index into them would be valid anyway).
void Deformer::release_cycle_state() {
  if (guard_) rejected_earlier_stages_ += guard_->statistics().rejected_moves;
  guard_.reset();
  const auto release = [](auto& v) { std::decay_t<decltype(v)>().swap(v); };
  release(checkers_);
  release(step_);
  release(cost_value_);
  release(active_);
  release(settled_);
  release(refused_);
  release(retry_at_);
  release(refusal_);
  release(anchor_);
  release(stage_start_);
  release(last_change_);
  release(local_area_);
  release(round_start_);
  release(mouth_verdict_);
  release(floor_verdict_);
  release(face_normal_);
  release(touched_);
  release(face_flags_);
  release(edge_dirty_);
}

// Beyond the paper: the final fit onto the threshold crossing, and the
// error-driven level of detail (collapse where flat, split where the surface
// leaves the faces, fit again).
void Deformer::finish(int cycle, DeformResult& result) {
  const bool lod = o_.lod_tolerance > 0.0;
  const bool budget = o_.face_budget > 0;
  if (!o_.subvoxel_fit && !lod && !budget) return;
  Stopwatch clock;
  // The last stage's splits were appended; nothing per vertex is kept past
  // here, so the fit and what follows get a mesh in space order too.
  sort_spatially(mesh_, voxel_);
  FitOptions fit;
  fit.passes = o_.fit_passes;
  fit.max_distance = o_.fit_max_distance;
  fit.regularization = o_.fit_smoothing;
  fit.search = std::max(1.5, o_.fit_max_distance + 0.5);
  fit.normal_rings = o_.normal_rings;
  fit.prevent_self_intersection = o_.prevent_self_intersection;
  fit.threads = threads_;
  // The fit keeps what a vertex alone sees in proportion to the image noise.
  fit.noise = estimate_crossing_noise(mesh_, volume_, o_.threshold, std::max(1.5, 3.0 * o_.lod_tolerance) * voxel_, threads_);
  // A quiet image (its voxels' noise explains no more than the crossings'):
  // with curvature_correction the crossings are corrected for the trilinear
  // field's bias on curved parts (FitOptions::curvature_correction); on a
  // noisy one the correction was no gain (README, stop 58). The image's
  // noise is estimated only where something reads it.
  const double image_noise = !lod || o_.curvature_correction ? image_edge_noise() : 0.0;
  const bool quiet = !(image_noise > fit.noise);
  fit.curvature_correction = o_.curvature_correction && quiet;
  const FitOptions crossing_fit = fit;
  // The model's fit and the budget's last one step past the offsets
  // (kFitOverRelaxation); the level of detail's rounds and the budget's
  // subdivided fits keep the plain step (crossing_fit).
  fit.over_relaxation = kFitOverRelaxation;
  // Not (yet) with the level of detail: its collapses and splits are tuned
  // against the crossing estimate (the 25 degree bound's cost on the
  // branching tube at lod_tolerance 0.1 rises 0.016 -> 0.020 voxel with it).
  if (!lod && !quiet) use_image_noise(fit, image_noise);
  std::vector<Vec3> origin;  // where the deformation left each vertex (new ones: where created)
  if (o_.subvoxel_fit || budget) result.fit_moves += fit_to_threshold(mesh_, volume_, o_.threshold, fit, origin).moves;
  if (o_.subvoxel_fit && !budget) sharpen_edges(fit, result);
  if (budget) {
    // The subdivided fits keep the full step: their scale grows four times
    // per subdivision already (refine_for_budget); on the larger noise.
    FitOptions fine = crossing_fit;
    fine.noise = fit.noise;
    refine_for_budget(cycle, fine, origin, result);
    reduce_to_budget(fit, result);
  }
  clock.add_to(result.seconds.fit);
  if (!lod) return;
  const double tolerance = o_.lod_tolerance * voxel_;
  CollapseOptions collapse;
  collapse.tolerance = 0.5 * tolerance;  // hysteresis against the split criterion
  collapse.search = std::max(1.5 * voxel_, 3.0 * tolerance);
  collapse.min_angle = o_.lod_min_angle;
  // Faces are not split, nor kept, to follow image noise (error_lod.h).
  collapse.noise = estimate_crossing_noise(mesh_, volume_, o_.threshold, collapse.search, threads_);
  for (int round = 0; round < o_.lod_rounds; ++round) {
    const std::size_t c = collapse_flat_edges(mesh_, &volume_, o_.threshold, collapse);
    const std::size_t s = split_deviating_faces(mesh_, volume_, o_.threshold, tolerance, 0.5 * voxel_, cycle, collapse.noise);
    result.lod_collapses += c;
    result.lod_splits += s;
    result.fit_moves += fit_to_threshold(mesh_, volume_, o_.threshold, crossing_fit, origin).moves;
    if (c + s == 0) break;
  }
  mesh_.garbage_collection();
  mesh_.release_vertex_status();
  mesh_.release_edge_status();
  mesh_.release_halfedge_status();
  mesh_.release_face_status();
  clock.add_to(result.seconds.error_lod);
}

// What the voxels' noise makes of a crossing where the model is
// (estimate_edge_noise; the voxels of the model's box, so a crop around the
// object changes nothing).
double Deformer::image_edge_noise() const {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (auto v : mesh_.vertices()) {
    lo = lo.cwiseMin(to_eigen(mesh_.point(v)));
    hi = hi.cwiseMax(to_eigen(mesh_.point(v)));
  }
  const Vec3 margin = Vec3::Constant(2.0 * voxel_);
  return estimate_edge_noise(mesh_, volume_, estimate_voxel_noise(volume_, lo - margin, hi + margin), threads_);
}

// Beyond the paper (issue 16): the crossing estimate reads the noise off
// crossings a voxel apart, which interpolate the same voxels, so it falls
// short of the noise, the more so the noisier the image. Where what the
// voxels' noise makes of a crossing (estimate_edge_noise; the voxels of the
// model's box, so a crop around the object changes nothing) is larger, the
// fit takes that as its noise, with twice the smoothing's scale at half the
// step (a pull that reaches most vertices must be damped: every vertex
// moves at once). On a clean image the crossings' scatter (the faces'
// chords) stays the scale, as it was. Measured in the README (stop 46):
// five noisy phantoms at 3, 5 and 10 % of the contrast, two noise seeds, up
// to 24 % closer to the truth (ellipsoid on 1 x 1 x 2 mm voxels at 10 %:
// 0.0745 -> 0.0564 voxel), none farther; clean phantoms and the real scans
// of ../shared/data keep their models.
void Deformer::use_image_noise(FitOptions& fit, double edge) const {
  fit.noise = edge;
  fit.regularization = std::min(5.0, 2.0 * fit.regularization);
  fit.quadric_step = 0.5;
}

// Section 6's 1-to-4 resampling, undone when it made faces meet. The new
// vertices are rounded midpoints: exactly, the four new faces tile the old
// one, but where the guard let faces come within rounding of each other
// (vertices the model pressed together: rounded midpoints of nearly
// coincident ends are the same point) the new faces cross or fold onto each
// other. Measured on an MRI head at the defaults: 0 intersecting pairs before
// the refinement, 104 after, all in one spot where the first stage had
// gathered vertices (371 pairs within 1e-3 mm of each other, inside 4 mm).
// Returns whether the mesh was refined.
bool Deformer::subdivide_safely(int cycle) {
  if (!o_.prevent_self_intersection) {
    subdivide_all(mesh_, cycle);
    return true;
  }
  Mesh coarser = mesh_;
  subdivide_all(mesh_, cycle);
  if (self_intersecting_pairs(mesh_, threads_) == 0) return true;
  mesh_ = std::move(coarser);
  return false;
}

// Beyond the paper (issue 16): the face budget needs a fitted model with more
// faces than the budget to choose from. While it has fewer than
// kBudgetSourceFactor times the budget, every face becomes four (section 6's
// global resampling: the new triangles lie inside the old ones) and the fit
// puts the new vertices on the threshold surface (anchored where they were
// created), as long as the faces stay within max_faces.
void Deformer::refine_for_budget(int cycle, const FitOptions& fit, std::vector<Vec3>& origin, DeformResult& result) {
  while (static_cast<double>(mesh_.n_faces()) < kBudgetSourceFactor * static_cast<double>(o_.face_budget) &&
         4 * mesh_.n_faces() <= o_.max_faces) {
    if (!subdivide_safely(cycle)) break;
    ++result.budget_subdivisions;
    // Each subdivision quarters the area the fit's 2-ring quadric sees, so its
    // noise-adaptive smoothing grows four times (at most the catalogue's 5):
    // the finer fit keeps to the surface the coarser one saw through the
    // noise (measured, mean distance at 8,000 faces: noisy ellipsoid on
    // 0.5 x 0.5 x 2 mm voxels 0.078 against 0.094 voxel with the plain fit,
    // noisy sphere 0.021 against 0.026, noisy branching tube 0.043 against
    // 0.054; no effect without noise).
    FitOptions fine = fit;
    fine.regularization = std::min(5.0, fit.regularization * std::pow(4.0, static_cast<double>(result.budget_subdivisions)));
    // Anchored where the subdivision left each vertex, within what the
    // coarser faces can miss of a smooth surface (subdivision_fit_bounds):
    // impulse noise no longer dents the fine model (salt-and-pepper
    // ellipsoid of the study at 5, 10, 20 % of flying edges' faces: mean
    // 0.145, 0.092, 0.130 -> 0.093, 0.068, 0.066 voxel, p95 0.700, 0.490,
    // 0.853 -> 0.376, 0.298, 0.296; the Gaussian-noise phantoms within
    // 0.003 of before).
    origin.clear();
    fine.vertex_max_distance = subdivision_fit_bounds(mesh_, 1, kBudgetBoundFloor * voxel_);
    result.fit_moves += fit_to_threshold(mesh_, volume_, o_.threshold, fine, origin).moves;
  }
}

// The fitted model reduced to the budget by guarded collapses, least quadric
// error of the fitted surface first, each merged vertex placed where the
// planes it stands for meet best (face_budget.h; the floor of new angles is
// the triangle-quality bound, or lod_min_angle when that is off), then fitted
// again so that the larger faces lie across the threshold surface.
// Measured against keeping an end of the edge (a halfedge collapse): mean
// distance 0.091 against 0.110 voxel on the noisy C tube at 500 faces, 0.094
// against 0.102 on the clean branching tube at 552.
void Deformer::reduce_to_budget(const FitOptions& fit, DeformResult& result) {
  // Sharp edges on the fine model first: the quadrics then hold their planes
  // and the collapses keep vertices on them (the cube with a corner missing
  // at 5 % of marching cubes' faces: mean distance of its edges to the
  // model 0.345 -> 0.011 voxel); again after the last fit, which rounds them.
  sharpen_edges(fit, result);
  const TriangleLocator fine(triangles_of(mesh_));
  ReduceOptions r;
  r.threads = threads_;
  r.faces = o_.face_budget;
  r.min_angle = o_.min_angle > 0.0 ? o_.min_angle : o_.lod_min_angle;
  r.noise = fit.noise;
  result.budget_collapses += reduce_to_faces(mesh_, r).collapses;
  // Two candidates, each fitted: the reduced model as the collapses left it,
  // and with its faces evened out (even_out_faces); kept, the one nearer the
  // fine fitted model the collapses started from (its vertices and face
  // centroids, mean_distance): the surface the image gave with the noise
  // smoothed at the fine fit's scale. Evened faces sit closer on smooth,
  // evenly curved parts; on the real scans' surfaces the collapses' own
  // placement mostly does (README, stop 61).
  Mesh plain = mesh_;
  DeformResult plain_result = result;
  const std::size_t relax_moves = even_out_faces();
  fit_reduced(fit, result);
  const double evened = mean_distance(mesh_, fine, threads_);
  std::swap(mesh_, plain);
  fit_reduced(fit, plain_result);
  if (evened < mean_distance(mesh_, fine, threads_)) {
    std::swap(mesh_, plain);
    result.budget_relax_moves += relax_moves;
  } else {
    result = plain_result;
  }
}

// The reduced model's last fit (anchored where the reduction left the
// vertices), its creases sharpened again after it.
void Deformer::fit_reduced(const FitOptions& fit, DeformResult& result) {
  std::vector<Vec3> origin;
  result.fit_moves += fit_to_threshold(mesh_, volume_, o_.threshold, fit, origin).moves;
  sharpen_edges(fit, result);
}



// Beyond the paper (issue 16): the reduction leaves the faces where the
// error says, but their shapes as the collapses fell (the clean sphere of the
// study at 758 faces: areas spread by 25 %, the mean smallest angle 43
// degrees). A face's sagitta over a curved surface is its circumradius
// squared times the curvature over two, least for an equilateral triangle of
// its area, so even shapes sit closer at the same count. Edges flipped to
// Delaunay where their faces are within kBudgetFlipDihedral of flat, then
// every vertex off the creases relaxed along the surface (relax_tangentially,
// fraction kBudgetRelaxFraction, kBudgetRelaxPasses passes, at most a voxel
// a pass), each flip and move checked by the guard; the fit after this puts
// the vertices back onto the threshold surface.
std::size_t Deformer::even_out_faces() {
  const double max_move = voxel_;
  IntersectionGuard guard(mesh_, 2.0 * max_move, 1e-6 * voxel_ * voxel_);
  guard.rebuild();
  const FlipVeto veto = [&](Mesh::EdgeHandle edge, const Mesh::VertexHandle (&quad)[4]) {
    return !o_.prevent_self_intersection || guard.flip_is_safe(edge, quad);
  };
  flip_to_improve(mesh_, kBudgetFlipDihedral, veto);
  return relax_tangentially(mesh_, crease_vertices(mesh_, kBudgetCreaseDihedral), kBudgetRelaxFraction, max_move,
                            kBudgetRelaxPasses, [&] { if (o_.prevent_self_intersection) guard.rebuild(); },
                            [&](Mesh::VertexHandle v, const Vec3& q) {
                              return volume_.contains(q) && (!o_.prevent_self_intersection || guard.move_is_safe(v, q));
                            });
}

// Vertices onto the object's sharp edges and corners (creases.h), after a
// fit, with the fit's estimate of the crossings' noise.
void Deformer::sharpen_edges(const FitOptions& fit, DeformResult& result) {
  if (!o_.sharp_edges) return;
  CreaseOptions c;
  c.noise = std::max(0.0, fit.noise);
  c.generation = report_.cycle;
  c.prevent_self_intersection = o_.prevent_self_intersection;
  c.threads = threads_;
  const CreaseResult r = sharpen_creases(mesh_, volume_, o_.threshold, c);
  result.sharp_corners += r.corners;
  result.sharp_edge_moves += r.edge_moves;
  result.sharp_edge_splits += r.splits;
}

// After the triangle-quality pass (its splits add faces, its collapses remove
// them): a count that drifted above the budget by more than kBudgetSlack is
// collapsed back to it, keeping the quality bound (a new face stays above
// min_angle, or above the smallest angle around when that is lower); one that
// drifted below is brought back by splitting the longest edges of the largest
// faces at their midpoints (the new faces lie inside the old ones: the surface
// and the guarantees stay) where no new angle falls below that bound.
void Deformer::settle_budget(DeformResult& result) {
  if (o_.face_budget == 0) return;
  const double budget = static_cast<double>(o_.face_budget);
  const double bound = o_.min_angle > 0.0 ? o_.min_angle : o_.lod_min_angle;
  if (static_cast<double>(mesh_.n_faces()) > (1.0 + kBudgetSlack) * budget) {
    ReduceOptions r;
    r.threads = threads_;
    r.faces = o_.face_budget;
    r.min_angle = bound;
    r.keep_floor = true;
    result.budget_collapses += reduce_to_faces(mesh_, r).collapses;
    return;
  }
  for (int pass = 0; pass < 4 && static_cast<double>(mesh_.n_faces()) < (1.0 - kBudgetSlack) * budget; ++pass) {
    const auto corner = [&](Mesh::HalfedgeHandle h) { return to_eigen(mesh_.point(mesh_.to_vertex_handle(h))); };
    // Would splitting h at its midpoint keep the new angles of both faces at it?
    const auto split_keeps_angles = [&](Mesh::HalfedgeHandle h) {
      const Vec3 m = 0.5 * (corner(h) + corner(mesh_.opposite_halfedge_handle(h)));
      for (const auto side : {h, mesh_.opposite_halfedge_handle(h)}) {
        const Vec3 a = corner(mesh_.opposite_halfedge_handle(side)), b = corner(side);
        const Vec3 apex = corner(mesh_.next_halfedge_handle(side));
        const double floor = std::min(bound, triangle_min_angle(a, b, apex));
        if (triangle_min_angle(a, m, apex) < floor || triangle_min_angle(m, b, apex) < floor) return false;
      }
      return true;
    };
    // The largest faces first (ties by index), as many as the budget lacks.
    std::vector<std::pair<double, int>> by_area;
    for (auto f : mesh_.faces()) {
      by_area.emplace_back(-face_area_normal(mesh_, f).norm(), f.idx());
    }
    std::sort(by_area.begin(), by_area.end());
    const auto wanted = static_cast<std::size_t>(std::ceil(0.5 * (budget - static_cast<double>(mesh_.n_faces()))));
    std::vector<char> chosen(mesh_.n_faces(), 0);
    for (std::size_t i = 0; i < by_area.size() && i < wanted; ++i) chosen[static_cast<std::size_t>(by_area[i].second)] = 1;
    const std::size_t splits = split_longest_edges(mesh_, report_.cycle, [&](Mesh::FaceHandle f, Mesh::HalfedgeHandle h) {
      return chosen[static_cast<std::size_t>(f.idx())] && split_keeps_angles(h);
    });
    result.budget_splits += splits;
    if (splits == 0) break;
  }
}

// Beyond the paper: a shrinking model's faces shrink with it (a sphere
// shrunk to half its radius has faces a quarter of the level of detail), and
// a global refinement would quarter them again. So before each global
// refinement in shrink mode, edges shorter than half the level of detail's
// edge are collapsed, shortest first, each one checked like the error-driven
// level of detail's (link condition, no self-intersection, no new angle
// below lod_min_angle, new faces within half a voxel of the threshold
// surface). The stage's per-vertex state is rebuilt after the refinement.
std::size_t Deformer::coarsen_shrunk_faces() {
  CollapseOptions c;
  c.max_length = 0.5 * lod_edge_length(o_, voxel_);
  c.tolerance = 0.5 * voxel_;
  c.search = 1.5 * voxel_;
  c.min_angle = o_.lod_min_angle;
  return collapse_edges(c);
}

// One pass of collapse_flat_edges, the deleted elements collected.
std::size_t Deformer::collapse_edges(const CollapseOptions& c) {
  const std::size_t collapses = collapse_flat_edges(mesh_, &volume_, o_.threshold, c);  // one pass
  mesh_.garbage_collection();
  mesh_.release_vertex_status();
  mesh_.release_edge_status();
  mesh_.release_halfedge_status();
  mesh_.release_face_status();
  return collapses;
}

// Starts the stage again from the model as it is (after collapses, which
// renumber the vertices).
void Deformer::restart_stage(int cycle) {
  // Every per-vertex state starts again: growing, the vertices are
  // renumbered along space first (mesh_order.h), so the stage's cycles walk
  // the mesh and the volume in cache-sized pieces. Shrinking, the stages
  // keep the order the splits made: the exact topology of a double torus
  // shrunk onto ends 1 to 2 voxels inside the tube next to an opened hole
  // for some noise fields in either order (1 of 24 sorted, 2 of 24 not), the
  // tests' field among the former; not yet understood.
  if (o_.mode == Mode::grow) sort_spatially(mesh_, voxel_);
  step_.clear();
  cost_value_.clear();
  active_.clear();
  settled_.clear();
  refused_.clear();
  retry_at_.clear();
  refusal_.clear();
  anchor_.clear();
  stage_start_.clear();
  last_change_.clear();
  local_area_.clear();
  start_stage(cycle);
}

// Beyond the paper (issue 15): a shrinking surface loses area, and where
// it loses it faster than its faces can follow it folds over on itself. On
// the whole tooth, shrunk onto from outside, 180 such pleats in the concave
// skirt between the roots: two parts of the model two to a dozen face rings
// apart face each other across a sliver of background (contact_faces),
// flaps, needles and knots of sliver faces (find_pleats). Once a stage
// converges, the knots' and flaps' edges are collapsed, then the pleats'
// vertices and two rings around them move toward the centroid of their
// neighbours (a Laplacian smoothing, which unfolds a fold, each move checked
// by the guard), and the stage goes on, so the image pulls them back onto
// the object. Returns the collapses and the vertices smoothed (0: no pleat).
std::size_t Deformer::smooth_pleats(int cycle) {
  // Where it crumpled, its faces shrank to slivers a small fraction of a
  // voxel across, folded into knots that stand out of the surface and that
  // no smoothing move the guard allows unfolds: their edges go first (any
  // deviation; topology, intersections and orientation checked).
  CollapseOptions c;
  c.max_length = kPleatEdge * voxel_;
  c.min_angle = 0.0;
  c.max_normal_change = 180.0;
  // The searches run again only after collapses changed the mesh.
  PleatMasks found = find_pleats();
  std::vector<char> edges = edges_between(grow_by_rings(mesh_, found.all, 1));
  c.only_edges = &edges;
  std::size_t collapses = collapse_edges(c);
  if (collapses > 0) {
    restart_stage(cycle);
    found = find_pleats();
  }
  // Then the edges between the vertices of the flaps, up to the level of
  // detail's length: a spike of model standing out of the surface shrinks
  // to a point. (Not where two parts face each other across background: the
  // object may have a slit thinner than a voxel there, as where the double
  // torus's tubes merge in a V-groove.)
  edges = edges_between(found.flaps);
  c.max_length = lod_edge_length(o_, voxel_);
  // Only vertices standing in background go (the kept one may lie on the
  // object): a collapse of the vertices at a flap's foot cut into the object
  // (a dent 3.8 voxels deep into a root of the molar phantom).
  const std::vector<char> loose = in_background(found.flaps);
  c.removable = &loose;
  const std::size_t spikes = collapse_edges(c);
  if (spikes > 0) {
    restart_stage(cycle);
    found = find_pleats();
  }
  collapses += spikes;
  const std::vector<char> pleat = grow_by_rings(mesh_, found.all, kPleatRings);
  std::vector<Mesh::VertexHandle> vertices;
  for (auto v : mesh_.vertices())
    if (pleat[static_cast<std::size_t>(v.idx())]) vertices.push_back(v);
  if (vertices.empty()) return collapses;
  const double max_move = o_.optimizer.max_step * voxel_;  // the guard's margin
  relax_toward_neighbours(mesh_, vertices, 1.0, max_move, kPleatPasses,
                          [&] { if (o_.prevent_self_intersection) guard_->prepare_moves(); },
                          [&](Mesh::VertexHandle v, const Vec3& q) {
                            return !o_.prevent_self_intersection || guard_->move_is_safe(v, q);
                          });
  std::fill(active_.begin(), active_.end(), 0);
  for (auto v : vertices) {
    touch(v);
    anchor_[static_cast<std::size_t>(v.idx())] = to_eigen(mesh_.point(v));
    last_change_[static_cast<std::size_t>(v.idx())] = cycle;
    activate_around(v);
  }
  last_split_cycle_ = cycle;
  return collapses + vertices.size();
}

// The flagged vertices with background half a voxel behind them (inside
// the model): not on the object's surface.
std::vector<char> Deformer::in_background(const std::vector<char>& flagged) const {
  std::vector<char> loose(flagged.size(), 0);
  for (auto v : mesh_.vertices()) {
    if (!flagged[static_cast<std::size_t>(v.idx())]) continue;
    Vec3 normal = Vec3::Zero();
    for (auto f : mesh_.vf_range(v)) normal += face_normal_of(f);
    const Vec3 p = to_eigen(mesh_.point(v));
    const Vec3 behind = normal.norm() > 0.0 ? Vec3(p - 0.5 * voxel_ * normal.normalized()) : p;
    loose[static_cast<std::size_t>(v.idx())] = !cost_.image.is_blocked(p) && !cost_.image.is_blocked(behind);
  }
  return loose;
}

// Face f's unit normal and centroid, from the mesh as it is.
Vec3 Deformer::face_normal_of(Mesh::FaceHandle f) const {
  const Vec3 n = face_area_normal(mesh_, f);
  return n.norm() > 0.0 ? Vec3(n.normalized()) : Vec3::Zero();
}

Vec3 Deformer::face_centroid(Mesh::FaceHandle f) const { return to_eigen(mesh_.calc_face_centroid(f)); }

// The edges (by index) whose two ends are flagged.
std::vector<char> Deformer::edges_between(const std::vector<char>& flagged) const {
  std::vector<char> edges(mesh_.n_edges(), 0);
  for (auto e : mesh_.edges()) {
    const auto h = mesh_.halfedge_handle(e, 0);
    edges[static_cast<std::size_t>(e.idx())] = flagged[static_cast<std::size_t>(mesh_.from_vertex_handle(h).idx())] &&
                                               flagged[static_cast<std::size_t>(mesh_.to_vertex_handle(h).idx())];
  }
  return edges;
}

// The vertices of the pleats. `flaps`: where the model is thinner than a
// voxel with background inside it (a thin part of the object itself is no
// pleat), and the needles below. `all`: those and where the model faces
// another part of itself across a sliver of background (contact_faces).
Deformer::PleatMasks Deformer::find_pleats() const {
  std::vector<Vec3> middles;
  const std::vector<char> met = contact_faces(mesh_, voxel_, nullptr, threads_);
  const std::vector<char> thin = thin_faces(mesh_, voxel_, &middles, threads_);
  PleatMasks found{std::vector<char>(mesh_.n_vertices(), 0), std::vector<char>(mesh_.n_vertices(), 0)};
  std::vector<char>& pleat = found.flaps;
  for (auto f : mesh_.faces()) {
    const std::size_t i = static_cast<std::size_t>(f.idx());
    const bool flap = thin[i] && !cost_.image.is_blocked(middles[i]);
    for (auto v : mesh_.fv_range(f)) {
      if (flap) pleat[static_cast<std::size_t>(v.idx())] = 1;
      if (flap || met[i]) found.all[static_cast<std::size_t>(v.idx())] = 1;
    }
  }
  // A needle or fin a few faces wide: its sides are neighbours on the mesh,
  // which thin_faces skips, and they meet at an edge folded back on itself
  // (a convex dihedral angle below 60 degrees) standing in background.
  for (auto e : mesh_.edges()) {
    if (mesh_.is_boundary(e)) continue;
    const auto h = mesh_.halfedge_handle(e, 0);
    const Mesh::FaceHandle f = mesh_.face_handle(h), g = mesh_.opposite_face_handle(h);
    const Vec3 nf = face_normal_of(f), ng = face_normal_of(g);
    if (!(nf.dot(ng) < -0.5)) continue;
    const Vec3 cf = face_centroid(f), cg = face_centroid(g);
    if ((cg - cf).dot(nf) >= 0.0 || cost_.image.is_blocked(0.5 * (cf + cg))) continue;  // a groove, or object
    for (auto v : {mesh_.from_vertex_handle(h), mesh_.to_vertex_handle(h)})
      pleat[static_cast<std::size_t>(v.idx())] = found.all[static_cast<std::size_t>(v.idx())] = 1;
  }
  return found;
}

// A vertex the gap gate holds: just outside it, the model's volume is
// closed while the caller's is free (an opening narrower than the gap).
bool Deformer::held_by_gate(Mesh::VertexHandle v) const {
  const Vec3 p = to_eigen(mesh_.point(v));
  const Vec3 normal = vertex_area_normal(mesh_, v);
  if (!(normal.norm() > 0.0)) return false;
  const double sense = o_.mode == Mode::grow ? 1.0 : -1.0;
  const Vec3 ahead = p + (sense * 0.75 * voxel_ / normal.norm()) * normal;
  if (!input_.contains(ahead)) return false;
  return cost_.image.is_blocked(ahead) && !input_image_.is_blocked(ahead);
}

// Beyond the paper: a bridged opening is capped by a membrane, not by the
// ball's bulge. The vertices the gate holds move toward the centroid of their
// neighbours (a discrete minimal surface spanning the opening's rim, which
// stays where the image put it), in vertex order, each move checked by the
// guard and kept out of the caller's blocked region. Returns the vertices of
// the caps.
std::size_t Deformer::relax_bridges() {
  std::vector<Mesh::VertexHandle> held;
  for (auto v : mesh_.vertices())
    if (held_by_gate(v)) held.push_back(v);
  if (held.empty()) return 0;
  const double max_move = 0.5 * o_.optimizer.max_step * voxel_;
  IntersectionGuard guard(mesh_, 2.0 * max_move, 1e-6 * voxel_ * voxel_);
  relax_toward_neighbours(mesh_, held, 1.0, max_move, 50, [&] { if (o_.prevent_self_intersection) guard.rebuild(); },
                          [&](Mesh::VertexHandle v, const Vec3& q) {
                            return !input_image_.is_blocked(q) && (!o_.prevent_self_intersection || guard.move_is_safe(v, q));
                          });
  return held.size();
}

// Beyond the paper (issue 16): the last geometric step, so that no later
// step undoes it (only the float snap follows, moving vertices by a float
// spacing). A flip or a collapse moves the surface by at most a tenth of a
// voxel (a quarter, then half a voxel for the faces still below the bound
// after that); relaxed vertices stay on the surface the fit found.
void Deformer::improve_quality(DeformResult& result) {
  if (!(o_.min_angle > 0.0)) return;
  QualityOptions q;
  q.min_angle = o_.min_angle;
  q.max_error = kQualityMaxError * voxel_;
  q.prevent_self_intersection = o_.prevent_self_intersection;
  q.obstacle = o_.obstacle;
  // Needles narrower than a voxel and a half at their base (spikes, the
  // image does not resolve them): removed.
  q.spike_radius = o_.obstacle ? 0.0 : kSpikeRadius * voxel_;
  // Crumples where the model's fronts met (fins, flaps folded onto each
  // other): their folded edges collapsed where that leaves fewer folds.
  q.unfold = !o_.obstacle;
  q.threads = threads_;
  const QualityResult r = improve_triangle_quality(mesh_, q);
  mesh_.release_vertex_status();
  mesh_.release_edge_status();
  mesh_.release_halfedge_status();
  mesh_.release_face_status();
  result.quality_flips = r.flips;
  result.quality_splits = r.splits;
  result.quality_collapses = r.collapses;
  result.quality_moves = r.moves;
  result.quality_spikes = r.spikes;
  result.quality_unfolds = r.unfolds;
  result.faces_below_min_angle = r.faces_below;
}

DeformResult Deformer::run(int first_cycle) {
  DeformResult result;
  generation_property(mesh_);
  start_stage(first_cycle);
  int cycle = first_cycle;
  Stopwatch clock;
  // The cycles' time goes to the stage they belong to.
  const auto stage_clock = [&]() -> double& {
    return report_.stage == 0 ? result.seconds.growth : result.seconds.refined_stages;
  };
  while (true) {
    if (cycle >= o_.max_cycles) {
      result.reason = StopReason::max_cycles;
      break;
    }
    ++cycle;
    const bool go_on = run_cycle(cycle);
    clock.add_to(stage_clock());
    if (!go_on) {
      result.reason = StopReason::cancelled;
      break;
    }
    if (mesh_.n_faces() > o_.max_faces) {
      result.reason = StopReason::face_limit;
      break;
    }
    if (o_.stop_at_border && count_border_vertices() > 0) {
      result.reason = StopReason::border;
      break;
    }
    const bool done = converged(cycle);
    clock.add_to(stage_clock());
    if (!done) continue;
    // A shrinking model's pleats, after each stage's convergence.
    if (o_.mode == Mode::shrink && !o_.obstacle && pleat_rounds_ < kPleatRounds) {
      ++pleat_rounds_;
      const std::size_t smoothed = smooth_pleats(cycle);
      result.pleat_vertices += smoothed;
      if (smoothed > 0) continue;
      pleat_rounds_ = kPleatRounds;
    }
    // Local refinement where faces are too large to enter what lies ahead,
    // once the last stage converged (the model is then as fine as the level
    // of detail asks everywhere else; refined vertices may travel).
    std::size_t asked = 0;
    if (o_.refine_channels && report_.stage == o_.global_refinements && local_rounds_ < 16 &&
        (asked = refine_where_blocked(cycle)) > 0) {
      ++local_rounds_;
      result.channel_faces += asked;
      continue;
    }
    if (report_.stage >= o_.global_refinements) {
      result.reason = StopReason::converged;
      break;
    }
    // Section 6: after a first convergence, refine globally and converge again.
    // (Not with an obstacle: a collapse is not checked against it.)
    if (o_.mode == Mode::shrink && !o_.obstacle) result.lod_collapses += coarsen_shrunk_faces();
    const bool refined = subdivide_safely(cycle);
    clock.add_to(result.seconds.refinement);
    if (!refined) {
      result.reason = StopReason::converged;
      break;
    }
    ++report_.stage;
    pleat_rounds_ = 0;
    restart_stage(cycle);
    clock.add_to(result.seconds.refinement);
  }
  clock.add_to(stage_clock());
  if (result.reason == StopReason::converged || result.reason == StopReason::max_cycles) {
    release_cycle_state();
    finish(cycle, result);
    clock = Stopwatch();
    if (&volume_ != &input_) result.bridge_vertices = relax_bridges();
    clock.add_to(result.seconds.fit);
    improve_quality(result);
    settle_budget(result);
    clock.add_to(result.seconds.quality);
  }
  if (o_.float_exact_output && result.reason != StopReason::cancelled) result.float_refused = snap_to_float(mesh_, threads_).refused;
  clock.add_to(result.seconds.float_snap);
  result.cycles = cycle;
  result.global_refinements = report_.stage;
  result.rejected_moves = rejected_earlier_stages_ + (guard_ ? guard_->statistics().rejected_moves : 0);
  result.flips = flips_;
  result.channel_rounds = local_rounds_;
  result.border_vertices = count_border_vertices();
  result.face_budget = o_.face_budget;
  result.faces = mesh_.n_faces();
  return result;
}

}  // namespace

namespace {

// The seed's vertices and centroid: where the gap gate and the cavity fill
// find the object the model grows in.
std::vector<Vec3> seed_points(const Mesh& mesh) {
  std::vector<Vec3> points;
  Vec3 centroid = Vec3::Zero();
  for (auto v : mesh.vertices()) {
    points.push_back(to_eigen(mesh.point(v)));
    centroid += points.back();
  }
  points.push_back(centroid / static_cast<double>(std::max<std::size_t>(1, mesh.n_vertices())));
  return points;
}

// The gap gate (passage.h) seeded by the model's vertices and centroid.
PassageGate gate_for(const Mesh& mesh, const Volume& volume, const DeformOptions& o) {
  if (!gap_gate_active(o.gap, volume)) return {};
  const std::vector<Vec3> points = seed_points(mesh);
  PassageOptions passage;
  passage.gap = o.gap;
  passage.threshold = o.threshold;
  passage.threads = o.threads;
  // Table 1's duality: growing, the background is blocked; shrinking, the object.
  passage.blocked_is_brighter = (o.polarity == Polarity::object_brighter) == (o.mode == Mode::shrink);
  return gate_passages(volume, passage, points);
}

// The cavity fill (cavities.h) of the volume the model grows in, seeded by
// the model's vertices and centroid.
CavityFill cavities_for(const Mesh& mesh, const Volume& volume, const DeformOptions& o) {
  if (!o.fill_cavities) return {};
  CavityOptions c;
  c.seed_points = seed_points(mesh);
  c.every_component = o.mode == Mode::shrink;  // a shrinking seed lies round the object (cavities.h)
  c.threshold = o.threshold;
  c.background_is_brighter = o.polarity == Polarity::object_darker;
  c.gap = o.gap;
  c.opening = o.cavity_opening;
  c.cap_handles = o.cap_handles;
  c.handle_repair = o.handle_repair;
  c.threads = o.threads;
  // A membrane the model's faces enter as fast as the handle's tube: at
  // least 3.5 voxels each side (cavities.cpp), more for faces larger than the
  // default level of detail's.
  c.membrane = std::max(3.5 * volume.voxel_size(), 0.75 * lod_edge_length(o, volume.voxel_size()));
  return fill_cavities(volume, c);
}

}  // namespace

// Faces finer than this grow crumpled: with eq. 3's extent floored where T
// lets D move the model (topology_extent_floor, 9.1 voxels), little holds a
// vertex of a small face to its neighbours while it advances (a ball's model
// came out with 1.5 times the sphere's area at 1 voxel^2, 3.5 times at 0.5).
// A finer level of detail therefore grows at 4^k times the area and is then
// refined k more times (section 6's 1-to-4 resampling keeps a converged
// surface smooth): the same band of face sizes in the end. Not from a
// coarser level: growing at 16 voxel^2 for 4 bridged the tooth's canals
// (pulp volume -15 % of the flood fill instead of -3.5 %).
constexpr double kGrowthLodFaceArea = 2.0;

DeformOptions growth_schedule(const DeformOptions& options) {
  DeformOptions o = options;
  if (!o.lod_topology_extent) return o;
  while (o.lod_face_area < kGrowthLodFaceArea) {
    o.lod_face_area *= 4.0;
    ++o.global_refinements;
  }
  return o;
}

// Multi-resolution growth (issue 17). A front crosses about a voxel a
// cycle, and most of the cycles of a model grown from a small seed are that
// crossing, with every face of the growing model in each. The model first
// grows in the volume reduced 2x per level (reduce_by_two: a coarse voxel is
// on the object's side only when its whole block is, so the coarse model
// stays inside the object), where the front crosses twice the distance per
// cycle with a quarter of the faces; each level's converged model is the
// seed of the next finer level, and at full resolution the vertices travel
// the last voxel or two. Section 7: the seed's size and shape change only
// the time; the full-resolution run (its cycles, refinements, fit, every
// guard) is the same as from any seed inside the object. Growing only (a
// shrinking seed lies round the object), without an obstacle.
constexpr int kCoarseMinExtent = 16;  // a coarser level keeps at least this many voxels on every axis
constexpr int kCoarseQuietCycles = 3;
constexpr double kCoarseQuietShare = 0.01;

struct CoarseStart {
  int levels = 0;       // coarser levels the model grew at
  int cycles = 0;       // their cycles, all levels together
  bool cancelled = false;
};

std::vector<Volume> coarser_levels(const Volume& grow_in, const DeformOptions& o) {
  std::vector<Volume> levels;
  if (o.mode != Mode::grow || o.obstacle) return levels;
  const bool keep_minimum = o.polarity == Polarity::object_brighter;
  const Volume* finer = &grow_in;
  while (static_cast<int>(levels.size()) < o.coarse_levels) {
    Volume coarse = reduce_by_two(*finer, keep_minimum);
    if (coarse.dims() == finer->dims()) break;
    if (*std::min_element(coarse.dims().begin(), coarse.dims().end()) < kCoarseMinExtent) break;
    levels.push_back(std::move(coarse));
    finer = &levels.back();
  }
  return levels;
}

// Grows `mesh` at the coarser levels, coarsest first. A level is used only
// when every seed vertex lies inside its grid on the object's side; a level
// whose run does not converge is dropped (the model goes back to what it was
// before it). Returns what was done; the mesh is the seed of the next level.
CoarseStart grow_coarse_first(Mesh& mesh, const Volume& grow_in, const Volume& input, const DeformOptions& o,
                              const DeformObserver& observer, double& seconds) {
  CoarseStart start;
  std::vector<Volume> levels = coarser_levels(grow_in, o);
  if (levels.empty()) return start;
  Stopwatch clock;
  DeformOptions c = o;
  c.intensity_scale = effective_intensity_scale(o, input);  // the same unit of I at every level
  c.global_refinements = 0;
  c.refine_channels = false;
  c.subvoxel_fit = false;
  c.lod_tolerance = 0.0;
  c.face_budget = 0;
  c.min_angle = 0.0;
  c.float_exact_output = false;
  c.gap = 0.0;               // the gate is in grow_in already
  c.fill_cavities = false;   // so are the filled cavities and the handles' membranes
  c.cap_handles = false;
  c.topology = Topology::solid;
  c.stop_at_border = false;
  for (int level = static_cast<int>(levels.size()) - 1; level >= 0; --level) {
    const Volume& coarse = levels[static_cast<std::size_t>(level)];
    // The first level used must hold the whole seed on the object's side (a
    // seed in a part thinner than the level's blocks waits for a finer one);
    // a coarser level's model is inside the object up to its blocks' half
    // width, and a vertex left outside turns back (section 5's local flip).
    bool inside = true;
    if (start.levels == 0) {
      const ImageEvent image(1.0, coarse, o.threshold, o.polarity, o.mode, 1.0);
      for (auto v : mesh.vertices()) {
        const Vec3 p = to_eigen(mesh.point(v));
        if (!coarse.contains(p) || image.is_blocked(p)) {
          inside = false;
          break;
        }
      }
    }
    if (!inside) continue;
    c.max_cycles = o.max_cycles - start.cycles;
    if (c.max_cycles < 1) break;
    Mesh before = mesh;
    // A coarse level ends when its front has stopped: kCoarseQuietCycles
    // cycles in a row in which under kCoarseQuietShare of the vertices moved.
    // Its tail (a few vertices creeping into what its blocks barely show) is
    // the finer level's work.
    int quiet = 0;
    bool front_stopped = false;
    const DeformObserver level_observer = [&](const CycleReport& report) {
      if (observer && !observer(report)) return false;
      quiet = static_cast<double>(report.moved) < kCoarseQuietShare * static_cast<double>(report.vertices) ? quiet + 1 : 0;
      front_stopped = quiet >= kCoarseQuietCycles;
      return !front_stopped;
    };
    DeformResult r = Deformer(mesh, coarse, coarse, c, level_observer).run(start.cycles);
    if (r.reason == StopReason::cancelled && !front_stopped) {
      start.cancelled = true;
      break;
    }
    if (front_stopped) r.reason = StopReason::converged;
    // Section 6's 1-to-4 resampling: the finer level starts at its own
    // level of detail (faces a quarter the area) instead of splitting there
    // cycle by cycle. Undone if the new faces meet (Deformer::subdivide_safely).
    if (r.reason == StopReason::converged) {
      Mesh coarser = mesh;
      subdivide_all(mesh, r.cycles);
      if (self_intersecting_pairs(mesh, o.threads) != 0) mesh = std::move(coarser);
    }
    if (r.reason != StopReason::converged) {
      mesh = std::move(before);
      continue;
    }
    start.cycles = r.cycles;
    ++start.levels;
  }
  seconds = clock.seconds();
  return start;
}

// The voxel seed (voxel_seed.h) of the object the model grows in, found
// from the seed's vertices and centroid; when it applies, `mesh` becomes it
// and `run` starts at the level of detail's final face size (the requested
// one over 4 per global refinement) without refinements: the seed's faces
// already have it.
VoxelSeed voxel_seed_for(Mesh& mesh, const Volume& grow_in, const DeformOptions& requested, DeformOptions& run) {
  if (!requested.voxel_seed || !voxel_seed_applies(requested)) return {};
  VoxelSeedOptions v;
  v.threshold = requested.threshold;
  v.object_brighter = requested.polarity == Polarity::object_brighter;
  v.face_area = requested.lod_face_area / std::pow(4.0, requested.global_refinements);
  v.threads = requested.threads;
  VoxelSeed seed = make_voxel_seed(grow_in, v, seed_points(mesh));
  if (!seed.applied) return seed;
  mesh = std::move(seed.mesh);
  run.lod_face_area = v.face_area;
  run.global_refinements = 0;
  return seed;
}

bool voxel_seed_applies(const DeformOptions& options) { return options.mode == Mode::grow && !options.obstacle; }

CavityFill cavity_fill_for(const Mesh& seed, const Volume& volume, const DeformOptions& requested) {
  validate(requested, volume);
  const DeformOptions options = growth_schedule(requested);
  const PassageGate gate = gate_for(seed, volume, options);
  return cavities_for(seed, gate.applied ? gate.volume : volume, options);
}

DeformResult deform(Mesh& mesh, const Volume& volume, const DeformOptions& requested, const DeformObserver& observer) {
  validate(requested, volume);
  const DeformOptions options = growth_schedule(requested);
  Deformer(mesh, volume, volume, options, observer).check_seed();
  Stopwatch clock;
  const PassageGate gate = gate_for(mesh, volume, options);
  const double gate_seconds = clock.seconds();
  clock = Stopwatch();
  const CavityFill fill = cavities_for(mesh, gate.applied ? gate.volume : volume, options);
  const double fill_seconds = clock.seconds();
  const Volume& gated = gate.applied ? gate.volume : volume;
  const Volume& grow_in = fill.applied ? fill.volume : gated;
  clock = Stopwatch();
  DeformOptions run_options = options;
  const VoxelSeed voxel = voxel_seed_for(mesh, grow_in, requested, run_options);
  const double voxel_seconds = clock.seconds();
  double coarse_seconds = 0.0;
  const CoarseStart coarse =
      voxel.applied ? CoarseStart{} : grow_coarse_first(mesh, grow_in, volume, options, observer, coarse_seconds);
  DeformResult result;
  if (coarse.cancelled)
    result.reason = StopReason::cancelled;
  else
    result = Deformer(mesh, voxel.applied && voxel.grow_in.voxel_count() > 0 ? voxel.grow_in : grow_in, volume,
                      run_options, observer)
                 .run(coarse.cycles);
  result.voxel_seed = voxel.applied;
  result.voxel_seed_voxels = voxel.voxels;
  result.voxel_seed_background = voxel.background_voxels;
  result.voxel_seed_left_out = voxel.left_out;
  result.voxel_seed_surface_faces = voxel.surface_faces;
  result.seconds.voxel_seed = voxel_seconds;
  result.coarse_levels = coarse.levels;
  result.coarse_cycles = coarse.cycles;
  result.handle_repair = options.handle_repair;
  result.seconds.growth += coarse_seconds;
  result.seconds.gap_gate = gate_seconds;
  result.seconds.cavity_fill = fill_seconds;
  result.gap_closed_voxels = gate.closed_voxels;
  result.gap_reachable_voxels = gate.reachable_voxels;
  if (fill.opening > 0.0 && options.fill_cavities)
    result.cavity_opening_width = fill.opening;
  for (const Cavity& c : fill.cavities) {  // largest first
    if (c.voxels < kCavitySpeckVoxels) {
      ++result.cavity_specks;
      continue;
    }
    result.filled_regions.push_back(c);
    if (c.kind == CavityKind::handle || c.kind == CavityKind::cut) {
      ++result.handles;
      result.handle_voxels += c.voxels;
      continue;
    }
    if (result.cavities++ == 0) result.largest_cavity_centre = c.centre;
    if (c.kind == CavityKind::narrow_openings) ++result.cavities_behind_openings;
    result.cavity_voxels += c.voxels;
  }
  result.cavity_volume = static_cast<double>(result.cavity_voxels) * volume.spacing().prod();
  clock = Stopwatch();
  add_cavity_components(mesh, gated, fill, requested, result, observer);  // topology exact (topology.h)
  clock.add_to(result.seconds.topology);
  return result;
}

}  // namespace gdm
