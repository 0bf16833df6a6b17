// The MeshLab filters' parameters as plain data (no Qt, no MeshLab): what each
// dialog shows, in order, with its default and help. The model's options are
// the catalogue's (gdm::pipeline_option_catalogue()): a parameter of kind
// `catalogue` takes the option's name, default, range and help from there, and
// every other catalogue option is reachable through `more_options`
// ("name=value ..."). The plugin builds its RichParameters from these lists,
// and meshlab-plugin/PARAMETERS.md is generated from them (a test fails when
// it is stale).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "gdm/pipeline.h"

namespace gdm_meshlab {

enum class ParamKind {
  volume_file,  // a file chooser (a file of a DICOM series stands for its folder)
  boolean,
  real,
  point,        // x, y, z in mm
  text,
  abs_perc,     // a length with its percentage of the layer's bounding box diagonal
  catalogue     // an option of the catalogue, by its name
};

struct FilterParam {
  std::string name;          // the parameter's name in scripts (the catalogue's for kind catalogue)
  ParamKind kind = ParamKind::real;
  std::string label;         // the dialog's label (a catalogue option's gets its unit appended)
  std::string help;          // the dialog's help (catalogue options: a short one; PARAMETERS.md has the full)
  double default_value = 0;  // booleans 0/1; abs_perc: the fraction of the bounding box diagonal
  std::string unit;          // replaces a catalogue option's unit (the wrap's level of detail is in cell^2)
  bool own_default = false;  // a catalogue option with this filter's default_value instead of the catalogue's
};

enum class Filter { from_volume, deform_mesh, shrink_wrap };

// The dialog of `filter`, in order.
const std::vector<FilterParam>& filter_parameters(Filter filter);

// The script name of `filter` ("Geometrically Deformed Model from Volume", ...).
std::string filter_name(Filter filter);

// The catalogue's option called `name` (dashes accepted), or nullptr.
const gdm::OptionEntry<gdm::PipelineOptions>* catalogue_option(std::string name);

// Sets the catalogue options named in `text`: "name=value" pairs separated by
// spaces, commas or semicolons; names as in the catalogue (dashes accepted),
// values as the gdm command takes them (numbers, inf, on/off, choice names).
// Throws gdm::InvalidOption naming the pair for an unknown name or a bad value.
void apply_more_options(const std::string& text, gdm::PipelineOptions& options);

// The volume file to read: `path` itself, or the folder of a DICOM slice
// (.dcm, .ima, or no extension) so that picking any slice reads its series.
std::string volume_path(const std::string& path);

// A meshlabserver script running `filter` with every parameter at its default
// but those in `values` (name -> the XML value; a point as "x y z", an
// abs_perc as the length in mm): meshlab-plugin/scripts/*.mlx and the tests.
std::string script(Filter filter, const std::vector<std::pair<std::string, std::string>>& values = {});

// The most help MeshLab 2020.09's dialog shows beside a parameter uncut.
constexpr std::size_t kDialogHelpCharacters = 88;

// The help a dialog shows for a catalogue option: the filter's short help (or
// the catalogue's up to its first ';'), with the option's range when it fits.
std::string dialog_help(const gdm::OptionInfo& option, const FilterParam& param);

// The label a dialog shows for `param`: a catalogue option's with its unit.
std::string dialog_label(const FilterParam& param);

// meshlab-plugin/PARAMETERS.md: every filter's parameters with defaults and help.
std::string parameters_markdown();

}  // namespace gdm_meshlab
