// The deformation driver: cycles of vertex moves and resampling until the
// model converges (paper sections 3 to 6), with the guarantees beyond the
// paper (no self-intersection, deterministic multithreading).
#pragma once

#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "gdm/cavities.h"
#include "gdm/cost_terms.h"
#include "gdm/obstacle.h"
#include "gdm/mesh.h"
#include "gdm/optimizer.h"
#include "gdm/topology.h"
#include "gdm/volume.h"

namespace gdm {

struct DeformOptions {
  Mode mode = Mode::grow;                         // grow from inside or shrink from outside (section 5)
  Polarity polarity = Polarity::object_brighter;  // which side of the threshold is the object
  double threshold = std::numeric_limits<double>::quiet_NaN();  // T of eq. 2; required
  double a0 = 1.0;                   // deformation gain (Table 2)
  double a1 = 1.0;                   // image event gain (Table 2)
  double a2 = 5.0;                   // topology gain (Table 2)
  double intensity_scale = 0.0;      // intensity per unit of I; 0 = 1% of the value range
  double reach = 1.0;                // distance of the normal-tracking target, voxels
  int normal_rings = 2;              // rings of faces averaged into a vertex normal (section 7)
  bool local_flip = true;            // flip the deformation sense of misplaced vertices (section 5)
  OptimizerOptions optimizer;        // step range and reductions (section 3.2)
  double lod_face_area = 10.0;       // split faces larger than this, voxel^2 (Table 2); below 2 the model grows
                                     // at 4^k times it and is refined k more times (deform(): same density)
  bool lod_topology_extent = true;   // floor eq. 3's extent at the level of detail (see TopologyTerm)
  double max_topology_ratio = 0.5;   // hard limit on eq. 3's ratio against leaks (see TopologyTerm); inf = off
  double refinement_travel = 0.5;    // after a global refinement a vertex moves at most this many
                                     // level-of-detail edge lengths from where the stage found it
  int global_refinements = 1;        // 1-to-4 resamplings, each after a convergence (section 6)
  double gap = 0.0;                  // G, mm: the model passes only where a ball of diameter G fits and
                                     // rolls from the seed (passage.h): openings narrower than G are
                                     // bridged, channels wider are followed; 0 (or up to two voxels) =
                                     // no gate, every channel two voxels wide is open
  bool fill_cavities = true;         // background the outside cannot reach (a hollow shell's inside;
                                     // chambers joined to the outside only through openings narrower
                                     // than cavity_opening) is given to the object first (cavities.h):
                                     // the model is the outer surface, with no double-walled sheet
                                     // around the cavity. Shrinking, the object is every voxel on its
                                     // side of T inside the seed's box (CavityOptions::every_component)
  double cavity_opening = 0.0;       // W, mm: with fill_cavities, a pocket of background the outside
                                     // reaches only through openings narrower than a ball of diameter W
                                     // (and wider inside) is filled: the tooth's pulp behind canals one
                                     // or two voxels wide; 0 = three voxels; up to two voxels = any path
                                     // of voxels keeps a pocket open (issue 15); a larger gap wins
  bool cap_handles = true;           // with fill_cavities, remove each handle before the model grows
                                     // (cavities.h): a genus-0 model of a torus without two fronts
                                     // meeting across its tube; reported as a handle
  HandleRepair handle_repair = HandleRepair::membrane;  // membrane: across each handle's hole at its
                                     // narrowest place (the hole closed); cut: across the handle's body at
                                     // its thinnest place (the hole followed, the model parts at the cut;
                                     // growing, topology solid)
  Topology topology = Topology::solid;  // grow or shrink: solid = one genus-0 outer surface (cavities filled, handles
                                        // capped); exact = the data's topology: each enclosed cavity also its
                                        // own closed component with normals into the cavity, each handle's
                                        // cap opened into a tube through the hole (genus up; topology.h);
                                        // needs fill_cavities
  bool refine_channels = true;       // once the last stage converged, refine locally where faces are too
                                     // large to enter a channel the image shows (so the level of detail
                                     // sets face sizes, the gap where the model goes; inside, faces follow
                                     // the room's width, channel_width.h): the tooth's canals at the
                                     // defaults (issue 14); off = the face size decides, as in the paper
  int coarse_levels = 0;             // multi-resolution growth, levels in [0, 4]: the model first grows in the
                                     // volume reduced 2x per level (a coarse voxel is object only where
                                     // its whole block is), coarsest first, each level's model subdivided
                                     // 1-to-4 as the seed of the next finer one; at full resolution the
                                     // vertices travel the last voxel or two (issue 17). Growing only;
                                     // a level needs 16 voxels per axis; 0 = off
  bool voxel_seed = false;           // growing: the model starts from the surface of the object's voxels,
                                     // grown from the seed's deepest voxel as a well-composed topological
                                     // ball (voxel_seed.h) and reduced to the level of detail's faces,
                                     // instead of growing from the seed: no front meets another inside
                                     // the object (no seams where the object is a thin shell), and no
                                     // cycles cross the object. The seed only says where the object is;
                                     // no coarse levels; off = grown from the seed, as in the paper
  int max_cycles = 2000;             // hard limit on deformation cycles, all stages together
  double convergence_tolerance = 0.5;  // a vertex counts as moving beyond this, voxels
  int convergence_window = 5;        // converged when nothing moved for this many cycles
  bool prevent_self_intersection = true;  // veto moves and flips that would self-intersect
  bool improve_triangles = true;     // Delaunay edge flips on nearly flat regions
  double flip_max_dihedral = 20.0;   // only flip where faces are this close to flat, degrees
  int threads = 0;                   // worker threads; 0 = all cores; results do not depend on it
  std::size_t max_faces = 2000000;   // stop when the model grows past this many faces
  bool stop_at_border = false;       // stop as soon as a vertex comes within a voxel of the volume's
                                     // border (StopReason::border: a leak, said within a cycle of the
                                     // first contact instead of after converging outside the object)

  // Beyond the paper: the final fit and the error-driven level of detail, run
  // once after the last convergence (see surface_fit.h and error_lod.h).
  bool subvoxel_fit = true;          // move every vertex onto the threshold crossing of the trilinear field
  int fit_passes = 8;                // sweeps of the fit (normals re-estimated each sweep; stops early at
                                     // a fixed point)
  double fit_max_distance = 1.0;     // a vertex moves at most this far in the fit, voxels (0, 4]
  double fit_smoothing = 0.5;        // noise-adaptive smoothing of the fit, in [0, 5] (0 = off): a vertex
                                     // within this many noise levels of the quadric over its 2-ring is
                                     // drawn toward it (FitOptions::regularization)
  bool curvature_correction = true;  // the fit's crossings corrected for the trilinear field's bias on
                                     // curved parts, on quiet images where the model's 3-ring is a
                                     // quadric (FitOptions::curvature_correction; README, stops 58, 59)
  bool sharp_edges = true;           // after the fit, vertices onto the object's sharp edges and corners
                                     // where the faces around them lie in two or three planes that meet
                                     // within 1.5 voxels of the data (creases.h): splits add vertices
                                     // on the edges; smooth bends and noise too strong to tell them
                                     // apart change nothing
  double lod_tolerance = 0.0;        // error-driven level of detail: largest deviation of a face from
                                     // the threshold surface, voxels (smallest spacing); 0 = off. It
                                     // fits the vertices it changes even when subvoxel_fit is off
  double lod_min_angle = 15.0;       // collapses keep every new angle above this (or the old smallest), degrees
  int lod_rounds = 6;                // collapse / split / fit rounds of the error-driven level of detail
  const Obstacle* obstacle = nullptr;  // triangles no move or flip may touch (obstacle.h), e.g. a
                                       // shrink-wrap's input; not owned; needs the fit and the
                                       // error-driven level of detail off
  std::size_t face_budget = 0;       // the final model's faces, about (within 5 %); 0 = off (the level of
                                     // detail decides). The converged model is subdivided 1-to-4 and fitted
                                     // until it has 3.5 times N faces, then edges are collapsed, least
                                     // quadric error of the fitted surface first, the faces evened out along
                                     // the surface (flips, tangential relaxation off the creases) and the
                                     // vertices fitted again (face_budget.h); needs lod_tolerance 0 and no
                                     // obstacle; fits
                                     // even when subvoxel_fit is off
  double min_angle = 10.0;           // triangle quality, degrees in [0, 30] (0 = off): the last geometric
                                     // step improves every face with a smaller angle by guarded flips,
                                     // cap splits, short-edge collapses and tangential relaxation on the
                                     // model's surface (triangle_quality.h); best effort, the faces left
                                     // below are counted in DeformResult::faces_below_min_angle
  bool float_exact_output = true;    // end with every vertex on a float-representable point, each move
                                     // checked by the guard (float_snap.h): float outputs (STL, MeshLab,
                                     // itk::Mesh<float>) keep the no-self-intersection guarantee
};

// Called once per cycle.
struct CycleReport {
  int cycle = 0;                // 1-based
  int stage = 0;                // global refinements done so far
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t evaluated = 0;    // vertices whose cost was evaluated (the active set)
  std::size_t moved = 0;        // vertices that moved this cycle
  std::size_t splits = 0;       // edges split by the local resampling
  double mean_cost = 0.0;       // mean vertex cost after the cycle
};

// Returns false to cancel the run.
using DeformObserver = std::function<bool(const CycleReport&)>;

enum class StopReason { converged, max_cycles, face_limit, cancelled, border };

// Wall time of each step of a run, seconds (for reports and profiling; never
// part of a result's geometry).
struct StageSeconds {
  double gap_gate = 0.0;        // the gap gate's passage flood (passage.h)
  double voxel_seed = 0.0;      // the voxel seed: ball, surface and reduction (voxel_seed.h)
  double cavity_fill = 0.0;     // the cavity fill and handle caps (cavities.h)
  double growth = 0.0;          // the cycles of stage 0 (the first convergence)
  double refinement = 0.0;      // the global 1-to-4 refinements and their checks (section 6)
  double refined_stages = 0.0;  // the cycles after the first global refinement
  double fit = 0.0;             // the sub-voxel fit (and the face budget's fits and reduction)
  double error_lod = 0.0;       // the error-driven level of detail's rounds
  double quality = 0.0;         // the triangle-quality pass (and settling the face budget)
  double float_snap = 0.0;      // the float-exact snap
  double topology = 0.0;        // topology exact: the cavity components and opened handles
  double total() const {
    return gap_gate + voxel_seed + cavity_fill + growth + refinement + refined_stages + fit + error_lod + quality + float_snap +
           topology;
  }
};
std::string to_string(StopReason reason);

struct DeformResult {
  StopReason reason = StopReason::converged;
  int cycles = 0;                 // all levels together (coarse_cycles of them at coarser levels)
  int coarse_levels = 0;          // coarser levels the model grew at first (DeformOptions::coarse_levels)
  int coarse_cycles = 0;          // their cycles
  bool voxel_seed = false;        // the model started from the object's voxels (DeformOptions::voxel_seed)
  std::size_t voxel_seed_voxels = 0;      // the ball's voxels
  std::size_t voxel_seed_background = 0;  // of them, background voxels (slits, well-composedness)
  std::size_t voxel_seed_left_out = 0;    // object voxels next to it it could not take
  std::size_t voxel_seed_surface_faces = 0;  // faces of its surface before the reduction
  int global_refinements = 0;     // performed
  std::size_t rejected_moves = 0; // moves vetoed by the self-intersection guard
  std::size_t flips = 0;          // edge flips performed
  std::size_t border_vertices = 0;  // vertices within one voxel of the volume's border (a leak)
  std::size_t fit_moves = 0;      // vertex moves of the sub-voxel fit
  std::size_t lod_splits = 0;     // edges split by the error-driven level of detail
  std::size_t lod_collapses = 0;  // edges collapsed by the error-driven level of detail (and, shrinking,
                                  // before each global refinement: Deformer::coarsen_shrunk_faces)
  std::size_t gap_closed_voxels = 0;     // free voxels no ball of the gap size reaches from the seed (0: no gate)
  std::size_t gap_reachable_voxels = 0;  // free voxels it reaches (0: no gate)
  std::size_t bridge_vertices = 0;       // vertices of the caps over bridged openings
  int channel_rounds = 0;                // rounds of local refinement into channels (refine_channels)
  std::size_t channel_faces = 0;         // faces that asked for it, all rounds together
  std::size_t pleat_vertices = 0;        // shrinking: edges collapsed and vertices smoothed where the model folded over on itself
  std::size_t cavities = 0;              // enclosed regions of background filled before growing
                                         // (fill_cavities), of at least kCavitySpeckVoxels voxels
  std::size_t cavity_voxels = 0;         // their voxels
  double cavity_volume = 0.0;            // their volume, mm^3
  Vec3 largest_cavity_centre = Vec3::Zero();  // centroid of the largest, mm
  std::size_t cavity_specks = 0;         // smaller regions (specks of noise, voxel-sized handles of a rough
                                         // surface), filled too
  std::size_t cavities_behind_openings = 0;  // of `cavities`, those the outside reaches only through
                                             // openings narrower than cavity_opening_width
  double cavity_opening_width = 0.0;     // that width W, mm (0: no fill)
  std::size_t handles = 0;               // handles capped by a membrane across the hole (cap_handles), of at
                                         // least kCavitySpeckVoxels voxels
  std::size_t handle_voxels = 0;         // the membranes' (or cuts') voxels
  HandleRepair handle_repair = HandleRepair::membrane;  // how the handles were removed
  Topology topology = Topology::solid;   // the topology the model was built with
  std::size_t handles_opened = 0;        // exact: of `handles`, caps replaced by a tube through the hole
                                         // (each raises the genus by one); the others stay caps
  std::size_t cavity_components = 0;     // exact: enclosed cavities added as closed inward components
  std::size_t cavity_component_faces = 0;  // their faces
  std::size_t cavities_not_modelled = 0;   // exact: enclosed cavities left filled (too thin for a seed, their
                                           // model failed, or it would have met the outer model)
  std::vector<Cavity> filled_regions;    // every cavity and membrane counted above (kind, voxels, centre,
                                         // openings), largest first
  std::size_t quality_flips = 0;      // edge flips of the triangle-quality pass
  std::size_t quality_splits = 0;     // cap edges split by it
  std::size_t quality_collapses = 0;  // short edges collapsed by it
  std::size_t quality_moves = 0;      // vertex moves of its relaxation (and its slides along edges)
  std::size_t quality_spikes = 0;     // of its collapses: needles narrower than 1.5 voxels removed
  std::size_t quality_unfolds = 0;    // of its collapses: edges folded beyond 160 degrees (mesh_checks.h)
  std::size_t faces_below_min_angle = 0;  // faces left with an angle below min_angle (0 when it is off)
  std::size_t sharp_corners = 0;      // vertices moved onto a corner of the object (sharp_edges)
  std::size_t sharp_edge_moves = 0;   // vertices moved onto one of its sharp edges (corners not counted)
  std::size_t sharp_edge_splits = 0;  // edges split where they cross a sharp edge (two faces each)
  std::size_t face_budget = 0;          // faces requested (DeformOptions::face_budget; 0 = off)
  std::size_t faces = 0;                // faces of the final model
  std::size_t budget_subdivisions = 0;  // 1-to-4 subdivisions (each followed by a fit) to exceed the budget
  std::size_t budget_collapses = 0;     // edges collapsed to meet it
  std::size_t budget_relax_moves = 0;   // moves evening out the reduced model's faces along its surface
  std::size_t budget_splits = 0;        // edges split to meet it again after the triangle-quality pass
  std::size_t float_refused = 0;  // vertices float_exact_output could not move safely (0 in practice)
  StageSeconds seconds;           // where the time went
};

// What the gap gate did, for logs: "gap: 1,234 free voxels beyond openings or
// channels narrower than the gap closed (12,345 reachable); caps over the
// bridged openings: 60 vertices". Empty when no gate was built.
std::string gap_summary(const DeformResult& result);

// What the voxel seed did, for logs: "voxel seed: 400698 voxels (331 of them
// background: slits narrower than two voxels, or taken to keep it
// well-composed; 0 object voxels next to it left out), its surface's 105152
// faces reduced to the level of detail before the model ran". Empty when it
// was not used.
std::string voxel_seed_summary(const DeformResult& result);

// What the face budget did, for logs: "face budget: 1500 faces requested,
// 1498 obtained (1 subdivision, 2562 collapses)". Empty when it was off.
std::string budget_summary(const DeformResult& result);

// The cavity fill deform() makes before a model grows from `seed` with
// `options` (cavities.h; on the volume as the gap gate leaves it when a gap
// is set): its regions, and the volume with them filled (`applied` false:
// nothing filled, or fill_cavities off). For tools that measure a model
// against what it fills on purpose, such as the benchmark study.
CavityFill cavity_fill_for(const Mesh& seed, const Volume& volume, const DeformOptions& options);

// What the cavity fill did, for logs: "cavities: 2 enclosed regions of
// background filled (1,234 voxels, 1234 mm^3; the largest around (12.5, 40,
// 8) mm): the model is the object's outer surface", with the pockets filled
// behind narrow openings and where their openings are. Empty when none.
std::string cavity_summary(const DeformResult& result);

// What the handle caps are, for logs: "handles: 1 capped by a membrane
// across its hole (the solid topology keeps the model genus 0): at (x, y, z)
// mm, the hole 12 mm across there, 420 voxels". Empty when none.
std::string handle_summary(const DeformResult& result);

// What the exact topology did, for logs: "topology exact: 1 enclosed cavity
// as its own closed component, normals into the cavity (1280 faces); 1 of 1
// handle(s) opened into a tube through the hole (genus +1)". Empty for solid.
std::string topology_summary(const DeformResult& result);

// Whether DeformOptions::voxel_seed applies with these options: growing,
// without an obstacle (the front ends' hint to start from the voxels asks it too).
bool voxel_seed_applies(const DeformOptions& options);

// Checks the options against the volume; throws InvalidOption or InvalidVolume.
void validate(const DeformOptions& options, const Volume& volume);

// Deforms `mesh` (a closed 2-manifold seed inside the volume) until it fits the
// object. Throws InvalidOption, InvalidVolume or InvalidSeed on bad input; the
// mesh is then left untouched. Vertices carry their generation ("v:generation").
DeformResult deform(Mesh& mesh, const Volume& volume, const DeformOptions& options,
                    const DeformObserver& observer = {});

}  // namespace gdm
