#include "filter_parameters.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "gdm/errors.h"
#include "gdm/option_catalogue.h"
#include "gdm/shrink_wrap.h"
#include "gdm/text.h"

namespace gdm_meshlab {
namespace {

FilterParam param(std::string name, ParamKind kind, std::string label, std::string help, double value = 0.0) {
  FilterParam p;
  p.name = std::move(name);
  p.kind = kind;
  p.label = std::move(label);
  p.help = std::move(help);
  p.default_value = value;
  return p;
}

// A catalogue option under a label a user reads and a help that fits beside
// it (the script keeps its name; PARAMETERS.md gives the catalogue's help).
FilterParam option(std::string name, std::string label, std::string help, std::string unit = {}) {
  FilterParam p;
  p.name = std::move(name);
  p.kind = ParamKind::catalogue;
  p.label = std::move(label);
  p.help = std::move(help);
  p.unit = std::move(unit);
  return p;
}

// The volume, its threshold and the few options most runs change; the rest
// behind `more_options`, so that the dialog fits on a screen.
std::vector<FilterParam> volume_head() {
  return {
      param("volume_file", ParamKind::volume_file, "Volume file",
            "Choose with ...: .mha, .mhd, .nrrd, .nii(.gz), .vtk, or a slice of a DICOM series"),
      param("threshold_otsu", ParamKind::boolean, "Otsu's threshold",
            "T by Otsu's method, as gdm does; off: the threshold below",
            1.0),
      param("threshold", ParamKind::real, "Threshold if not Otsu's",
            "T of eq. 2 between object and background, in image units (e.g. HU)"),
      option("polarity", "Object is", "bright: above the threshold; dark: below it"),
      option("smooth", "Gaussian smoothing", "Sigma of a Gaussian applied first; 0 = none"),
  };
}

std::vector<FilterParam> volume_tail() {
  return {
      option("gap", "Gap size", "Openings narrower than this are bridged, wider channels entered; 0 = two voxels"),
      option("lod_face_area", "Face area", "Level of detail: larger faces are split (Table 2)"),
      option("lod_tolerance", "Error tolerance", "Fewest faces within this distance of the data"),
      option("min_angle", "Smallest angle", "Faces with a smaller angle are improved at the end; 0 = off"),
      option("face_budget", "Face budget", "About this many faces, the most accurate the model makes; 0 = off"),
      option("allow_border", "Object may touch the border",
             "Off: allowed only where the scan cuts the object (a quarter of the border at most)"),
      param("more_options", ParamKind::text, "More options",
            "Other options of docs/options.md as name=value pairs, e.g. a2=3 global_refinements=0"),
  };
}

// The wrap refines globally only when asked: its faces then stay near the
// level of detail (4 times fewer than with one refinement, and 4 times faster).
FilterParam wrap_refinements() {
  FilterParam p = option("global_refinements", "Global refinements", "1-to-4 refinements after converging (section 6)");
  p.own_default = true;
  p.default_value = 0.0;
  return p;
}

std::vector<FilterParam> make(Filter filter) {
  std::vector<FilterParam> out;
  const auto append = [&out](const std::vector<FilterParam>& more) { out.insert(out.end(), more.begin(), more.end()); };
  switch (filter) {
    case Filter::from_volume:
      append(volume_head());
      append({param("seed_automatic", ParamKind::boolean, "Automatic seed",
                    "At the deepest point of the largest object region; off: the point below",
                    1.0),
              param("seed_point", ParamKind::point, "Seed point (mm)",
                    "Centre of the seed sphere when the automatic seed is off; inside the object."),
              option("seed_radius", "Seed radius", "0 = automatic: half the depth, or two voxels"),
              option("voxel_seed", "Start from the object's voxels",
                     "Start from the object's voxel surface, not grow: no seams in thin shells; slower")});
      append(volume_tail());
      break;
    case Filter::deform_mesh:
      append(volume_head());
      append({option("mode", "Mode", "grow: the layer lies inside the object; shrink: around it"),
              param("new_layer", ParamKind::boolean, "Add the result as a new layer",
                    "Keep the current layer and add the model as a new one; off: replace it.", 1.0)});
      append(volume_tail());
      break;
    case Filter::shrink_wrap:
      append({param("cell_size", ParamKind::abs_perc, "Grid cell size",
                    "Cells of the distance grid (the face area is in cells); default 1% of the diagonal",
                    0.01),
              param("tolerance", ParamKind::abs_perc, "Tolerance",
                    "Largest distance of the layer from the wrap (>= a cell); default 2% of the diagonal",
                    0.02),
              option("lod_face_area", "Face area", "Level of detail: larger faces are split", "cell^2"), wrap_refinements(),
              // On by default (issue 18): without it the wrap sinks into every
              // opening and stands in pyramids over it; 10 x the tolerance.
              param("bridge", ParamKind::abs_perc, "Bridge",
                    "Holes up to about this wide get a smooth cap; 0 = off (the wrap sinks into them)", 0.2),
              param("time_limit", ParamKind::real, "Time limit (s)",
                    "Refuse at once a wrap estimated to take longer (see the log); 0 = no limit",
                    gdm::WrapOptions{}.time_limit),
              param("memory_limit", ParamKind::real, "Memory limit (GiB)",
                    "Refuse at once a wrap estimated to need more memory; 0 = no limit.",
                    gdm::WrapOptions{}.memory_limit),
              param("more_options", ParamKind::text, "More options",
                    "Other options as name=value pairs: a0, a1, a2, max_cycles, threads.")});
      break;
  }
  return out;
}

double parse_value(const gdm::OptionInfo& o, const std::string& text) {
  if (o.type == gdm::OptionType::boolean) {
    if (text == "on" || text == "true" || text == "yes" || text == "1") return 1.0;
    if (text == "off" || text == "false" || text == "no" || text == "0") return 0.0;
  } else if (o.type == gdm::OptionType::choice) {
    const auto it = std::find(o.choices.begin(), o.choices.end(), text);
    if (it != o.choices.end()) return static_cast<double>(it - o.choices.begin());
  } else {
    char* end = nullptr;
    const double v = std::strtod(text.c_str(), &end);
    if (!text.empty() && end == text.c_str() + text.size()) return v;
  }
  throw gdm::InvalidOption(o.name, "more_options: " + o.name + " must be " + gdm::range_text(o) + ", got " + text);
}

}  // namespace

const gdm::OptionEntry<gdm::PipelineOptions>* catalogue_option(std::string name) {
  std::replace(name.begin(), name.end(), '-', '_');
  for (const auto& o : gdm::pipeline_option_catalogue())
    if (o.name == name) return &o;
  return nullptr;
}

std::string dialog_help(const gdm::OptionInfo& o, const FilterParam& p) {
  // MeshLab 2020.09 shows about two lines of help beside a parameter (its
  // help column, 250 pixels) and cuts the rest, seen under Xvfb: the dialog's
  // short help, with the option's range when it still fits.
  std::string help = p.help;
  if (help.empty()) {
    help = o.help;
    const auto semicolon = help.find(';');
    if (semicolon != std::string::npos) help = help.substr(0, semicolon);
  }
  const bool numeric = o.type == gdm::OptionType::real || o.type == gdm::OptionType::integer;
  const std::string range = "(" + gdm::range_text(o) + ")";
  if (numeric && help.size() + 1 + range.size() <= kDialogHelpCharacters) help += " " + range;
  return help;
}

std::string dialog_label(const FilterParam& p) {
  if (p.kind != ParamKind::catalogue) return p.label;
  const auto* o = catalogue_option(p.name);
  const std::string unit = p.unit.empty() ? (o != nullptr ? o->unit : std::string()) : p.unit;
  return (p.label.empty() ? p.name : p.label) + (unit.empty() ? "" : " (" + unit + ")");
}

const std::vector<FilterParam>& filter_parameters(Filter filter) {
  static const std::vector<FilterParam> lists[3] = {make(Filter::from_volume), make(Filter::deform_mesh),
                                                    make(Filter::shrink_wrap)};
  return lists[static_cast<int>(filter)];
}

std::string filter_name(Filter filter) {
  switch (filter) {
    case Filter::from_volume: return "Geometrically Deformed Model from Volume";
    case Filter::deform_mesh: return "Deform Current Mesh into Volume";
    case Filter::shrink_wrap: return "Shrink-Wrap Current Mesh";
  }
  return {};
}

void apply_more_options(const std::string& text, gdm::PipelineOptions& options) {
  std::string spaced = text;
  for (char& c : spaced)
    if (c == ',' || c == ';') c = ' ';
  std::istringstream in(spaced);
  std::string pair;
  while (in >> pair) {
    const auto eq = pair.find('=');
    if (eq == std::string::npos || eq == 0)
      throw gdm::InvalidOption("more_options", "more_options: '" + pair + "' is not name=value");
    const auto* o = catalogue_option(pair.substr(0, eq));
    if (o == nullptr)
      throw gdm::InvalidOption("more_options", "more_options: no option '" + pair.substr(0, eq) +
                                                   "' (the names are those of docs/options.md)");
    const double v = parse_value(*o, pair.substr(eq + 1));
    if (!gdm::accepts(*o, v))
      throw gdm::InvalidOption(o->name, "more_options: " + o->name + " must be " + gdm::range_text(*o) + ", got " +
                                            pair.substr(eq + 1));
    o->set(options, v);
  }
}

std::string volume_path(const std::string& path) {
  const auto slash = path.find_last_of('/');
  const std::string file = slash == std::string::npos ? path : path.substr(slash + 1);
  const auto dot = file.find_last_of('.');
  std::string ext = dot == std::string::npos ? std::string() : file.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const bool dicom_slice = ext.empty() || ext == ".dcm" || ext == ".ima";
  if (!dicom_slice || slash == std::string::npos || file.empty()) return path;
  return path.substr(0, slash == 0 ? 1 : slash);
}

std::string script(Filter filter, const std::vector<std::pair<std::string, std::string>>& values) {
  const gdm::PipelineOptions defaults;
  std::ostringstream s;
  s << "<!DOCTYPE FilterScript>\n<FilterScript>\n <filter name=\"" << filter_name(filter) << "\">\n";
  for (const auto& p : filter_parameters(filter)) {
    std::string value;
    bool given = false;
    for (const auto& v : values)
      if (v.first == p.name) {
        value = v.second;
        given = true;
      }
    const std::string name = "name=\"" + p.name + "\"";
    switch (p.kind) {
      case ParamKind::volume_file:
        s << "  <Param type=\"RichOpenFile\" value=\"" << value << "\" exts_cardinality=\"0\" " << name << "/>\n";
        break;
      case ParamKind::boolean:
        s << "  <Param type=\"RichBool\" value=\"" << (given ? value : p.default_value != 0.0 ? "true" : "false") << "\" "
          << name << "/>\n";
        break;
      case ParamKind::real:
        s << "  <Param type=\"RichFloat\" value=\"" << (given ? value : gdm::format_number(p.default_value)) << "\" "
          << name << "/>\n";
        break;
      case ParamKind::point: {
        std::istringstream xyz(given ? value : "0 0 0");
        std::string x, y, z;
        xyz >> x >> y >> z;
        s << "  <Param type=\"RichPoint3f\" x=\"" << x << "\" y=\"" << y << "\" z=\"" << z << "\" " << name << "/>\n";
        break;
      }
      case ParamKind::text:
        s << "  <Param type=\"RichString\" value=\"" << value << "\" " << name << "/>\n";
        break;
      case ParamKind::abs_perc:
        // Not given: the default for a layer whose diagonal is 100 mm.
        s << "  <Param type=\"RichAbsPerc\" value=\"" << (given ? value : gdm::format_number(100.0 * p.default_value))
          << "\" min=\"0\" max=\"1000\" " << name
          << "/>\n";
        break;
      case ParamKind::catalogue: {
        const auto* o = catalogue_option(p.name);
        const double v = p.own_default ? p.default_value : o->get(defaults);
        switch (o->type) {
          case gdm::OptionType::real:
            s << "  <Param type=\"RichFloat\" value=\"" << (given ? value : gdm::format_number(v)) << "\" " << name << "/>\n";
            break;
          case gdm::OptionType::integer:
            s << "  <Param type=\"RichInt\" value=\"" << (given ? value : gdm::format_number(v)) << "\" " << name << "/>\n";
            break;
          case gdm::OptionType::boolean:
            s << "  <Param type=\"RichBool\" value=\"" << (given ? value : v != 0.0 ? "true" : "false") << "\" " << name
              << "/>\n";
            break;
          case gdm::OptionType::choice:
            s << "  <Param type=\"RichEnum\" value=\"" << (given ? value : gdm::format_number(v)) << "\" enum_cardinality=\""
              << o->choices.size() << "\"";
            for (std::size_t i = 0; i < o->choices.size(); ++i) s << " enum_val" << i << "=\"" << o->choices[i] << "\"";
            s << " " << name << "/>\n";
            break;
        }
        break;
      }
    }
  }
  s << " </filter>\n</FilterScript>\n";
  return s.str();
}

std::string parameters_markdown() {
  const gdm::PipelineOptions defaults;
  std::ostringstream s;
  s << "# The MeshLab filters' parameters\n\n"
    << "Generated from `meshlab-plugin/filter_parameters.cpp` and the catalogue of options\n"
    << "(`gdm_ml_testtool parameters > meshlab-plugin/PARAMETERS.md`; a test fails when this\n"
    << "file is stale). A meshlabserver script must list every parameter of a filter\n"
    << "(Debian's meshlabserver 2020.09 aborts on a missing one): `meshlab-plugin/scripts/`\n"
    << "holds one per filter with every parameter at its default.\n";
  for (const Filter f : {Filter::from_volume, Filter::deform_mesh, Filter::shrink_wrap}) {
    s << "\n## " << filter_name(f) << "\n\n| parameter | dialog label | type | default | what it does |\n|---|---|---|---|---|\n";
    for (const auto& p : filter_parameters(f)) {
      std::string type, value, help = p.help;
      switch (p.kind) {
        case ParamKind::volume_file: type = "RichOpenFile"; value = "(none)"; break;
        case ParamKind::boolean: type = "RichBool"; value = p.default_value != 0.0 ? "true" : "false"; break;
        case ParamKind::real: type = "RichFloat"; value = gdm::format_number(p.default_value); break;
        case ParamKind::point: type = "RichPoint3f"; value = "0, 0, 0"; break;
        case ParamKind::text: type = "RichString"; value = "(empty)"; break;
        case ParamKind::abs_perc:
          type = "RichAbsPerc";
          value = gdm::format_number(100.0 * p.default_value) + "% of the diagonal";
          break;
        case ParamKind::catalogue: {
          const auto* o = catalogue_option(p.name);
          const double v = p.own_default ? p.default_value : o->get(defaults);
          switch (o->type) {
            case gdm::OptionType::real: type = "RichFloat"; break;
            case gdm::OptionType::integer: type = "RichInt"; break;
            case gdm::OptionType::boolean: type = "RichBool"; break;
            case gdm::OptionType::choice: type = "RichEnum"; break;
          }
          value = o->type == gdm::OptionType::boolean ? (v != 0.0 ? "true" : "false")
                  : o->type == gdm::OptionType::choice ? gdm::format_number(v) + " (" + gdm::value_text(*o, v) + ")"
                                                        : gdm::value_text(*o, v);
          const std::string unit = p.unit.empty() ? o->unit : p.unit;
          help = o->help + " (" + (unit.empty() ? "" : unit + "; ") + gdm::range_text(*o) + ")";
          break;
        }
      }
      s << "| `" << p.name << "` | " << dialog_label(p) << " | " << type << " | " << value << " | " << help << " |\n";
    }
  }
  return s.str();
}

}  // namespace gdm_meshlab
