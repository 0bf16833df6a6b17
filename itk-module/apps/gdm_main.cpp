// gdm: from a scan (DICOM, NIfTI, NRRD, MetaImage, VTK) to a closed mesh and
// a report, through the core's pipeline (gdm/pipeline.h): the same code path
// as the ITK filter, the MeshLab filters and Python.
//
//   gdm [options] [INPUT]        (gdm --help lists every option)
//   gdm wrap MESH -o OUT ...     (shrink-wrap a triangle mesh; gdm wrap --help)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <iostream>
#include <new>
#include <sstream>

#include <sys/resource.h>

#include "cli_errors.h"
#include "cli_options.h"
#include "default_input.h"
#include "gdm/mesh_io.h"
#include "gdm/pipeline.h"
#include "image_input.h"
#include "mesh_writers.h"
#include "progress.h"
#include "report.h"
#include "wrap_command.h"

namespace gdm_cli {
namespace {

// <input name without folder and extension>-gdm.ply in the current folder.
std::string default_output(const std::string& input) {
  std::string name = input;
  while (name.size() > 1 && name.back() == '/') name.pop_back();
  const auto slash = name.find_last_of('/');
  if (slash != std::string::npos) name = name.substr(slash + 1);
  const std::string ext = file_extension(name);
  if (!ext.empty()) name = name.substr(0, name.size() - ext.size());
  if (name.empty() || name == "." || name == "..") name = "gdm";
  return name + "-gdm.ply";
}

// True when both paths name the same file (or would: the same absolute path).
bool same_file(const std::string& a, const std::string& b) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec)) return fs::equivalent(a, b, ec);
  return fs::weakly_canonical(fs::absolute(a, ec), ec) == fs::weakly_canonical(fs::absolute(b, ec), ec);
}

// Before any work: no output may overwrite the input or the other output, and
// the output folders must exist (a typo in -o must not cost the whole run).
void check_output_paths(const Options& o) {
  namespace fs = std::filesystem;
  const auto check_folder = [](const std::string& path, const char* what) {
    const fs::path parent = fs::path(path).parent_path();
    std::error_code ec;
    if (!parent.empty() && !fs::is_directory(parent, ec))
      throw OutputError(std::string("cannot write ") + path + ": the folder " + parent.string() + " of the " + what +
                        " does not exist");
  };
  check_folder(o.output, "output");
  if (!o.report.empty()) check_folder(o.report, "report");
  if (!o.input.empty() && same_file(o.output, o.input))
    throw UsageError("--output " + o.output + " is the input: gdm never overwrites its input");
  if (!o.report.empty() && !o.input.empty() && same_file(o.report, o.input))
    throw UsageError("--report " + o.report + " is the input: gdm never overwrites its input");
  if (!o.report.empty() && same_file(o.report, o.output))
    throw UsageError("--report and --output name the same file " + o.output);
}

// The choices the pipeline made before the model runs (gdm::describe_choices).
std::string choices_text(const Options& o, const gdm::PreparedModel& p, bool phantom_default) {
  std::ostringstream s;
  const gdm::PipelineOptions& po = o.pipeline;
  if (po.use_roi) s << "  cropped to the voxel box " << po.roi.lo[0] << "," << po.roi.lo[1] << "," << po.roi.lo[2]
                    << " to " << po.roi.hi[0] << "," << po.roi.hi[1] << "," << po.roi.hi[2] << "\n";
  if (po.smooth > 0.0) s << "  smoothed with a Gaussian of sigma " << po.smooth << " mm\n";
  for (std::string line : gdm::describe_choices(p)) {
    const auto given = line.find("(given)");
    if (phantom_default && given != std::string::npos) line.replace(given, 7, "(phantom default)");
    if (p.choices.seed_source == "mesh" && line.rfind("seed: ", 0) == 0) line = "seed: " + o.seed_mesh + ", " + line.substr(6);
    s << line << "\n";
  }
  return s.str();
}

// The seed mesh of --seed-mesh (gdm::read_mesh: .ply, .obj, .off, .stl, .vtk).
gdm::Mesh read_seed_mesh(const std::string& path) {
  try {
    return gdm::read_mesh(path);
  } catch (const gdm::Error& e) {
    throw InputError("cannot read the seed mesh " + path + ": " + e.what());
  }
}

void record_choices(const gdm::PipelineChoices& c, bool phantom_default, RunRecord& record) {
  record.threshold = c.threshold;
  record.threshold_source = phantom_default ? "phantom default" : c.threshold_source;
  record.seed_source = c.seed_source;
  record.seed_center = {c.seed_center.x(), c.seed_center.y(), c.seed_center.z()};
  record.seed_radius = c.seed_radius;
  if (c.seed_source == "auto") {
    record.seed_depth = c.auto_seed.depth;
    record.seed_region_voxels = c.auto_seed.region_voxels;
    record.seed_regions = c.auto_seed.regions;
  }
  record.cut_by_scan = c.cut_by_scan;
  record.border_fraction = c.border.fraction();
  record.border_sides = c.border.sides_text();
}

void record_model(const gdm::PipelineResult& r, RunRecord& record) {
  record.model = r.deform;
  record.model_seconds = r.seconds;
  record.check_seconds = r.check_seconds;
  record.mesh = r.report;
  record.contacts = r.contacts;
  record_extent(r.mesh, record);
}

// The process's largest resident set so far, MiB (Linux: ru_maxrss in KiB);
// 0 when the system does not say.
double peak_memory_mb() {
  struct rusage usage {};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0.0;
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// The run's time and peak memory so far, into the record.
void record_cost(std::chrono::steady_clock::time_point start, RunRecord& record) {
  record.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  record.peak_memory_mb = peak_memory_mb();
}

int run(const Options& options_in, RunRecord& record) {
  const auto start = std::chrono::steady_clock::now();
  Options options = options_in;
  std::ostream& out = std::cout;
  const bool talk = !options.quiet;

  // Input and outputs.
  bool phantom = false;
  if (options.input.empty()) {
    options.input = find_phantom();
    if (options.input.empty()) {
      std::string where;
      for (const auto& c : phantom_candidates()) where += "\n  " + c;
      throw InputError("no input given and the embedded phantom was not found; looked for:" + where);
    }
    phantom = true;
    if (!options.threshold_given) {
      options.pipeline.threshold_otsu = false;
      options.pipeline.threshold = kPhantomThreshold;
    }
  }
  if (options.output.empty()) options.output = default_output(phantom ? "phantom" : options.input);
  if (!is_supported_mesh_extension(options.output))
    throw UsageError("--output " + options.output + ": unknown mesh extension (use .ply, .obj, .stl, .off or .vtk)");
  check_output_paths(options);
  if (options.pipeline.seed.kind == gdm::SeedKind::mesh) options.pipeline.seed.mesh = read_seed_mesh(options.seed_mesh);

  const auto memory_limit = static_cast<std::uint64_t>(std::ceil(options.memory_limit_gb * 1073741824.0));
  const gdm::Volume volume = read_input(options.input, options.series, memory_limit, record.input, out);
  if (talk) out << input_text(record.input) << std::flush;

  // Preprocessing, threshold and seed (gdm::prepare_model), then the model.
  const gdm::PreparedModel prepared = gdm::prepare_model(volume, options.pipeline);
  record_choices(prepared.choices, phantom && !options.threshold_given, record);
  if (talk) out << choices_text(options, prepared, phantom && !options.threshold_given) << std::flush;

  ProgressPrinter printer(options.quiet);
  gdm::PipelineResult result;
  try {
    result = gdm::run_model(prepared, [&](const gdm::PipelineProgress& p) {
      printer.cycle({static_cast<std::size_t>(p.cycle.cycle), static_cast<std::size_t>(p.cycle.stage),
                     p.cycle.vertices, p.cycle.faces, p.cycle.moved, p.fraction});
      return true;
    });
  } catch (...) {
    printer.finish();
    throw;
  }
  printer.finish();
  record_model(result, record);
  record.voxel_seed_possible = gdm::voxel_seed_applies(prepared.deform);
  record_cost(start, record);

  if (!result.failure.empty()) {
    std::string failure = result.failure;
    if (result.deform.border_vertices > 0 && !prepared.allow_border)  // said with the command's flags
      failure = "the model reached the volume border (" + std::to_string(result.deform.border_vertices) +
                " vertices within a voxel of it): it leaked out of the object. Check --polarity (is the object " +
                (prepared.deform.polarity == gdm::Polarity::object_darker ? "darker" : "brighter") +
                " than T?) and --threshold, or pass --allow-border if the object really touches the border";
    record.status = failure;
    record.exit_code = exit_model_failed;
    if (talk) out << summary_text(record);
    if (!options.report.empty()) write_text_file(report_json(record, options), options.report);
    throw ModelError(failure);
  }
  if (result.deform.reason == gdm::StopReason::max_cycles)
    std::cerr << "gdm: warning: stopped at --max-cycles " << prepared.deform.max_cycles << " before converging\n";

  // The report first: a failed report write then leaves no new mesh behind.
  record.output = options.output;
  record.status = "ok";
  record.exit_code = exit_ok;
  record_cost(start, record);
  if (!options.report.empty()) write_text_file(report_json(record, options), options.report);
  // Until the mesh is written, the report goes with it: on a failed write, and
  // on SIGINT, SIGTERM or SIGHUP (gdm::RemoveOnInterrupt).
  gdm::RemoveOnInterrupt report_only_with_the_mesh(options.report);
  try {
    gdm_cli::write_mesh(result.mesh, options.output);
  } catch (...) {
    if (!options.report.empty()) std::remove(options.report.c_str());
    throw;
  }
  report_only_with_the_mesh.release();
  if (talk) {
    out << summary_text(record);
    if (!options.report.empty()) out << "wrote " << options.report << "\n";
  }
  return exit_ok;
}

// A core error as the command's: its exit code, and the option in the command's spelling.
CliError cli_error(const gdm::Error& e) {
  if (const auto* option = dynamic_cast<const gdm::InvalidOption*>(&e)) {
    std::string message = e.what();
    if (!option->option().empty()) {
      std::string flag = "--" + option->option();
      std::replace(flag.begin(), flag.end(), '_', '-');
      if (message.rfind(option->option() + " ", 0) == 0) message = flag + ":" + message.substr(option->option().size());
    }
    return UsageError(message);
  }
  if (dynamic_cast<const gdm::InvalidSeed*>(&e)) return UsageError(e.what());
  if (dynamic_cast<const gdm::InvalidVolume*>(&e) || dynamic_cast<const gdm::InvalidInput*>(&e))
    return InputError(e.what());
  return ModelError(e.what());
}

}  // namespace
}  // namespace gdm_cli

int main(int argc, char* argv[]) {
  using namespace gdm_cli;
  // SIGINT, SIGTERM, SIGHUP: remove the temporary file of a write in flight
  // (and the report written before its mesh), then end by that signal.
  gdm::remove_on_interrupt_install();
  if (argc > 1 && std::string(argv[1]) == "wrap") return wrap_command(argc, argv);  // wrap_command.h
  Options options;
  try {
    options = parse_arguments(argc, argv);
  } catch (const CliError& e) {
    std::cerr << "gdm: error: " << e.what() << "\n";
    return e.code();
  }
  if (options.help) {
    std::cout << help_text("gdm");
    return exit_ok;
  }
  if (options.version) {
    std::cout << "gdm " << GDM_VERSION << "\n";
    return exit_ok;
  }
  RunRecord record;
  try {
    return run(options, record);
  } catch (const CliError& e) {
    std::cout << std::flush;
    std::cerr << "gdm: error: " << e.what() << "\n";
    return e.code();
  } catch (const gdm::Error& core) {
    const CliError e = cli_error(core);
    std::cout << std::flush;
    std::cerr << "gdm: error: " << e.what() << "\n";
    return e.code();
  } catch (const std::bad_alloc&) {
    std::cerr << "gdm: error: out of memory\n";
    return exit_internal;
  } catch (const std::exception& e) {
    std::cerr << "gdm: internal error: " << e.what() << "\n";
    return exit_internal;
  }
}
