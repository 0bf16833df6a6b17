#include "gdm/option_catalogue.h"

#include <cmath>
#include <sstream>
#include <type_traits>
#include <utility>

#include "gdm/errors.h"
#include "gdm/text.h"

namespace gdm {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string number(double v) { return format_number(v); }

// Builders of the catalogue's rows. A row: name, group, unit, help, then the range.
using Entry = OptionEntry<DeformOptions>;

Entry row(std::string name, std::string group, std::string unit, std::string help) {
  Entry e;
  e.name = std::move(name);
  e.group = std::move(group);
  e.unit = std::move(unit);
  e.help = std::move(help);
  return e;
}

// `field` is a lambda returning a reference to the option's field.
template <typename Field>
Entry bind(Entry e, OptionType type, double lo, bool lo_open, double hi, bool hi_open, Field field) {
  using T = std::remove_reference_t<decltype(field(std::declval<DeformOptions&>()))>;
  e.type = type;
  e.lo = lo;
  e.lo_open = lo_open;
  e.hi = hi;
  e.hi_open = hi_open;
  e.get = [field](const DeformOptions& o) {
    const T& v = field(const_cast<DeformOptions&>(o));
    if constexpr (std::is_enum_v<T>) return static_cast<double>(static_cast<int>(v));
    else return static_cast<double>(v);
  };
  // The row as far as the range goes (special values and aliases, added
  // later, concern real options only): what an integer setter checks against.
  const OptionInfo info = e;
  e.set = [field, info](DeformOptions& o, double v) {
    if constexpr (std::is_same_v<T, bool>) field(o) = v != 0.0;
    else if constexpr (std::is_enum_v<T> || std::is_integral_v<T>) field(o) = integer_field_value<T>(info, v);
    else field(o) = static_cast<T>(v);
  };
  return e;
}

template <typename Field>
Entry real(Entry e, double lo, bool lo_open, double hi, bool hi_open, Field field) {
  return bind(std::move(e), OptionType::real, lo, lo_open, hi, hi_open, field);
}

template <typename Field>
Entry integer(Entry e, double lo, double hi, Field field) {
  return bind(std::move(e), OptionType::integer, lo, false, hi, false, field);
}

template <typename Field>
Entry boolean(Entry e, Field field) {
  return bind(std::move(e), OptionType::boolean, 0.0, false, 1.0, false, field);
}

template <typename Field>
Entry choice(Entry e, std::vector<std::string> names, Field field) {
  const double hi = static_cast<double>(names.size() - 1);
  e.choices = std::move(names);
  return bind(std::move(e), OptionType::choice, 0.0, false, hi, false, field);
}

Entry special(Entry e, double value, std::string text) {
  e.special.push_back(value);
  e.special_text = std::move(text);
  return e;
}

Entry alias(Entry e, std::string old) {
  e.alias = std::move(old);
  return e;
}

std::vector<Entry> make_catalogue() {
  const char* model = "Model (paper's Table 2 and sections 3 to 6)";
  const char* guard = "Guarantees and limits";
  const char* fit = "After convergence (beyond the paper)";
  constexpr bool open = true, closed = false;
  const double int_max = static_cast<double>(std::numeric_limits<int>::max());
#define F(field) [](DeformOptions & o) -> auto& { return field; }
  // One line per option: its name, group, unit and help, then its kind and range.
  return {
      choice(row("mode", model, "", "grow from inside the object or shrink from around it (section 5)"), {"grow", "shrink"}, F(o.mode)),
      choice(row("polarity", model, "", "the object is brighter or darker than the threshold"), {"bright", "dark"}, F(o.polarity)),
      real(row("a0", model, "", "deformation gain a0 of eq. 1 (Table 2)"), 0.0, open, kInf, open, F(o.a0)),
      real(row("a1", model, "", "image event gain a1 of eq. 1 (Table 2)"), 0.0, closed, kInf, open, F(o.a1)),
      real(row("a2", model, "", "topology gain a2 of eq. 1 (Table 2)"), 0.0, closed, kInf, open, F(o.a2)),
      real(row("intensity_scale", model, "image units", "intensity per unit of I (0 = 1% of the value range)"), 0.0, closed, kInf, open, F(o.intensity_scale)),
      real(row("reach", model, "voxels", "distance of the normal-tracking target (section 3.1.1)"), 0.0, open, 10.0, closed, F(o.reach)),
      integer(row("normal_rings", model, "", "rings of faces averaged into a vertex normal (section 7)"), 1, 4, F(o.normal_rings)),
      boolean(row("local_flip", model, "", "flip the sense of vertices that crossed the boundary (section 5)"), F(o.local_flip)),
      real(row("min_step", model, "voxels", "smallest optimizer step (section 3.2)"), 0.0, open, 10.0, closed, F(o.optimizer.min_step)),
      real(row("max_step", model, "voxels", "largest optimizer step (section 3.2)"), 0.0, open, 10.0, closed, F(o.optimizer.max_step)),
      alias(integer(row("max_step_reductions", model, "", "step halvings tried before a vertex stays put"), 0, 16, F(o.optimizer.max_step_reductions)), "step-reductions"),
      real(row("gradient_step", model, "voxels", "central-difference half width of the gradient"), 0.0, open, 1.0, closed, F(o.optimizer.gradient_step)),
      alias(real(row("lod_face_area", model, "voxels^2", "level of detail: faces larger than this are split (Table 2)"), 0.5, closed, kInf, open, F(o.lod_face_area)), "lod"),
      boolean(row("lod_topology_extent", model, "", "floor eq. 3's extent at the level of detail"), F(o.lod_topology_extent)),
      special(real(row("max_topology_ratio", model, "", "hard limit on eq. 3's ratio, against leaks through narrow gaps"), 0.0, open, kInf, open, F(o.max_topology_ratio)), kInf, "inf = off"),
      special(real(row("refinement_travel", model, "level-of-detail edge lengths", "after a global refinement a vertex moves at most this far from where the stage found it"), 0.0, open, kInf, open, F(o.refinement_travel)), kInf, "inf = off"),
      special(real(row("gap", model, "mm", "gap size G: the model passes only where a ball of diameter G fits, so openings in the object's wall narrower than G are bridged and channels wider than G are followed, whatever the level of detail"), 0.0, open, 1e9, closed, F(o.gap)), 0.0, "0 (two voxels: no gate)"),
      boolean(row("fill_cavities", model, "", "fill the background the outside cannot reach before the model deforms (a hollow shell's inside; chambers joined to the outside only through openings narrower than cavity_opening): the model is the object's outer surface, without a double-walled sheet around each cavity; shrinking, the object is every voxel on its side of T inside the seed's box"), F(o.fill_cavities)),
      special(real(row("cavity_opening", model, "mm", "with fill_cavities, a pocket of background joined to the outside only through openings narrower than a ball of this diameter, and wider inside, is filled (a pulp chamber behind canals one or two voxels wide); grooves and slits stay open; a larger gap wins"), 0.0, open, 1e9, closed, F(o.cavity_opening)), 0.0, "0 (three voxels; up to two voxels: any path keeps a pocket open)"),
      choice(row("topology", model, "", "grow or shrink: solid = one closed genus-0 outer surface (cavities filled, handles capped); exact = the data's topology: each enclosed cavity also its own closed component with normals into the cavity, each handle a tube through its hole (the genus goes up); needs fill_cavities"), {"solid", "exact"}, F(o.topology)),
      boolean(row("cap_handles", model, "", "with fill_cavities, cap each handle of the object by a membrane across its hole at the narrowest place (or cut it, handle_repair), so the genus-0 model does not meet itself across the handle; reported as a handle"), F(o.cap_handles)),
      choice(row("handle_repair", model, "", "with cap_handles, growing, topology solid: membrane = background across each handle's hole given to the object where the hole is narrowest (the model closes the hole); cut = object across the handle's body given to the background where the body is thinnest (the model follows the hole and parts at the cut: closer where holes are wide and bodies thin, as a skull's openings)"), {"membrane", "cut"}, F(o.handle_repair)),
      boolean(row("refine_channels", model, "", "once converged, refine locally where faces are too large to enter a channel the image shows (the level of detail then sets face sizes, the gap where the model goes: canals are followed at any level of detail); off = the face size decides where the model goes, as in the paper"), F(o.refine_channels)),
      boolean(row("voxel_seed", model, "", "growing: start from the surface of the object's voxels, taken from the seed's deepest voxel as a well-composed topological ball and reduced to the level of detail's faces, instead of growing from the seed: no seams where fronts would meet in a thin shell (a scalp), no cycles crossing the object; the seed only says where the object is; off = grow from the seed, as in the paper"), F(o.voxel_seed)),
      integer(row("coarse_levels", model, "levels", "multi-resolution growth: the model first grows in the volume reduced 2x per level (a coarse voxel belongs to the object only where its whole block does), coarsest first, each level's model the seed of the next; at full resolution the vertices travel the last voxel or two. Growing only; 0 = off"), 0, 4, F(o.coarse_levels)),
      alias(integer(row("global_refinements", model, "", "global 1-to-4 resamplings, each after a convergence (section 6)"), 0, 4, F(o.global_refinements)), "refinements"),
      integer(row("max_cycles", model, "cycles", "hard limit on deformation cycles, all stages"), 1, int_max, F(o.max_cycles)),
      alias(real(row("convergence_tolerance", model, "voxels", "a vertex counts as moving beyond this"), 0.0, open, kInf, open, F(o.convergence_tolerance)), "tolerance"),
      alias(integer(row("convergence_window", model, "cycles", "converged when nothing moved for this many cycles"), 1, int_max, F(o.convergence_window)), "window"),
      alias(boolean(row("prevent_self_intersection", guard, "", "veto moves and flips that would self-intersect"), F(o.prevent_self_intersection)), "self-intersection-guard"),
      boolean(row("improve_triangles", model, "", "Delaunay edge flips on nearly flat regions"), F(o.improve_triangles)),
      alias(real(row("flip_max_dihedral", model, "degrees", "only flip where faces are this close to flat"), 0.0, closed, 90.0, open, F(o.flip_max_dihedral)), "flip-dihedral"),
      integer(row("threads", guard, "", "worker threads (0 = all cores); the result does not depend on it"), 0, 1024, F(o.threads)),
      integer(row("max_faces", guard, "faces", "stop when the model grows past this many faces"), 20, 1e12, F(o.max_faces)),
      boolean(row("subvoxel_fit", fit, "", "after convergence, move every vertex onto the threshold crossing of the trilinear field"), F(o.subvoxel_fit)),
      integer(row("fit_passes", fit, "", "sweeps of the sub-voxel fit"), 1, 20, F(o.fit_passes)),
      real(row("fit_max_distance", fit, "voxels", "a vertex moves at most this far in the fit"), 0.0, open, 4.0, closed, F(o.fit_max_distance)),
      real(row("fit_smoothing", fit, "", "the fit draws a vertex toward the quadric over its 2-ring where it stands within this many image-noise levels of it (smooths noise, keeps edges); 0 = off"), 0.0, closed, 5.0, closed, F(o.fit_smoothing)),
      boolean(row("curvature_correction", fit, "", "the fit's crossings corrected for the trilinear interpolation's bias on curved surfaces (a convex part's crossing lies up to a quarter of its curvature, in voxels, inside), with the model's curvature where its 3-ring is a quadric; quiet images only (noisy ones: no effect)"), F(o.curvature_correction)),
      boolean(row("sharp_edges", fit, "", "after the fit, vertices onto the object's sharp edges and corners: where the faces around a vertex lie in two or three flat planes that the data bends between within 1.5 voxels, the vertex moves to where they meet and edges crossing the line are split on it (a box's edges and corners kept, not rounded); smooth bends and noisy data are left as they are"), F(o.sharp_edges)),
      special(real(row("lod_tolerance", fit, "voxels", "error-driven level of detail: at most this deviation of a face from the threshold surface; splits where the surface leaves the faces, collapses where flat"), 0.01, closed, 10.0, closed, F(o.lod_tolerance)), 0.0, "0 (off)"),
      real(row("lod_min_angle", fit, "degrees", "collapses of the error-driven level of detail keep every angle above this"), 0.0, closed, 60.0, open, F(o.lod_min_angle)),
      integer(row("lod_rounds", fit, "rounds", "collapse / split / fit rounds of the error-driven level of detail"), 1, 50, F(o.lod_rounds)),
      alias(special(integer(row("face_budget", fit, "faces", "face budget: the final model gets about this many faces (within 5 %), fitted at a finer level of detail and reduced by guarded collapses, least error of the fitted surface first, then fitted again, its faces evened out along the surface first where that lies nearer the finer fitted model; at most max_faces; excludes lod_tolerance"), 20, 1e9, F(o.face_budget)), 0.0, "0 (off)"), "faces"),
      real(row("min_angle", fit, "degrees", "triangle quality: the last step improves every face with an angle below this (flips, cap splits, short-edge collapses, relaxation on the surface; best effort, the report gives the smallest angle); 0 = off"), 0.0, closed, 30.0, closed, F(o.min_angle)),
      alias(boolean(row("float_exact_output", guard, "", "end with every vertex on a float point, checked by the guard (float outputs stay free of self-intersections)"), F(o.float_exact_output)), "float-exact"),
  };
#undef F
}

}  // namespace

bool accepts(const OptionInfo& o, double v) {
  if (std::isnan(v)) return false;
  for (const double s : o.special)
    if (v == s) return true;
  if (o.type == OptionType::integer && v != std::floor(v)) return false;
  const bool above = o.lo_open ? v > o.lo : v >= o.lo;
  const bool below = o.hi_open ? v < o.hi : v <= o.hi;
  return above && below;
}

std::string range_text(const OptionInfo& o) {
  if (o.type == OptionType::boolean) return "on or off";
  if (o.type == OptionType::choice) {
    std::string s;
    for (std::size_t i = 0; i < o.choices.size(); ++i)
      s += (i == 0 ? "" : i + 1 == o.choices.size() ? " or " : ", ") + o.choices[i];
    return s;
  }
  std::string interval;
  if (std::isinf(o.hi))
    interval = (o.lo_open ? "> " : ">= ") + number(o.lo);
  else
    interval = std::string("in ") + (o.lo_open ? "(" : "[") + number(o.lo) + ", " + number(o.hi) + (o.hi_open ? ")" : "]");
  if (o.special_text.empty()) return interval;
  // "0 (off) or in [0.01, 10]"; "> 0 (inf = off)"
  if (o.special_text.find('=') != std::string::npos) return interval + " (" + o.special_text + ")";
  return o.special_text + " or " + interval;
}

std::string value_text(const OptionInfo& o, double v) {
  if (o.type == OptionType::boolean) return v != 0.0 ? "on" : "off";
  if (o.type == OptionType::choice) {
    // No cast before the range check: NaN or 1e300 has no int (found by fuzz_pipeline).
    if (v >= 0.0 && v < static_cast<double>(o.choices.size())) return o.choices[static_cast<std::size_t>(v)];
    return number(v);
  }
  return number(v);
}

void check_option(const OptionInfo& o, double v) {
  if (!accepts(o, v)) throw InvalidOption(o.name, o.name + " must be " + range_text(o) + ", got " + value_text(o, v));
}

const std::vector<OptionEntry<DeformOptions>>& deform_option_catalogue() {
  static const std::vector<Entry> catalogue = make_catalogue();
  return catalogue;
}

}  // namespace gdm
