#include "cli_options.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "cli_errors.h"
#include "json_writer.h"

namespace gdm_cli {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t");
  const auto b = s.find_last_not_of(" \t");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// A setter/getter pair for one option kind.
struct Binding {
  std::function<void(Options&, const std::string&)> set;
  std::function<std::string(const Options&)> get;
};

template <typename T>
using Accessor = T& (*)(Options&);

std::string range_text(double lo, double hi) {
  std::ostringstream s;
  if (std::isinf(hi)) s << ">= " << lo;
  else s << "in [" << lo << ", " << hi << "]";
  return s.str();
}

Binding real(Accessor<double> field, double lo, double hi) {
  return {[=](Options& o, const std::string& v) {
            const double x = parse_real("", v);
            if (!(x >= lo && x <= hi)) throw UsageError("must be " + range_text(lo, hi) + ", got " + v);
            field(o) = x;
          },
          [=](const Options& o) { return json_number(field(const_cast<Options&>(o))); }};
}

// A real in an interval whose ends may be open: (lo, hi], [lo, hi), ...
Binding real_interval(Accessor<double> field, double lo, bool lo_open, double hi, bool hi_open) {
  std::ostringstream range;
  range << "in " << (lo_open ? "(" : "[") << lo << ", " << hi << (hi_open ? ")" : "]");
  const std::string text = range.str();
  return {[=](Options& o, const std::string& v) {
            const double x = parse_real("", v);
            const bool above = lo_open ? x > lo : x >= lo;
            const bool below = hi_open ? x < hi : x <= hi;
            if (!(above && below)) throw UsageError("must be " + text + ", got " + v);
            field(o) = x;
          },
          [=](const Options& o) { return json_number(field(const_cast<Options&>(o))); }};
}

// A positive real where inf turns the limit off (rendered "inf" in the report,
// which the parser reads back).
Binding positive_or_inf(Accessor<double> field) {
  return {[=](Options& o, const std::string& v) {
            const double x = parse_real("", v);
            if (!(x > 0.0)) throw UsageError("must be > 0 (inf = off), got " + v);
            field(o) = x;
          },
          [=](const Options& o) {
            const double x = field(const_cast<Options&>(o));
            return std::isinf(x) ? json_string("inf") : json_number(x);
          }};
}

// The error-driven level of detail's tolerance: 0 (off) or in [0.01, 10] voxels.
Binding lod_tolerance() {
  return {[](Options& o, const std::string& v) {
            const double x = parse_real("", v);
            if (!(x == 0.0 || (x >= 0.01 && x <= 10.0)))
              throw UsageError("must be 0 (off) or in [0.01, 10] voxels, got " + v);
            o.deform.lod_tolerance = x;
          },
          [](const Options& o) { return json_number(o.deform.lod_tolerance); }};
}

Binding integer(Accessor<int> field, long lo, long hi) {
  return {[=](Options& o, const std::string& v) {
            const long x = parse_integer("", v);
            if (x < lo || x > hi) throw UsageError("must be " + range_text(lo, hi) + ", got " + v);
            field(o) = static_cast<int>(x);
          },
          [=](const Options& o) { return json_number(field(const_cast<Options&>(o))); }};
}

Binding count(Accessor<std::size_t> field, long lo) {
  return {[=](Options& o, const std::string& v) {
            const long x = parse_integer("", v);
            if (x < lo) throw UsageError("must be >= " + std::to_string(lo) + ", got " + v);
            field(o) = static_cast<std::size_t>(x);
          },
          [=](const Options& o) { return json_number(field(const_cast<Options&>(o))); }};
}

Binding on_off(Accessor<bool> field) {
  return {[=](Options& o, const std::string& v) {
            if (v == "on" || v == "yes" || v == "true" || v == "1") field(o) = true;
            else if (v == "off" || v == "no" || v == "false" || v == "0") field(o) = false;
            else throw UsageError("must be on or off, got " + v);
          },
          [=](const Options& o) { return json_bool(field(const_cast<Options&>(o))); }};
}

Binding flag(Accessor<bool> field) {
  return {[=](Options& o, const std::string&) { field(o) = true; },
          [=](const Options& o) { return json_bool(field(const_cast<Options&>(o))); }};
}

Binding text(Accessor<std::string> field) {
  return {[=](Options& o, const std::string& v) {
            if (v.empty()) throw UsageError("needs a non-empty value");
            field(o) = v;
          },
          [=](const Options& o) {
            const std::string& s = field(const_cast<Options&>(o));
            return s.empty() ? std::string("null") : json_string(s);
          }};
}

// The seed: "auto" or x,y,z in mm.
Binding seed_point() {
  return {[](Options& o, const std::string& v) {
            if (trim(v) == "auto") {
              o.seed.kind = SeedKind::automatic;
              return;
            }
            const auto p = parse_list("", v, 3);
            o.seed.kind = SeedKind::point;
            o.seed.point = {p[0], p[1], p[2]};
          },
          [](const Options& o) -> std::string {
            switch (o.seed.kind) {
              case SeedKind::automatic: return json_string("auto");
              case SeedKind::point: return json_array(o.seed.point);
              default: return "null";
            }
          }};
}

Binding seed_index() {
  return {[](Options& o, const std::string& v) {
            const auto p = parse_list("", v, 3);
            for (const double x : p)
              if (x != std::floor(x)) throw UsageError("needs integer voxel indices, got " + v);
            o.seed.kind = SeedKind::index;
            o.seed.index = {static_cast<long>(p[0]), static_cast<long>(p[1]), static_cast<long>(p[2])};
          },
          [](const Options& o) -> std::string {
            if (o.seed.kind != SeedKind::index) return "null";
            return "[" + std::to_string(o.seed.index[0]) + ", " + std::to_string(o.seed.index[1]) + ", " +
                   std::to_string(o.seed.index[2]) + "]";
          }};
}

Binding seed_mesh() {
  return {[](Options& o, const std::string& v) {
            if (v.empty()) throw UsageError("needs a file name");
            o.seed.kind = SeedKind::mesh;
            o.seed.mesh = v;
          },
          [](const Options& o) {
            return o.seed.kind == SeedKind::mesh ? json_string(o.seed.mesh) : std::string("null");
          }};
}

Binding roi() {
  return {[](Options& o, const std::string& v) {
            const auto p = parse_list("", v, 6);
            for (int d = 0; d < 6; ++d) {
              if (p[d] != std::floor(p[d]) || p[d] < 0) throw UsageError("needs non-negative integer indices, got " + v);
              o.roi[d] = static_cast<long>(p[d]);
            }
            for (int d = 0; d < 3; ++d)
              if (o.roi[d + 3] < o.roi[d]) throw UsageError("needs i0 <= i1, j0 <= j1, k0 <= k1, got " + v);
            o.has_roi = true;
          },
          [](const Options& o) -> std::string {
            if (!o.has_roi) return "null";
            std::string s = "[";
            for (int d = 0; d < 6; ++d) s += (d ? ", " : "") + std::to_string(o.roi[d]);
            return s + "]";
          }};
}

Binding threshold() {
  return {[](Options& o, const std::string& v) {
            o.threshold_given = true;
            if (trim(v) == "otsu") {
              o.threshold_otsu = true;
              return;
            }
            const double x = parse_real("", v);
            if (!std::isfinite(x)) throw UsageError("must be a finite number or otsu, got " + v);
            o.threshold_otsu = false;
            o.threshold_value = x;
          },
          [](const Options& o) {
            return o.threshold_otsu ? json_string("otsu") : json_number(o.threshold_value);
          }};
}

Binding polarity() {
  return {[](Options& o, const std::string& v) {
            if (v == "bright" || v == "brighter") o.deform.polarity = gdm::Polarity::object_brighter;
            else if (v == "dark" || v == "darker") o.deform.polarity = gdm::Polarity::object_darker;
            else throw UsageError("must be bright or dark, got " + v);
          },
          [](const Options& o) {
            return json_string(o.deform.polarity == gdm::Polarity::object_darker ? "dark" : "bright");
          }};
}

Binding mode() {
  return {[](Options& o, const std::string& v) {
            if (v == "grow") o.deform.mode = gdm::Mode::grow;
            else if (v == "shrink") o.deform.mode = gdm::Mode::shrink;
            else throw UsageError("must be grow or shrink, got " + v);
          },
          [](const Options& o) { return json_string(o.deform.mode == gdm::Mode::shrink ? "shrink" : "grow"); }};
}

// A row of the table.
OptionSpec row(std::string name, std::string metavar, std::string unit, std::string group, std::string help,
               Binding b, std::string default_text = {}) {
  return {std::move(name), std::move(metavar), std::move(unit), std::move(group), std::move(help),
          std::move(b.set), std::move(b.get), std::move(default_text)};
}

#define GDM_FIELD(type, expr) static_cast<Accessor<type>>([](Options& o) -> type& { return o.expr; })

std::vector<OptionSpec> make_table() {
  const char* in = "Input";
  const char* pre = "Preprocessing";
  const char* seed = "Seed";
  const char* model = "Model (the core's DeformOptions; paper's defaults)";
  const char* out = "Output";
  // One line per option: name, value, unit, group, help, binding[, default shown in --help].
  // The line gives the parser, --help and the report's "parameters"; a new
  // field of gdm::DeformOptions also needs its filter setter in run_model.cxx.
  return {
      row("--series", "UID", "", in, "DICOM series to read from a folder with several", text(GDM_FIELD(std::string, series)), "the series with most slices"),
      row("--smooth", "SIGMA", "mm", pre, "Gaussian smoothing before the model (0 = none)", real(GDM_FIELD(double, smooth_mm), 0.0, 1000.0)),
      row("--roi", "I0,J0,K0,I1,J1,K1", "voxels", pre, "crop to this inclusive voxel box first", roi(), "the whole volume"),
      row("--threshold", "T|otsu", "image units (HU for CT)", pre, "iso-value T of eq. 2; otsu = Otsu's method", threshold()),
      row("--polarity", "bright|dark", "", pre, "the object is brighter or darker than T", polarity()),
      row("--seed", "auto|X,Y,Z", "mm", seed, "seed centre (physical); auto = deepest point of the largest object region", seed_point()),
      row("--seed-index", "I,J,K", "voxels", seed, "seed centre as a voxel index of the input (also with --roi)", seed_index(), "none"),
      row("--seed-radius", "R", "mm", seed, "seed sphere radius (0 = auto: half the depth for --seed auto, else 2 voxels)", real(GDM_FIELD(double, seed.radius), 0.0, kInf)),
      row("--seed-level", "N", "", seed, "subdivisions of the icosahedron seed (20*4^N faces)", integer(GDM_FIELD(int, seed.level), 0, 8)),
      row("--seed-mesh", "FILE", "", seed, "closed triangle seed mesh (.vtk/.obj/.off, mm)", seed_mesh(), "none"),
      row("--mode", "grow|shrink", "", model, "grow from inside the object or shrink from around it (section 5)", mode()),
      row("--a0", "A0", "", model, "deformation gain a0 of eq. 1 (Table 2)", real(GDM_FIELD(double, deform.a0), 0.0, kInf)),
      row("--a1", "A1", "", model, "image event gain a1 of eq. 1 (Table 2)", real(GDM_FIELD(double, deform.a1), 0.0, kInf)),
      row("--a2", "A2", "", model, "topology gain a2 of eq. 1 (Table 2)", real(GDM_FIELD(double, deform.a2), 0.0, kInf)),
      row("--intensity-scale", "S", "image units", model, "intensity per unit of I (0 = 1% of the value range)", real(GDM_FIELD(double, deform.intensity_scale), 0.0, kInf)),
      row("--reach", "R", "voxels", model, "distance of the normal-tracking target (section 3.1.1)", real(GDM_FIELD(double, deform.reach), 0.01, 10.0)),
      row("--normal-rings", "N", "", model, "rings of faces averaged into a vertex normal (section 7)", integer(GDM_FIELD(int, deform.normal_rings), 1, 4)),
      row("--local-flip", "on|off", "", model, "flip the sense of vertices that crossed the boundary (section 5)", on_off(GDM_FIELD(bool, deform.local_flip))),
      row("--min-step", "S", "voxels", model, "smallest optimizer step (section 3.2)", real(GDM_FIELD(double, deform.optimizer.min_step), 0.01, 10.0)),
      row("--max-step", "S", "voxels", model, "largest optimizer step (section 3.2)", real(GDM_FIELD(double, deform.optimizer.max_step), 0.01, 10.0)),
      row("--step-reductions", "N", "", model, "step halvings tried before a vertex stays put", integer(GDM_FIELD(int, deform.optimizer.max_step_reductions), 0, 16)),
      row("--gradient-step", "H", "voxels", model, "central-difference half width of the gradient", real(GDM_FIELD(double, deform.optimizer.gradient_step), 0.01, 1.0)),
      row("--lod", "AREA", "voxels^2", model, "level of detail: faces larger than this are split (Table 2)", real(GDM_FIELD(double, deform.lod_face_area), 0.5, kInf)),
      row("--lod-topology-extent", "on|off", "", model, "floor eq. 3's extent at the level of detail", on_off(GDM_FIELD(bool, deform.lod_topology_extent))),
      row("--max-topology-ratio", "R", "", model, "hard limit on eq. 3's ratio, against leaks through narrow gaps (inf = off)", positive_or_inf(GDM_FIELD(double, deform.max_topology_ratio))),
      row("--refinement-travel", "D", "level-of-detail edge lengths", model, "after a global refinement a vertex moves at most this far from where the stage found it (inf = off)", positive_or_inf(GDM_FIELD(double, deform.refinement_travel))),
      row("--refinements", "N", "", model, "global 1-to-4 resamplings, each after a convergence (section 6)", integer(GDM_FIELD(int, deform.global_refinements), 0, 4)),
      row("--max-cycles", "N", "cycles", model, "hard limit on deformation cycles, all stages", integer(GDM_FIELD(int, deform.max_cycles), 1, std::numeric_limits<int>::max())),
      row("--tolerance", "D", "voxels", model, "a vertex counts as moving beyond this", real(GDM_FIELD(double, deform.convergence_tolerance), 0.001, kInf)),
      row("--window", "N", "cycles", model, "converged when nothing moved for this many cycles", integer(GDM_FIELD(int, deform.convergence_window), 1, std::numeric_limits<int>::max())),
      row("--self-intersection-guard", "on|off", "", model, "veto moves and flips that would self-intersect", on_off(GDM_FIELD(bool, deform.prevent_self_intersection))),
      row("--improve-triangles", "on|off", "", model, "Delaunay edge flips on nearly flat regions", on_off(GDM_FIELD(bool, deform.improve_triangles))),
      row("--flip-dihedral", "DEG", "degrees", model, "only flip where faces are this close to flat", real(GDM_FIELD(double, deform.flip_max_dihedral), 0.0, 89.9)),
      row("--max-faces", "N", "faces", model, "stop when the model grows past this many faces", count(GDM_FIELD(std::size_t, deform.max_faces), 20)),
      row("--subvoxel-fit", "on|off", "", model, "after convergence, move every vertex onto the threshold crossing of the trilinear field", on_off(GDM_FIELD(bool, deform.subvoxel_fit))),
      row("--fit-passes", "N", "", model, "sweeps of the sub-voxel fit, in [1, 20]", integer(GDM_FIELD(int, deform.fit_passes), 1, 20)),
      row("--fit-max-distance", "D", "voxels", model, "a vertex moves at most this far in the fit, in (0, 4]", real_interval(GDM_FIELD(double, deform.fit_max_distance), 0.0, true, 4.0, false)),
      row("--fit-smoothing", "S", "", model, "the fit draws a vertex toward the quadric over its 2-ring where it stands within S image-noise levels of it (smooths noise, keeps edges), in [0, 5], 0 = off", real_interval(GDM_FIELD(double, deform.fit_smoothing), 0.0, false, 5.0, false)),
      row("--lod-tolerance", "E", "voxels", model, "error-driven level of detail: at most this deviation of a face from the threshold surface; splits where the surface leaves the faces, collapses where flat (0 = off, else [0.01, 10])", lod_tolerance()),
      row("--lod-min-angle", "DEG", "degrees", model, "collapses of the error-driven level of detail keep every angle above this, in [0, 60)", real_interval(GDM_FIELD(double, deform.lod_min_angle), 0.0, false, 60.0, true)),
      row("--lod-rounds", "N", "rounds", model, "collapse / split / fit rounds of the error-driven level of detail, in [1, 50]", integer(GDM_FIELD(int, deform.lod_rounds), 1, 50)),
      row("--float-exact", "on|off", "", model, "end with every vertex on a float point, checked by the guard (float outputs stay free of self-intersections)", on_off(GDM_FIELD(bool, deform.float_exact_output))),
      row("--threads", "N", "", model, "worker threads (0 = all cores); the result does not depend on it", integer(GDM_FIELD(int, deform.threads), 0, 1024)),
      row("--output", "FILE", "", out, "mesh file: .ply (binary, vertex generation), .obj, .stl, .off, .vtk (also -o)", text(GDM_FIELD(std::string, output)), "<input name>-gdm.ply"),
      row("--report", "FILE", "", out, "write a JSON report (figures and every parameter) here", text(GDM_FIELD(std::string, report)), "none"),
      row("--allow-border", "", "", out, "accept a model that reached the volume border (else exit 4)", flag(GDM_FIELD(bool, allow_border))),
      row("--quiet", "", "", out, "no progress and no summary; errors only (also -q)", flag(GDM_FIELD(bool, quiet))),
      row("--help", "", "", out, "this text (also -h)", flag(GDM_FIELD(bool, help))),
      row("--version", "", "", out, "the version", flag(GDM_FIELD(bool, version))),
  };
}
#undef GDM_FIELD

}  // namespace

const std::vector<OptionSpec>& option_table() {
  static const std::vector<OptionSpec> table = make_table();
  return table;
}

double parse_real(const std::string& option, const std::string& text) {
  const std::string t = trim(text);
  char* end = nullptr;
  errno = 0;
  const double x = std::strtod(t.c_str(), &end);
  if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE || std::isnan(x))
    throw UsageError((option.empty() ? "" : option + " ") + "needs a number, got '" + text + "'");
  return x;
}

long parse_integer(const std::string& option, const std::string& text) {
  const std::string t = trim(text);
  char* end = nullptr;
  errno = 0;
  const long x = std::strtol(t.c_str(), &end, 10);
  if (t.empty() || end != t.c_str() + t.size() || errno == ERANGE)
    throw UsageError((option.empty() ? "" : option + " ") + "needs an integer, got '" + text + "'");
  return x;
}

std::vector<double> parse_list(const std::string& option, const std::string& text, std::size_t count) {
  std::vector<double> values;
  std::string item;
  std::istringstream in(text);
  while (std::getline(in, item, ',')) values.push_back(parse_real(option, item));
  if (values.size() != count)
    throw UsageError((option.empty() ? "" : option + " ") + "needs " + std::to_string(count) +
                     " comma-separated numbers, got '" + text + "'");
  return values;
}

Options parse_arguments(int argc, const char* const argv[]) {
  Options options;
  const auto& table = option_table();
  bool positional_only = false;
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (positional_only || arg.empty() || arg[0] != '-' || arg == "-") {
      if (!options.input.empty())
        throw UsageError("more than one input given ('" + options.input + "' and '" + arg + "')");
      options.input = arg;
      continue;
    }
    if (arg == "--") {
      positional_only = true;
      continue;
    }
    if (arg == "-o") arg = "--output";
    else if (arg == "-h") arg = "--help";
    else if (arg == "-q") arg = "--quiet";
    std::string value;
    bool has_value = false;
    const auto eq = arg.find('=');
    if (arg.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = arg.substr(eq + 1);
      arg = arg.substr(0, eq);
      has_value = true;
    }
    const OptionSpec* spec = nullptr;
    for (const auto& s : table)
      if (s.name == arg) spec = &s;
    if (spec == nullptr) throw UsageError("unknown option '" + arg + "' (see gdm --help)");
    if (!spec->metavar.empty() && !has_value) {
      if (i + 1 >= argc) throw UsageError(arg + " needs a value (" + spec->metavar + ")");
      value = argv[++i];
    } else if (spec->metavar.empty() && has_value) {
      throw UsageError(arg + " takes no value");
    }
    try {
      spec->set(options, value);
    } catch (const UsageError& e) {
      throw UsageError(arg + ": " + e.what());
    }
  }
  return options;
}

std::string help_text(const std::string& program) {
  std::ostringstream s;
  s << "Usage: " << program << " [options] [INPUT]\n\n"
    << "Extracts a closed, 2-manifold, self-intersection-free triangle mesh of an object\n"
    << "in a 3D scan with a Geometrically Deformed Model (Miller et al., SIGGRAPH 1991).\n\n"
    << "INPUT: a DICOM series folder, a single (multi-frame) DICOM file, or a .mha/.mhd,\n"
    << ".nrrd/.nhdr, .nii/.nii.gz or .vtk image; any scalar pixel type (read as float;\n"
    << "DICOM rescale slope/intercept applied, so CT values are HU). Spacing, origin and\n"
    << "direction are honoured: coordinates are physical, in mm. Without INPUT, gdm runs\n"
    << "on its embedded CT-like phantom (data/phantom.mha) with --threshold 400.\n";
  const Options defaults;
  std::string group;
  for (const auto& o : option_table()) {
    if (o.group != group) {
      group = o.group;
      s << "\n" << group << ":\n";
    }
    std::string head = "  " + o.name + (o.metavar.empty() ? "" : " " + o.metavar);
    if (head.size() < 30) head.resize(30, ' ');
    else head += "\n" + std::string(30, ' ');
    std::string def = o.default_text;
    if (def.empty() && !o.metavar.empty()) {
      def = o.get(defaults);
      if (def.size() > 1 && def.front() == '"') def = def.substr(1, def.size() - 2);
      if (def == "true") def = "on";
      if (def == "false") def = "off";
    }
    std::string line = o.help;
    if (!o.metavar.empty()) line += " [" + (o.unit.empty() ? std::string() : o.unit + "; ") + "default: " + def + "]";
    else if (!o.unit.empty()) line += " [" + o.unit + "]";
    // Word-wrap the description at 100 columns, aligned under its start.
    std::string wrapped, word;
    std::size_t column = 30;
    std::istringstream words(line);
    while (words >> word) {
      if (column > 30 && column + 1 + word.size() > 100) {
        wrapped += "\n" + std::string(30, ' ');
        column = 30;
      } else if (column > 30) {
        wrapped += ' ';
        ++column;
      }
      wrapped += word;
      column += word.size();
    }
    s << head << wrapped;
    s << "\n";
  }
  s << "\nOutput files are written to a temporary name and renamed: a failed run leaves none.\n"
    << "Progress goes to stderr, one line per cycle (cycle, refinement stage, faces, vertices\n"
    << "that moved; updated in place on a terminal, none with --quiet).\n\n"
    << "Exit codes:\n"
    << "  0  success\n"
    << "  1  internal error (a bug)\n"
    << "  2  bad usage: unknown option, bad value, seed outside the volume or the object\n"
    << "  3  unreadable or invalid input: missing file, no DICOM series, not 3D, corrupt header\n"
    << "  4  the model failed: it reached the volume border (check --polarity and --threshold),\n"
    << "     hit the face limit, or the core rejected the run\n"
    << "  5  the mesh or the report could not be written\n";
  return s.str();
}

std::string parameters_json(const Options& options, int indent) {
  JsonObject object;
  object.add("input", options.input.empty() ? std::string("null") : json_string(options.input));
  for (const auto& o : option_table()) {
    if (o.name == "--help" || o.name == "--version") continue;
    object.add(o.name.substr(2), o.get(options));
  }
  return object.str(indent);
}

}  // namespace gdm_cli
