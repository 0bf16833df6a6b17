// gdm: from a scan (DICOM, NIfTI, NRRD, MetaImage, VTK) to a closed mesh and
// a report, with itk::GeometricallyDeformedModelImageToMeshFilter.
//
//   gdm [options] [INPUT]        (gdm --help lists every option)
//
// ITK headers come first in this translation unit (see the build notes).
#include "image_input.h"
#include "preprocess.h"
#include "run_model.h"
#include "seeding.h"

#include <chrono>
#include <cmath>
#include <exception>
#include <iostream>
#include <new>
#include <sstream>

#include "cli_errors.h"
#include "cli_options.h"
#include "default_input.h"
#include "mesh_writers.h"
#include "wrap_command.h"
#include "progress.h"
#include "report.h"

namespace gdm_cli {
namespace {

std::string point_text(const std::array<double, 3>& p) {
  std::ostringstream s;
  s.precision(6);
  s << "(" << p[0] << ", " << p[1] << ", " << p[2] << ")";
  return s.str();
}

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

std::string volume_extent_text(const Image* image) {
  const auto region = image->GetLargestPossibleRegion();
  std::array<long, 3> hi{};
  for (unsigned int d = 0; d < 3; ++d) hi[d] = region.GetIndex(d) + static_cast<long>(region.GetSize(d)) - 1;
  return point_text(index_to_point(image, {region.GetIndex(0), region.GetIndex(1), region.GetIndex(2)})) + " to " +
         point_text(index_to_point(image, hi)) + " mm";
}

// Checks that a seed sphere lies inside the volume and its centre on the object side of T.
void check_seed_sphere(const Image* image, const std::array<double, 3>& c, double radius, const Options& o,
                       double threshold, const std::string& what) {
  if (!inside_volume(image, c))
    throw UsageError(what + " " + point_text(c) + " mm is outside the volume (voxel centres span " +
                     volume_extent_text(image) + ")");
  for (int d = 0; d < 3; ++d)
    for (const double sign : {-1.0, 1.0}) {
      auto p = c;
      p[d] += sign * radius;
      if (!inside_volume(image, p))
        throw UsageError("the seed sphere (centre " + point_text(c) + " mm, radius " + std::to_string(radius) +
                         " mm) extends outside the volume: use a smaller --seed-radius");
    }
  if (o.deform.mode == gdm::Mode::grow) {
    const double v = value_at(image, c);
    const bool darker = o.deform.polarity == gdm::Polarity::object_darker;
    if (darker ? !(v < threshold) : !(v > threshold)) {
      std::ostringstream s;
      s << what << " " << point_text(c) << " mm is not inside the object: its value " << v << " is "
        << (darker ? "not below" : "not above") << " the threshold " << threshold << " (object "
        << (darker ? "darker" : "brighter") << "); check --seed, --threshold and --polarity";
      throw UsageError(s.str());
    }
  }
}

int run(const Options& options_in, RunRecord& record) {
  const auto start = std::chrono::steady_clock::now();
  Options options = options_in;
  std::ostream& out = std::cout;
  const bool talk = !options.quiet;

  // Input.
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
      options.threshold_otsu = false;
      options.threshold_value = kPhantomThreshold;
    }
  }
  if (options.output.empty()) options.output = default_output(phantom ? "phantom" : options.input);
  if (!is_supported_mesh_extension(options.output))
    throw UsageError("--output " + options.output + ": unknown mesh extension (use .ply, .obj, .stl, .off or .vtk)");

  Image::Pointer image = read_input(options.input, options.series, record.input, out);
  const Image::Pointer original = image;  // --seed-index counts in its voxels, also with --roi
  if (talk) out << input_text(record.input) << std::flush;

  // Preprocessing.
  if (options.has_roi) {
    image = crop(image, options.roi);
    if (talk) out << "  cropped to " << volume_extent_text(image) << "\n";
  }
  if (options.smooth_mm > 0.0) {
    image = smooth(image, options.smooth_mm);
    if (talk) out << "  smoothed with a Gaussian of sigma " << options.smooth_mm << " mm\n";
  }
  InputInfo processed;
  describe_image(image, processed);
  double threshold = options.threshold_value;
  record.threshold_source = phantom && !options.threshold_given ? "phantom default" : "given";
  if (options.threshold_otsu) {
    threshold = otsu_threshold(image);
    record.threshold_source = "otsu";
  }
  record.threshold = threshold;
  if (!(threshold > processed.minimum && threshold < processed.maximum)) {
    std::ostringstream s;
    s << "the threshold " << threshold << " is outside the value range [" << processed.minimum << ", "
      << processed.maximum << "] of the " << (options.smooth_mm > 0.0 || options.has_roi ? "preprocessed " : "")
      << "volume";
    throw UsageError(s.str());
  }
  const bool darker = options.deform.polarity == gdm::Polarity::object_darker;
  if (talk)
    out << "threshold " << threshold << " (" << record.threshold_source << "), object "
        << (darker ? "darker" : "brighter") << ", mode " << (options.deform.mode == gdm::Mode::grow ? "grow" : "shrink")
        << "\n";

  // Seed.
  ModelSeed seed;
  seed.level = options.seed.level;
  const double voxel = voxel_size(image);
  const double manual_radius = options.seed.radius > 0.0 ? options.seed.radius : 2.0 * voxel;
  switch (options.seed.kind) {
    case SeedKind::automatic:
      if (options.deform.mode == gdm::Mode::shrink) {
        seed.use_mesh = true;
        seed.mesh = volume_box(image);
        record.seed_source = "box";
        if (talk) out << "seed: a box one voxel inside the volume (shrink mode)\n";
      } else {
        const AutoSeed a = find_auto_seed(image, threshold, darker);
        seed.center = a.center;
        seed.radius = options.seed.radius > 0.0 ? options.seed.radius : a.radius;
        record.seed_source = "auto";
        record.seed_depth = a.depth;
        record.seed_region_voxels = a.region_voxels;
        record.seed_regions = a.regions;
        if (options.seed.radius > 0.0) check_seed_sphere(image, seed.center, seed.radius, options, threshold, "the automatic seed");
        if (talk)
          out << "seed: auto, centre " << point_text(a.center) << " mm (voxel " << a.index[0] << ", " << a.index[1]
              << ", " << a.index[2] << "), radius " << seed.radius << " mm; the largest of " << a.regions
              << " object regions (" << a.region_voxels << " voxels), " << a.depth << " mm deep\n";
      }
      break;
    case SeedKind::point:
      seed.center = options.seed.point;
      seed.radius = manual_radius;
      record.seed_source = "point";
      check_seed_sphere(image, seed.center, seed.radius, options, threshold, "--seed");
      break;
    case SeedKind::index: {
      const auto region = original->GetLargestPossibleRegion();
      for (unsigned int d = 0; d < 3; ++d)
        if (options.seed.index[d] < 0 || options.seed.index[d] >= static_cast<long>(region.GetSize(d)))
          throw UsageError("--seed-index " + std::to_string(options.seed.index[0]) + "," +
                           std::to_string(options.seed.index[1]) + "," + std::to_string(options.seed.index[2]) +
                           " is outside the volume (" + std::to_string(region.GetSize(0)) + " x " +
                           std::to_string(region.GetSize(1)) + " x " + std::to_string(region.GetSize(2)) +
                           " voxels, indices from 0)");
      seed.center = index_to_point(original, {region.GetIndex(0) + options.seed.index[0],
                                           region.GetIndex(1) + options.seed.index[1],
                                           region.GetIndex(2) + options.seed.index[2]});
      seed.radius = manual_radius;
      record.seed_source = "index";
      check_seed_sphere(image, seed.center, seed.radius, options, threshold, "--seed-index");
      break;
    }
    case SeedKind::mesh:
      seed.use_mesh = true;
      seed.mesh = read_seed_mesh(options.seed.mesh);
      record.seed_source = "mesh";
      for (const auto& p : seed.mesh.points)
        if (!inside_volume(image, p))
          throw UsageError("--seed-mesh " + options.seed.mesh + ": the point " + point_text(p) +
                           " mm is outside the volume (" + volume_extent_text(image) + ")");
      if (talk) out << "seed: " << options.seed.mesh << ", " << seed.mesh.faces.size() << " faces\n";
      break;
  }
  if (!seed.use_mesh) {
    record.seed_center = seed.center;
    record.seed_radius = seed.radius;
    if (talk && options.seed.kind != SeedKind::automatic)
      out << "seed: centre " << point_text(seed.center) << " mm, radius " << seed.radius << " mm\n";
  }

  // The model.
  gdm::DeformOptions deform = options.deform;
  deform.threshold = threshold;
  ProgressPrinter printer(options.quiet);
  if (talk) out << std::flush;
  ModelResult result;
  try {
    result = run_model(image, deform, seed,
                       [&](const CycleFigures& c) { printer.cycle(c); });
  } catch (...) {
    printer.finish();
    throw;
  }
  printer.finish();
  record.model = result.stats;
  record.mesh = measure_mesh(result.mesh);
  record.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  std::string failure;
  if (result.stats.border_vertices > 0 && !options.allow_border)
    failure = "the model reached the volume border (" + std::to_string(result.stats.border_vertices) +
              " vertices within a voxel of it): it leaked out of the object. Check --polarity (is the object " +
              (darker ? "darker" : "brighter") + " than T?) and --threshold, or pass --allow-border if the object "
              "really touches the border";
  else if (result.stats.stop_reason == gdm::to_string(gdm::StopReason::face_limit))
    failure = "the model grew past --max-faces " + std::to_string(deform.max_faces) +
              " faces: it probably leaked; check --polarity and --threshold, or raise --max-faces";
  else if (!record.mesh.closed || !record.mesh.manifold)
    failure = "the model is not a closed 2-manifold mesh (a bug: please report it)";
  if (!failure.empty()) {
    record.status = failure;
    record.exit_code = exit_model_failed;
    if (talk) out << summary_text(record);
    if (!options.report.empty()) write_text_file(report_json(record, options), options.report);
    throw ModelError(failure);
  }
  if (result.stats.stop_reason == gdm::to_string(gdm::StopReason::max_cycles))
    std::cerr << "gdm: warning: stopped at --max-cycles " << deform.max_cycles << " before converging\n";

  write_mesh(result.mesh, options.output);
  record.output = options.output;
  record.status = "ok";
  record.exit_code = exit_ok;
  record.total_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (talk) out << summary_text(record);
  if (!options.report.empty()) {
    write_text_file(report_json(record, options), options.report);
    if (talk) out << "wrote " << options.report << "\n";
  }
  return exit_ok;
}

}  // namespace
}  // namespace gdm_cli

int main(int argc, char* argv[]) {
  using namespace gdm_cli;
  if (argc >= 2 && std::string(argv[1]) == "wrap") return wrap_command(argc, argv);  // wrap_command.h
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
  } catch (const std::bad_alloc&) {
    std::cerr << "gdm: error: out of memory\n";
    return exit_internal;
  } catch (const std::exception& e) {
    std::cerr << "gdm: internal error: " << e.what() << "\n";
    return exit_internal;
  }
}
