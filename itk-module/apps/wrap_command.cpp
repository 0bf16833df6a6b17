#include "wrap_command.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "cli_errors.h"
#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/mesh_io.h"
#include "gdm/shrink_wrap.h"
#include "json_writer.h"
#include "mesh_writers.h"
#include "progress.h"

namespace gdm_cli {
namespace {

const char* const kUsage =
    "usage: gdm wrap IN.(ply|obj|off|stl|vtk) -o OUT.(ply|obj|off|stl|vtk) --tolerance D\n"
    "                [--cell-size C] [--bridge W] [--coverage-rounds N] [--time-limit S] [--memory-limit GB]\n"
    "                [--estimate] [--quiet] [--report R.json]\n"
    "\n"
    "A closed, 2-manifold, genus-0, self-intersection-free mesh around every triangle of IN\n"
    "(open meshes, several pieces, noise), shrunk from a sphere; no face of it touches IN.\n"
    "  -o, --output FILE        the wrap (.ply keeps the per-vertex generation)\n"
    "  --tolerance D            wanted largest distance of IN from the wrap, mm (> 0, required)\n"
    "  --cell-size C            distance-field cell, mm (<= D; default D / 3)\n"
    "  --bridge W, --gap W      cap openings up to about W mm wide with no input under them (holes)\n"
    "                           smoothly, the envelope of balls of diameter W, instead of sinking into\n"
    "                           them (mm; default 0 = off; e.g. 10 x D)\n"
    "  --coverage-rounds N      refinement rounds where IN lies beyond 90% of D (default 4, 0 = off)\n"
    "  --time-limit S           refuse, before starting, a wrap estimated to take longer (s; default 180,\n"
    "                           0 = no limit)\n"
    "  --memory-limit GB        refuse, before starting, a wrap estimated to need more memory (GiB;\n"
    "                           default 2, 0 = no limit)\n"
    "  --estimate               print the estimated time, memory, grid and faces, and stop\n"
    "  --quiet                  no progress and no notes\n"
    "  --report FILE            a JSON report of the options and the result\n"
    "Exit codes: 0 written, 2 bad usage or refused as too costly (the estimate above a limit),\n"
    "3 unreadable input, 4 the wrap failed, 5 not written.\n";

struct WrapArgs {
  std::string input, output, report;
  double tolerance = std::nan("");
  double cell_size = std::nan("");  // default tolerance / 3
  int coverage_rounds = 4;
  double bridge = 0.0;  // mm, 0 = off
  double time_limit = gdm::WrapOptions{}.time_limit;      // s, 0 = none
  double memory_limit = gdm::WrapOptions{}.memory_limit;  // GiB, 0 = none
  bool estimate = false;
  bool quiet = false;
  bool help = false;
};

double number(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || !std::isfinite(v))
    throw UsageError(option + " needs a number, got '" + text + "'");
  return v;
}

// True when both paths name the same file (or would: the same absolute path).
bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a, ec), ec) == fs::weakly_canonical(fs::absolute(b, ec), ec);
}

WrapArgs parse(int argc, char* argv[]) {
  WrapArgs a;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw UsageError(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "-h" || arg == "--help") a.help = true;
    else if (arg == "-o" || arg == "--output") a.output = value();
    else if (arg == "--tolerance") a.tolerance = number(arg, value());
    else if (arg == "--cell-size") a.cell_size = number(arg, value());
    else if (arg == "--bridge" || arg == "--gap") {  // the wrap's gap size, as the model's --gap
      a.bridge = number(arg, value());
      if (a.bridge < 0) throw UsageError(arg + " must be >= 0 (mm; 0 = off), got " + std::string(argv[i]));
    }
    else if (arg == "--coverage-rounds") {
      const double n = number(arg, value());
      if (n != std::floor(n) || n < 0 || n > 1000) throw UsageError("--coverage-rounds must be an integer in [0, 1000]");
      a.coverage_rounds = static_cast<int>(n);
    } else if (arg == "--time-limit" || arg == "--memory-limit") {
      const double v = number(arg, value());
      if (v < 0) throw UsageError(arg + " must be >= 0 (0 = no limit), got " + argv[i]);
      (arg == "--time-limit" ? a.time_limit : a.memory_limit) = v;
    } else if (arg == "--estimate") a.estimate = true;
    else if (arg == "--quiet") a.quiet = true;
    else if (arg == "--report") a.report = value();
    else if (!arg.empty() && arg[0] == '-') throw UsageError("unknown option '" + arg + "'");
    else if (a.input.empty()) a.input = arg;
    else throw UsageError("more than one input mesh ('" + a.input + "', '" + arg + "')");
  }
  if (a.help) return a;
  if (a.input.empty()) throw UsageError("no input mesh");
  if (a.output.empty() && !a.estimate) throw UsageError("no output mesh (-o OUT.ply)");
  if (!is_supported_mesh_extension(a.input))
    throw UsageError("cannot read '" + a.input + "': unknown mesh extension (use .ply, .obj, .off, .stl or .vtk)");
  if (!a.output.empty() && !is_supported_mesh_extension(a.output))
    throw UsageError("cannot write '" + a.output + "': unknown mesh extension (use .ply, .obj, .stl, .off or .vtk)");
  if (std::isnan(a.tolerance)) throw UsageError("--tolerance is required (mm)");
  if (!(a.tolerance > 0)) throw UsageError("--tolerance must be > 0 (mm), got " + std::to_string(a.tolerance));
  if (std::isnan(a.cell_size)) a.cell_size = a.tolerance / 3.0;
  if (!(a.cell_size > 0)) throw UsageError("--cell-size must be > 0 (mm), got " + std::to_string(a.cell_size));
  if (a.cell_size > a.tolerance) throw UsageError("--cell-size must be <= --tolerance");
  // No output may overwrite the input or the other output.
  if (!a.output.empty() && same_file(a.output, a.input)) throw UsageError("--output " + a.output + " is the input: gdm never overwrites its input");
  if (!a.report.empty() && same_file(a.report, a.input))
    throw UsageError("--report " + a.report + " is the input: gdm never overwrites its input");
  if (!a.report.empty() && !a.output.empty() && same_file(a.report, a.output))
    throw UsageError("--report and --output name the same file " + a.output);
  return a;
}

std::string yes_no(bool b) { return b ? "yes" : "no"; }

std::string estimate_json(const gdm::WrapEstimate& e) {
  JsonObject o;
  o.add("grid", "[" + std::to_string(e.grid[0]) + ", " + std::to_string(e.grid[1]) + ", " + std::to_string(e.grid[2]) + "]")
      .add("cells", json_number(e.cells))
      .add("faces", json_number(std::round(e.faces)))
      .add("cycles", json_number(std::round(e.cycles)))
      .add("seconds", json_number(e.seconds))
      .add("bytes", json_number(std::round(e.bytes)));
  return o.str();
}

// The core's refusal in the command's words.
std::string command_words(std::string message) {
  const std::string api = "(time_limit, memory_limit; 0 = no limit)";
  const auto at = message.find(api);
  if (at != std::string::npos) message.replace(at, api.size(), "(--time-limit S, --memory-limit GB; 0 = no limit)");
  const std::string cell = "Raise the cell size";
  const auto c = message.find(cell);
  if (c != std::string::npos) message.replace(c, cell.size(), "Raise --cell-size");
  return message;
}

std::string report_json(const WrapArgs& a, std::size_t input_triangles, const gdm::WrapEstimate& estimate,
                        const gdm::WrapResult& r) {
  JsonObject options, result;
  options.add("input", json_string(a.input))
      .add("output", json_string(a.output))
      .add("tolerance_mm", json_number(a.tolerance))
      .add("cell_size_mm", json_number(a.cell_size))
      .add("bridge_mm", json_number(a.bridge))
      .add("coverage_rounds", json_number(a.coverage_rounds))
      .add("time_limit_s", json_number(a.time_limit))
      .add("memory_limit_gib", json_number(a.memory_limit));
  std::string notes = "[";
  for (std::size_t i = 0; i < r.notes.size(); ++i) notes += (i ? ", " : "") + json_string(r.notes[i]);
  notes += "]";
  result.add("input_triangles", json_number(input_triangles))
      .add("faces", json_number(r.report.faces))
      .add("vertices", json_number(r.report.vertices))
      .add("closed", json_bool(r.report.closed))
      .add("two_manifold", json_bool(r.report.two_manifold))
      .add("genus", json_number(r.report.genus))
      .add("self_intersections", json_number(r.report.self_intersections))
      .add("volume_mm3", json_number(r.report.volume))
      .add("farthest_input_distance_mm", json_number(r.farthest_input_distance))
      .add("farthest_wrap_distance_mm", json_number(r.farthest_wrap_distance))
      .add("coverage_rounds_done", json_number(r.coverage_rounds_done))
      .add("cycles", json_number(r.total_cycles))
      .add("stop_reason", json_string(gdm::to_string(r.deform.reason)))
      .add("notes", notes);
  JsonObject root;
  root.add("command", json_string("wrap"))
      .add("options", options.str())
      .add("estimate", estimate_json(estimate))
      .add("result", result.str());
  return root.str() + "\n";
}

int run(const WrapArgs& a) {
  std::vector<gdm::Triangle> input;
  try {
    input = gdm::read_triangles(a.input);
  } catch (const gdm::Error& e) {
    throw InputError(e.what());
  }
  gdm::WrapOptions o;
  o.tolerance = a.tolerance;
  o.cell_size = a.cell_size;
  o.coverage_rounds = a.coverage_rounds;
  o.bridge = a.bridge;
  o.time_limit = a.time_limit;
  o.memory_limit = a.memory_limit;
  gdm::WrapEstimate estimate;
  try {
    estimate = gdm::estimate_wrap(input, o);
  } catch (const gdm::InvalidOption& e) {
    throw UsageError(e.what());
  }
  if (a.estimate) {
    std::cout << "estimate for the wrap of " << a.input << " (" << input.size() << " triangles): " << estimate.text()
              << "\n";
    return exit_ok;
  }
  const bool within = (o.time_limit <= 0.0 || estimate.seconds <= o.time_limit) &&
                      (o.memory_limit <= 0.0 || estimate.bytes <= o.memory_limit * 1073741824.0);
  if (!a.quiet && within) std::cerr << "gdm wrap: estimate: " << estimate.text() << "\n";
  ProgressPrinter printer(a.quiet);
  const int stages = o.global_refinements + 1 + o.coverage_rounds;
  const gdm::DeformObserver observer = [&](const gdm::CycleReport& c) {
    CycleFigures f;
    f.cycle = static_cast<std::size_t>(c.cycle);
    f.stage = static_cast<std::size_t>(c.stage);
    f.vertices = c.vertices;
    f.faces = c.faces;
    f.moving = c.moved;
    f.progress = std::min(0.99, static_cast<double>(c.stage) / stages);
    printer.cycle(f);
    return true;
  };
  gdm::WrapResult r;
  try {
    r = gdm::shrink_wrap(input, o, observer);
  } catch (const gdm::WrapTooCostly& e) {
    printer.finish();
    throw CliError(exit_usage, command_words(e.what()));  // refused before any work: no usage text
  } catch (const gdm::InvalidOption& e) {
    printer.finish();
    throw UsageError(e.what());
  } catch (const gdm::Error& e) {
    printer.finish();
    throw ModelError(std::string("the wrap failed: ") + e.what());
  }
  printer.finish();
  if (!a.quiet)
    for (const auto& n : r.notes) std::cerr << "gdm wrap: " << n << "\n";
  // The report first, then the mesh (as gdm does): a failed report leaves no
  // mesh, a failed mesh (or an interrupt while it is written) no report.
  if (!a.report.empty()) write_text_file(report_json(a, input.size(), estimate, r), a.report);
  gdm::RemoveOnInterrupt report_only_with_the_mesh(a.report);
  try {
    gdm::write_mesh(r.mesh, a.output);
  } catch (const gdm::Error& e) {
    if (!a.report.empty()) std::remove(a.report.c_str());
    throw OutputError(e.what());
  }
  report_only_with_the_mesh.release();
  const auto& m = r.report;
  std::cout << "wrap of " << a.input << " (" << input.size() << " triangles) written to " << a.output << "\n"
            << "  faces " << m.faces << ", vertices " << m.vertices << "\n"
            << "  closed " << yes_no(m.closed) << ", 2-manifold " << yes_no(m.two_manifold) << ", genus " << m.genus
            << ", self-intersections " << m.self_intersections << "\n"
            << "  farthest input distance " << r.farthest_input_distance << " mm (tolerance " << a.tolerance
            << " mm), farthest wrap distance " << r.farthest_wrap_distance << " mm\n";
  if (r.farthest_input_distance > a.tolerance)
    std::cerr << "gdm wrap: warning: some input lies farther than the tolerance from the wrap\n";
  return exit_ok;
}

}  // namespace

int wrap_command(int argc, char* argv[]) {
  try {
    const WrapArgs a = parse(argc, argv);
    if (a.help) {
      std::cout << kUsage;
      return exit_ok;
    }
    return run(a);
  } catch (const CliError& e) {
    std::cout << std::flush;
    std::cerr << "gdm wrap: error: " << e.what() << "\n";
    if (dynamic_cast<const UsageError*>(&e) != nullptr) std::cerr << kUsage;
    return e.code();
  } catch (const std::bad_alloc&) {
    std::cerr << "gdm wrap: error: out of memory\n";
    return exit_model_failed;
  } catch (const std::exception& e) {
    std::cerr << "gdm wrap: internal error: " << e.what() << "\n";
    return exit_internal;
  }
}

}  // namespace gdm_cli
