#include "cli_options.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>

#include "cli_errors.h"
#include "json_writer.h"

namespace gdm_cli {
namespace {

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

// A row of the core's catalogue: parsed by its type, checked by the core's
// range check (the same one validate() runs), rendered by its value text.
Binding catalogue(const gdm::OptionEntry<gdm::PipelineOptions>& entry) {
  return {[entry](Options& o, const std::string& v) {
            double x = 0.0;
            switch (entry.type) {
              case gdm::OptionType::boolean:
                if (v == "on" || v == "yes" || v == "true" || v == "1") x = 1.0;
                else if (v == "off" || v == "no" || v == "false" || v == "0") x = 0.0;
                else throw UsageError("must be on or off, got " + v);
                break;
              case gdm::OptionType::choice: {
                const auto& c = entry.choices;
                const auto it = std::find(c.begin(), c.end(), trim(v));
                if (it == c.end()) throw UsageError("must be " + gdm::range_text(entry) + ", got " + v);
                x = static_cast<double>(it - c.begin());
                break;
              }
              case gdm::OptionType::integer:
              case gdm::OptionType::real:
                x = parse_real("", v);
                if (!gdm::accepts(entry, x)) throw UsageError("must be " + gdm::range_text(entry) + ", got " + v);
                break;
            }
            entry.set(o.pipeline, x);
          },
          [entry](const Options& o) {
            const double x = entry.get(o.pipeline);
            switch (entry.type) {
              case gdm::OptionType::boolean: return json_bool(x != 0.0);
              case gdm::OptionType::choice: return json_string(gdm::value_text(entry, x));
              default: return std::isinf(x) ? json_string("inf") : json_number(x);
            }
          }};
}

// Voxel indices: integers within the range a volume can have (no overflowing cast).
std::vector<long> parse_indices(const std::string& v, std::size_t count, bool non_negative) {
  std::vector<long> out;
  for (const double x : parse_list("", v, count)) {
    if (x != std::floor(x) || std::fabs(x) > 1e9 || (non_negative && x < 0))
      throw UsageError(std::string("needs ") + (non_negative ? "non-negative " : "") +
                       "integer voxel indices (at most 1e9), got " + v);
    out.push_back(static_cast<long>(x));
  }
  return out;
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
              o.pipeline.seed.kind = gdm::SeedKind::automatic;
              return;
            }
            const auto p = parse_list("", v, 3);
            o.pipeline.seed.kind = gdm::SeedKind::point;
            o.pipeline.seed.point = gdm::Vec3(p[0], p[1], p[2]);
          },
          [](const Options& o) -> std::string {
            switch (o.pipeline.seed.kind) {
              case gdm::SeedKind::automatic: return json_string("auto");
              case gdm::SeedKind::point: {
                const auto& p = o.pipeline.seed.point;
                return json_array(std::array<double, 3>{p.x(), p.y(), p.z()});
              }
              default: return "null";
            }
          }};
}

Binding seed_index() {
  return {[](Options& o, const std::string& v) {
            const auto p = parse_indices(v, 3, false);
            o.pipeline.seed.kind = gdm::SeedKind::index;
            for (int d = 0; d < 3; ++d) o.pipeline.seed.index[d] = static_cast<int>(p[d]);
          },
          [](const Options& o) -> std::string {
            if (o.pipeline.seed.kind != gdm::SeedKind::index) return "null";
            const auto& i = o.pipeline.seed.index;
            return "[" + std::to_string(i[0]) + ", " + std::to_string(i[1]) + ", " + std::to_string(i[2]) + "]";
          }};
}

Binding seed_mesh() {
  return {[](Options& o, const std::string& v) {
            if (v.empty()) throw UsageError("needs a file name");
            o.pipeline.seed.kind = gdm::SeedKind::mesh;
            o.seed_mesh = v;
          },
          [](const Options& o) {
            return o.pipeline.seed.kind == gdm::SeedKind::mesh ? json_string(o.seed_mesh) : std::string("null");
          }};
}

Binding roi() {
  return {[](Options& o, const std::string& v) {
            const auto p = parse_indices(v, 6, true);
            auto& box = o.pipeline.roi;
            for (int d = 0; d < 3; ++d) {
              box.lo[d] = static_cast<int>(p[d]);
              box.hi[d] = static_cast<int>(p[d + 3]);
              if (box.hi[d] < box.lo[d]) throw UsageError("needs i0 <= i1, j0 <= j1, k0 <= k1, got " + v);
            }
            o.pipeline.use_roi = true;
          },
          [](const Options& o) -> std::string {
            if (!o.pipeline.use_roi) return "null";
            const auto& b = o.pipeline.roi;
            std::string s = "[";
            for (int d = 0; d < 6; ++d) s += (d ? ", " : "") + std::to_string(d < 3 ? b.lo[d] : b.hi[d - 3]);
            return s + "]";
          }};
}

Binding threshold() {
  return {[](Options& o, const std::string& v) {
            o.threshold_given = true;
            if (trim(v) == "otsu") {
              o.pipeline.threshold_otsu = true;
              return;
            }
            const double x = parse_real("", v);
            if (!std::isfinite(x)) throw UsageError("must be a finite number or otsu, got " + v);
            o.pipeline.threshold_otsu = false;
            o.pipeline.threshold = x;
          },
          [](const Options& o) {
            return o.pipeline.threshold_otsu ? json_string("otsu") : json_number(o.pipeline.threshold);
          }};
}

// --memory-limit: GiB (2^30 bytes) of float voxels, 0 = none.
Binding memory_limit() {
  return {[](Options& o, const std::string& v) {
            const double x = parse_real("", v);
            if (!(x >= 0.0 && x <= 1e6)) throw UsageError("must be in [0, 1e6] GiB (0 = no limit), got " + v);
            o.memory_limit_gb = x;
          },
          [](const Options& o) { return json_number(o.memory_limit_gb); }};
}

// A row of the table.
OptionSpec row(std::string name, std::string metavar, std::string unit, std::string group, std::string help,
               Binding b, std::string default_text = {}) {
  return {std::move(name), {}, std::move(metavar), std::move(unit), std::move(group), std::move(help),
          std::move(b.set), std::move(b.get), std::move(default_text)};
}

// The catalogue's name as a flag: lod_face_area -> --lod-face-area.
std::string flag_name(const std::string& name) {
  std::string s = "--" + name;
  std::replace(s.begin(), s.end(), '_', '-');
  return s;
}

OptionSpec catalogue_row(const gdm::OptionEntry<gdm::PipelineOptions>& e) {
  std::string metavar;
  switch (e.type) {
    case gdm::OptionType::boolean: metavar = "on|off"; break;
    case gdm::OptionType::choice:
      for (const auto& c : e.choices) metavar += (metavar.empty() ? "" : "|") + c;
      break;
    case gdm::OptionType::integer: metavar = "N"; break;
    case gdm::OptionType::real: metavar = "X"; break;
  }
  // An on/off option that is off by default is a bare flag (--allow-border).
  if (e.type == gdm::OptionType::boolean && e.get(gdm::PipelineOptions{}) == 0.0) {
    const auto set = e.set;
    return row(flag_name(e.name), "", e.unit, e.group, e.help,
               {[set](Options& o, const std::string&) { set(o.pipeline, 1.0); }, catalogue(e).get});
  }
  std::string help = e.help;
  if (e.type == gdm::OptionType::real || e.type == gdm::OptionType::integer) help += ", " + gdm::range_text(e);
  OptionSpec spec = row(flag_name(e.name), metavar, e.unit, e.group, help, catalogue(e));
  if (!e.alias.empty()) spec.alias = "--" + e.alias;
  return spec;
}

#define GDM_FIELD(type, expr) static_cast<Accessor<type>>([](Options& o) -> type& { return o.expr; })

std::vector<OptionSpec> make_table() {
  const char* in = "Input";
  const char* pre = "Preprocessing";
  const char* seed = "Seed";
  const char* out = "Output";
  const auto& entries = gdm::pipeline_option_catalogue();
  const auto from_catalogue = [&](std::vector<OptionSpec>& table, const std::string& group) {
    for (const auto& e : entries)
      if (e.group == group) table.push_back(catalogue_row(e));
  };
  // The command's own rows (files, the threshold's otsu, the seed's forms,
  // the region of interest), then the catalogue's rows in its groups.
  std::vector<OptionSpec> table = {
      row("--series", "UID", "", in, "DICOM series to read from a folder with several", text(GDM_FIELD(std::string, series)), "the series with most slices"),
      row("--memory-limit", "GB", "GiB", in, "refuse a volume whose voxels take more than this as float (4 bytes each; 0 = no limit)", memory_limit()),
      row("--roi", "I0,J0,K0,I1,J1,K1", "voxels", pre, "crop to this inclusive voxel box first", roi(), "the whole volume"),
      row("--threshold", "T|otsu", "image units (HU for CT)", pre, "iso-value T of eq. 2; otsu = Otsu's method", threshold()),
  };
  from_catalogue(table, pre);
  table.push_back(row("--seed", "auto|X,Y,Z", "mm", seed, "seed centre (physical); auto = deepest point of the largest object region (with --mode shrink: a sphere around the object's voxels)", seed_point()));
  table.push_back(row("--seed-index", "I,J,K", "voxels", seed, "seed centre as a voxel index of the input (also with --roi)", seed_index(), "none"));
  table.push_back(row("--seed-mesh", "FILE", "", seed, "closed triangle seed mesh (.ply/.obj/.off/.stl/.vtk, mm)", seed_mesh(), "none"));
  from_catalogue(table, seed);
  for (const auto& e : entries)
    if (e.group != pre && e.group != seed && e.group != out) table.push_back(catalogue_row(e));
  table.push_back(row("--output", "FILE", "", out, "mesh file: .ply (binary, vertex generation), .obj, .stl, .off, .vtk (also -o)", text(GDM_FIELD(std::string, output)), "<input name>-gdm.ply"));
  table.push_back(row("--report", "FILE", "", out, "write a JSON report (figures and every parameter) here", text(GDM_FIELD(std::string, report)), "none"));
  from_catalogue(table, out);
  table.push_back(row("--quiet", "", "", out, "no progress and no summary; errors only (also -q)", flag(GDM_FIELD(bool, quiet))));
  table.push_back(row("--help", "", "", out, "this text (also -h)", flag(GDM_FIELD(bool, help))));
  table.push_back(row("--version", "", "", out, "the version", flag(GDM_FIELD(bool, version))));
  return table;
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
      if (s.name == arg || (!s.alias.empty() && s.alias == arg)) spec = &s;
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
    if (!o.alias.empty()) line += " (also " + o.alias + ")";
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
    std::string key = o.name.substr(2);
    std::replace(key.begin(), key.end(), '-', '_');  // the catalogue's spelling
    object.add(key, o.get(options));
  }
  return object.str(indent);
}

}  // namespace gdm_cli
