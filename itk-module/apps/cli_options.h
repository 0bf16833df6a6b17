// The options of the gdm command: one table (cli_options.cpp) drives the
// parser, --help and the "parameters" block of the JSON report. Its numeric,
// on/off and choice rows come from the core's catalogue of options
// (gdm/option_catalogue.h, gdm::pipeline_option_catalogue()): a new option is
// its core field plus one catalogue line, and the flag, its help and its range
// check follow.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "gdm/pipeline.h"

namespace gdm_cli {

struct Options {
  std::string input;                      // image file or DICOM folder; empty = embedded phantom
  std::string output;                     // mesh file; empty = <input name>-gdm.ply
  std::string report;                     // JSON report file; empty = none
  std::string series;                     // DICOM series UID; empty = the one with most slices
  double memory_limit_gb = 8.0;           // largest volume read, GiB of float voxels; 0 = no limit
  bool threshold_given = false;           // --threshold was on the command line
  std::string seed_mesh;                  // seed mesh file (--seed-mesh); read into pipeline.seed.mesh
  gdm::PipelineOptions pipeline;          // everything the pipeline takes (the catalogue's options)
  bool quiet = false;                     // no progress, no summary
  bool help = false;
  bool version = false;
};

// One command-line option. `set` parses a value into the options (throws
// UsageError naming the option); `get` renders the current value as a JSON
// literal (used for the report and, on default options, for --help).
struct OptionSpec {
  std::string name;       // "--a0"
  std::string alias;      // an older spelling ("--lod"), accepted too; empty when none
  std::string metavar;    // "A0"; empty for a flag without value
  std::string unit;       // "mm", "voxels", ...; empty when none
  std::string group;      // heading in --help
  std::string help;       // one line
  std::function<void(Options&, const std::string&)> set;
  std::function<std::string(const Options&)> get;
  std::string default_text;  // shown in --help instead of get(defaults) when not empty
};

const std::vector<OptionSpec>& option_table();

// Parses argv into options. Throws UsageError.
Options parse_arguments(int argc, const char* const argv[]);

// The --help text.
std::string help_text(const std::string& program);

// The parameters as a JSON object (every option in the table, by name without "--").
std::string parameters_json(const Options& options, int indent);

// Parse helpers (exposed for the tests of the parser): throw UsageError.
double parse_real(const std::string& option, const std::string& text);
long parse_integer(const std::string& option, const std::string& text);
std::vector<double> parse_list(const std::string& option, const std::string& text, std::size_t count);

}  // namespace gdm_cli
