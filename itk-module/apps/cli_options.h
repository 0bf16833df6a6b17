// The options of the gdm command: one table (cli_options.cpp) drives the
// parser, --help and the "parameters" block of the JSON report, so a new flag
// is one line in that table.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "gdm/deformer.h"

namespace gdm_cli {

enum class SeedKind { automatic, point, index, mesh };

struct SeedOptions {
  SeedKind kind = SeedKind::automatic;    // --seed auto (default), --seed x,y,z, --seed-index, --seed-mesh
  std::array<double, 3> point{0, 0, 0};   // physical seed centre, mm (--seed x,y,z)
  std::array<long, 3> index{0, 0, 0};     // seed centre as a voxel index (--seed-index)
  double radius = 0.0;                    // seed sphere radius, mm; 0 = automatic
  int level = 1;                          // subdivisions of the icosahedron seed (20 * 4^level faces)
  std::string mesh;                       // seed mesh file (--seed-mesh)
};

struct Options {
  std::string input;                      // image file or DICOM folder; empty = embedded phantom
  std::string output;                     // mesh file; empty = <input name>-gdm.ply
  std::string report;                     // JSON report file; empty = none
  std::string series;                     // DICOM series UID; empty = the one with most slices
  double smooth_mm = 0.0;                 // Gaussian sigma, mm; 0 = no smoothing
  bool has_roi = false;                   // crop to roi before anything else
  std::array<long, 6> roi{0, 0, 0, 0, 0, 0};  // i0,j0,k0,i1,j1,k1 (inclusive voxel indices)
  bool threshold_otsu = true;             // T by Otsu's method (default), else threshold_value
  bool threshold_given = false;           // --threshold was on the command line
  double threshold_value = 0.0;           // T of eq. 2 in the image's units (HU for CT)
  SeedOptions seed;
  gdm::DeformOptions deform;              // the core options (threshold and polarity set from above)
  bool allow_border = false;              // accept a model that touches the volume border
  bool quiet = false;                     // no progress, no summary
  bool help = false;
  bool version = false;
};

// One command-line option. `set` parses a value into the options (throws
// UsageError naming the option); `get` renders the current value as a JSON
// literal (used for the report and, on default options, for --help).
struct OptionSpec {
  std::string name;       // "--a0"
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
