#include "gdm/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

#include "gdm/float_snap.h"
#include "gdm/seed.h"
#include "gdm/text.h"

namespace gdm {
namespace {

std::string num(double v) { return format_number(v); }

std::string point_text(const Vec3& p) { return "(" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + ")"; }

std::string index_text(const Index3& i) {
  return std::to_string(i[0]) + "," + std::to_string(i[1]) + "," + std::to_string(i[2]);
}

// The pipeline's own rows of the catalogue.
std::vector<OptionEntry<PipelineOptions>> make_pipeline_catalogue() {
  const char* pre = "Preprocessing";
  const char* seed = "Seed";
  auto row = [](const char* name, const char* group, const char* unit, const char* help, OptionType type, double lo,
                double hi, std::function<double(const PipelineOptions&)> get,
                std::function<void(PipelineOptions&, double)> set) {
    OptionEntry<PipelineOptions> e;
    e.name = name;
    e.group = group;
    e.unit = unit;
    e.help = help;
    e.type = type;
    e.lo = lo;
    e.hi = hi;
    e.get = std::move(get);
    e.set = std::move(set);
    if (type == OptionType::integer)  // no cast of a value an int cannot hold (NaN, inf, 1e300)
      e.set = [info = static_cast<const OptionInfo&>(e), set = std::move(e.set)](PipelineOptions& o, double v) {
        set(o, static_cast<double>(integer_field_value<int>(info, v)));
      };
    return e;
  };
  std::vector<OptionEntry<PipelineOptions>> rows = {
      row("smooth", pre, "mm", "Gaussian smoothing before the model (0 = none)", OptionType::real, 0.0, 1000.0,
          [](const PipelineOptions& o) { return o.smooth; }, [](PipelineOptions& o, double v) { o.smooth = v; }),
      row("seed_radius", seed, "mm", "seed sphere radius, at least 0.75 voxel (0 = auto: half the depth for the automatic seed, at least 0.75 voxel; else 2 voxels)",
          OptionType::real, 0.0, 1e6, [](const PipelineOptions& o) { return o.seed.radius; },
          [](PipelineOptions& o, double v) { o.seed.radius = v; }),
      // Level 5 already has 20,480 faces, smaller than any level of detail: the model could not move them.
      row("seed_level", seed, "", "subdivisions of the icosahedron seed (20*4^N faces)", OptionType::integer, 0, 4,
          [](const PipelineOptions& o) { return static_cast<double>(o.seed.level); },
          [](PipelineOptions& o, double v) { o.seed.level = static_cast<int>(v); }),
      row("time_limit", "Guarantees and limits", "s", "stop the model after this many seconds and report it as failed (0 = no limit)",
          OptionType::real, 0.0, 1e9, [](const PipelineOptions& o) { return o.time_limit; },
          [](PipelineOptions& o, double v) { o.time_limit = v; }),
      row("allow_border", "Output", "",
          "accept a model that reached the volume border; off: accepted only when the seed's object region meets "
          "the border on at most a quarter of it (an object the scan cuts), else the model has leaked",
          OptionType::boolean, 0, 1, [](const PipelineOptions& o) { return o.allow_border ? 1.0 : 0.0; },
          [](PipelineOptions& o, double v) { o.allow_border = v != 0.0; }),
  };
  for (auto& e : lift_options(&PipelineOptions::deform)) rows.push_back(std::move(e));
  return rows;
}

std::shared_ptr<const Volume> preprocess(const Volume& input, const PipelineOptions& o) {
  if (!o.use_roi && o.smooth == 0.0) return std::shared_ptr<const Volume>(&input, [](const Volume*) {});
  Volume v = o.use_roi ? crop(input, o.roi) : input;
  if (o.smooth > 0.0) v = gaussian_smooth(v, o.smooth);
  return std::make_shared<const Volume>(std::move(v));
}

double choose_threshold(const Volume& volume, const PipelineOptions& o, PipelineChoices& choices) {
  if (volume.voxel_count() == 0) throw InvalidVolume("the volume is empty");
  if (!(volume.max_value() > volume.min_value()))
    throw InvalidVolume("the volume is constant (every voxel is " + num(volume.min_value()) +
                        "): there is no boundary to find");
  const double t = o.threshold_otsu ? otsu_threshold(volume) : o.threshold;
  choices.threshold = t;
  choices.threshold_source = o.threshold_otsu ? "otsu" : "given";
  if (!(t > volume.min_value() && t < volume.max_value()))
    throw InvalidOption("threshold", "the threshold " + num(t) + " is outside the value range [" +
                                         num(volume.min_value()) + ", " + num(volume.max_value()) + "] of the " +
                                         (o.use_roi || o.smooth > 0.0 ? "preprocessed " : "") + "volume");
  return t;
}

// The sphere lies inside the volume and, when growing, its centre on the object side of T.
void check_seed_sphere(const Volume& volume, const Vec3& c, double radius, const DeformOptions& d,
                       const std::string& what) {
  if (!volume.contains(c)) {
    Vec3 lo = volume.to_physical(Vec3::Zero());
    Vec3 hi = volume.to_physical(Vec3(volume.dims()[0] - 1, volume.dims()[1] - 1, volume.dims()[2] - 1));
    throw InvalidSeed(what + " " + point_text(c) + " mm is outside the volume (voxel centres span " +
                      point_text(lo) + " to " + point_text(hi) + " mm)");
  }
  for (int axis = 0; axis < 3; ++axis)
    for (const double sign : {-1.0, 1.0}) {
      Vec3 p = c;
      p[axis] += sign * radius;
      if (!volume.contains(p))
        throw InvalidSeed("the seed sphere (centre " + point_text(c) + " mm, radius " + num(radius) +
                          " mm) extends outside the volume: use a smaller seed radius");
    }
  if (d.mode == Mode::grow) {
    const double v = volume.sample(c);
    const bool darker = d.polarity == Polarity::object_darker;
    if (darker ? !(v < d.threshold) : !(v > d.threshold))
      throw InvalidSeed(what + " " + point_text(c) + " mm is not inside the object: its value " + num(v) + " is " +
                        (darker ? "not below" : "not above") + " the threshold " + num(d.threshold) + " (object " +
                        (darker ? "darker" : "brighter") + "); check the seed, the threshold and the polarity");
  }
}

// Refuses a run whose faces could not even cover the volume's box within
// max_faces: the faces of the level of detail are at least half its area.
void check_face_budget(const Volume& volume, const DeformOptions& d) {
  Vec3 extent;
  for (int axis = 0; axis < 3; ++axis) extent[axis] = (volume.dims()[axis] - 1) * volume.spacing()[axis];
  const double box_area = 2.0 * (extent.x() * extent.y() + extent.y() * extent.z() + extent.z() * extent.x());
  const double face_area = d.lod_face_area * volume.voxel_size() * volume.voxel_size();
  const double faces = 2.0 * box_area / face_area;
  if (faces > static_cast<double>(d.max_faces))
    throw InvalidOption("lod_face_area",
                        "lod_face_area " + num(d.lod_face_area) + " voxel^2 (" + num(face_area) +
                            " mm^2, one voxel being the smallest spacing " + num(volume.voxel_size()) +
                            " mm) would need about " + num(faces) + " faces to cover the volume's box (" +
                            num(box_area) + " mm^2), above max_faces " + std::to_string(d.max_faces) +
                            ": raise lod_face_area or max_faces, or resample the volume (spacing " +
                            num(volume.spacing().x()) + " x " + num(volume.spacing().y()) + " x " +
                            num(volume.spacing().z()) + " mm)");
}

Mesh choose_seed(const Volume& input, const Volume& volume, const PipelineOptions& o, const DeformOptions& d,
                 PipelineChoices& choices) {
  const SeedOptions& s = o.seed;
  const double manual_radius = s.radius > 0.0 ? s.radius : 2.0 * volume.voxel_size();
  Vec3 center;
  double radius = manual_radius;
  switch (s.kind) {
    case SeedKind::automatic:
      if (d.mode == Mode::shrink) {
        choices.seed_source = "sphere";
        Mesh sphere = make_enclosing_sphere(volume, d.threshold, d.polarity);
        choices.seed_faces = sphere.n_faces();
        return sphere;
      } else {
        const AutoSeed a = find_auto_seed(volume, d.threshold, d.polarity);
        choices.seed_source = "auto";
        choices.auto_seed = a;
        center = a.center;
        radius = s.radius > 0.0 ? s.radius : a.radius;
        if (s.radius > 0.0) check_seed_sphere(volume, center, radius, d, "the automatic seed");
      }
      break;
    case SeedKind::point:
      choices.seed_source = "point";
      center = s.point;
      check_seed_sphere(volume, center, radius, d, "the seed centre");
      break;
    case SeedKind::index: {
      for (int axis = 0; axis < 3; ++axis)
        if (s.index[axis] < 0 || s.index[axis] >= input.dims()[axis])
          throw InvalidSeed("the seed index " + index_text(s.index) + " is outside the volume (" +
                            std::to_string(input.dims()[0]) + " x " + std::to_string(input.dims()[1]) + " x " +
                            std::to_string(input.dims()[2]) + " voxels, indices from 0)");
      choices.seed_source = "index";
      center = input.to_physical(Vec3(s.index[0], s.index[1], s.index[2]));
      check_seed_sphere(volume, center, radius, d, "the seed index " + index_text(s.index) + " at");
      break;
    }
    case SeedKind::mesh: {
      choices.seed_source = "mesh";
      Mesh mesh = prepare_seed_mesh(s.mesh, &choices.seed_reversed);
      for (auto v : mesh.vertices())
        if (!volume.contains(to_eigen(mesh.point(v))))
          throw InvalidSeed("the seed mesh's point " + point_text(to_eigen(mesh.point(v))) + " mm is outside the volume");
      choices.seed_faces = mesh.n_faces();
      return mesh;
    }
  }
  if (!(radius >= kMinGrowingSeedRadius * volume.voxel_size()))
    throw InvalidOption("seed_radius", "seed_radius " + num(radius) + " mm is below " + num(kMinGrowingSeedRadius) +
                                           " voxel (" + num(kMinGrowingSeedRadius * volume.voxel_size()) +
                                           " mm): a seed smaller than the model's smallest steps does not grow");
  choices.seed_center = center;
  choices.seed_radius = radius;
  Mesh sphere = make_geodesic_sphere(center, radius, s.level);
  choices.seed_faces = sphere.n_faces();
  return sphere;
}

// Why the result is not the object, or empty.
std::string failure_of(const DeformResult& r, const MeshReport& m, const DeformOptions& d, bool allow_border,
                       double seed_volume) {
  const bool darker = d.polarity == Polarity::object_darker;
  if (r.border_vertices > 0 && !allow_border)
    return "the model reached the volume border (" + std::to_string(r.border_vertices) +
           " vertices within a voxel of it): it leaked out of the object. Check the polarity (is the object " +
           (darker ? "darker" : "brighter") + " than T?) and the threshold, or allow the border if the object "
           "really touches it";
  if (r.reason == StopReason::face_limit)
    return "the model grew past " + std::to_string(d.max_faces) +
           " faces (max_faces): it probably leaked; check the polarity and the threshold, or raise max_faces";
  if (!m.closed || !m.two_manifold || m.self_intersections > 0 || !(m.volume > 0.0))
    return "the model breaks a guarantee (closed " + std::string(m.closed ? "yes" : "no") + ", manifold " +
           (m.two_manifold ? "yes" : "no") + ", " + std::to_string(m.self_intersections) +
           " self-intersecting face pairs, volume " + num(m.volume) + "): a bug, please report it";
  // A growing model that ends no larger than its seed did not grow: nothing
  // in it is the object's surface (a seed too small for the optimiser's
  // steps, or held by the guard from the first cycle).
  if (d.mode == Mode::grow && r.reason == StopReason::converged && seed_volume > 0.0 &&
      !(m.volume > 1.01 * seed_volume))
    return "the model did not grow from its seed (volume " + num(m.volume) + " mm^3, the seed's " + num(seed_volume) +
           " mm^3): try a larger seed radius or another seed";
  // The genus and components against the Euler characteristic, and the
  // components against what the topology built (topology.h).
  const int expected = 1 + static_cast<int>(r.cavity_components);
  if (!m.euler_consistent || (d.topology == Topology::exact && m.components != expected))
    return "the model breaks a guarantee (chi " + std::to_string(m.euler) + ", genus " + std::to_string(m.genus) +
           ", " + std::to_string(m.components) + " components, " + std::to_string(expected) +
           " expected by the topology): a bug, please report it";
  return {};
}

}  // namespace

const std::vector<OptionEntry<PipelineOptions>>& pipeline_option_catalogue() {
  static const std::vector<OptionEntry<PipelineOptions>> catalogue = make_pipeline_catalogue();
  return catalogue;
}

std::string options_markdown() {
  const PipelineOptions defaults;
  std::ostringstream s;
  s << "# gdm options\n\n"
    << "Generated from the catalogue of options (`common/include/gdm/option_catalogue.h`,\n"
    << "`gdm::pipeline_option_catalogue()`) by `gdm_options_markdown`; a test fails when this\n"
    << "file is stale. Every front end spells an option the same way: the C++ field and\n"
    << "the MeshLab parameter are the name, the `gdm` flag is `--name-with-dashes`.\n"
    << "The `gdm` command adds `--threshold T|otsu`, `--roi`, `--seed`, `--seed-index`,\n"
    << "`--seed-mesh`, `--series`, `--output`, `--report` and `--quiet` (see `gdm --help`).\n";
  std::string group;
  for (const auto& o : pipeline_option_catalogue()) {
    if (o.group != group) {
      group = o.group;
      s << "\n## " << group << "\n\n| name | flag | unit | default | range | what it does |\n|---|---|---|---|---|---|\n";
    }
    std::string flag = "--" + o.name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (!o.alias.empty()) flag += " (--" + o.alias + ")";
    s << "| `" << o.name << "` | `" << flag << "` | " << o.unit << " | " << value_text(o, o.get(defaults)) << " | "
      << range_text(o) << " | " << o.help << " |\n";
  }
  return s.str();
}

void validate(const PipelineOptions& o) {
  for (const auto& option : pipeline_option_catalogue()) check_option(option, option.get(o));
  if (!o.threshold_otsu && !std::isfinite(o.threshold))
    throw InvalidOption("threshold", "the threshold must be a finite number (or Otsu's), got " + num(o.threshold));
  if (o.seed.kind == SeedKind::point && !o.seed.point.allFinite())
    throw InvalidOption("seed", "the seed centre must be finite, got " + point_text(o.seed.point));
}

PreparedModel prepare_model(const Volume& input, const PipelineOptions& o) {
  validate(o);
  PreparedModel p;
  p.volume = preprocess(input, o);
  p.deform = o.deform;
  p.deform.threshold = choose_threshold(*p.volume, o, p.choices);
  validate(p.deform, *p.volume);
  check_face_budget(*p.volume, p.deform);
  p.seed = choose_seed(input, *p.volume, o, p.deform, p.choices);
  p.allow_border = o.allow_border;
  p.time_limit = o.time_limit;
  if (!o.allow_border && p.deform.mode == Mode::grow && p.choices.seed_source != "mesh") {
    // An object the scan cuts is no leak: its region meets the border on a
    // small part of it (border_contact.h), so the border is allowed up front.
    const Vec3 c = p.volume->to_continuous_index(p.choices.seed_center);
    const Index3 voxel{static_cast<int>(std::lround(c.x())), static_cast<int>(std::lround(c.y())),
                       static_cast<int>(std::lround(c.z()))};
    p.choices.border = measure_border_contact(*p.volume, voxel, p.deform.threshold, p.deform.polarity);
    p.choices.cut_by_scan = p.choices.border.cut_by_scan();
    p.allow_border = p.choices.cut_by_scan;
  }
  // A growing leak stops at its first contact with the border (a shrinking model starts there).
  p.deform.stop_at_border = !p.allow_border && p.deform.mode == Mode::grow;
  return p;
}

std::vector<std::string> describe_choices(const PreparedModel& p) {
  const PipelineChoices& c = p.choices;
  const bool darker = p.deform.polarity == Polarity::object_darker;
  std::vector<std::string> lines;
  lines.push_back("threshold " + num(c.threshold) + " (" + c.threshold_source + "), object " +
                  (darker ? "darker" : "brighter") + ", mode " + (p.deform.mode == Mode::grow ? "grow" : "shrink"));
  if (c.seed_source == "sphere") {
    lines.push_back("seed: a sphere through the corners of the box around the object's voxels (shrink mode, " +
                    std::to_string(c.seed_faces) + " faces; outside the volume counts as background)");
  } else if (c.seed_source == "auto") {
    const AutoSeed& a = c.auto_seed;
    lines.push_back("seed: auto, centre " + point_text(a.center) + " mm (voxel " + std::to_string(a.index[0]) + ", " +
                    std::to_string(a.index[1]) + ", " + std::to_string(a.index[2]) + "), radius " +
                    num(c.seed_radius) + " mm; the largest of " + std::to_string(a.regions) + " object regions (" +
                    std::to_string(a.region_voxels) + " voxels), " + num(a.depth) + " mm deep");
  } else if (c.seed_source == "mesh") {
    lines.push_back("seed: a mesh of " + std::to_string(c.seed_faces) + " faces" +
                    (c.seed_reversed ? " (reversed: it pointed inwards)" : ""));
  } else {
    lines.push_back("seed: centre " + point_text(c.seed_center) + " mm, radius " + num(c.seed_radius) + " mm");
  }
  if (c.cut_by_scan)
    lines.push_back("the object is cut by the scan: its region meets the volume's border at " + c.border.sides_text() +
                    ", " + num(100.0 * c.border.fraction()) +
                    " % of the border; the model is closed there (as with allow_border)");
  return lines;
}

ProgressEstimator::ProgressEstimator(int global_refinements, int max_cycles)
    : stages_(static_cast<double>(global_refinements + 1)), max_cycles_(static_cast<double>(max_cycles)) {}

double ProgressEstimator::update(const CycleReport& report) {
  if (report.stage != stage_) {
    stage_ = report.stage;
    stage_start_ = report.cycle;
  }
  const double in_stage = 1.0 - std::exp(-static_cast<double>(report.cycle - stage_start_ + 1) / 50.0);
  double estimate = (static_cast<double>(report.stage) + in_stage) / stages_;
  estimate = std::max(estimate, static_cast<double>(report.cycle) / max_cycles_);
  fraction_ = std::max(fraction_, std::min(estimate, 0.99));
  return fraction_;
}

PipelineResult run_model(const PreparedModel& p, const PipelineObserver& observer) {
  const auto start = std::chrono::steady_clock::now();
  PipelineResult r;
  r.mesh = p.seed;
  r.choices = p.choices;
  DeformObserver on_cycle;
  ProgressEstimator estimator(p.deform.global_refinements, p.deform.max_cycles);
  bool out_of_time = false;
  const auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  if (observer || p.time_limit > 0.0)
    on_cycle = [&](const CycleReport& c) {
      if (p.time_limit > 0.0 && elapsed() > p.time_limit) {
        out_of_time = true;
        return false;
      }
      return !observer || observer({c, estimator.update(c)});
    };
  r.deform = deform(r.mesh, *p.volume, p.deform, on_cycle);
  r.mesh.garbage_collection();
  if (out_of_time) {
    r.failure = "the model ran out of time (time_limit " + num(p.time_limit) + " s) after " +
                std::to_string(r.deform.cycles) + " cycles with " + std::to_string(r.mesh.n_faces()) + " faces";
  } else if (r.deform.reason != StopReason::cancelled) {
    const auto checks = std::chrono::steady_clock::now();
    r.report = measure(r.mesh, p.deform.threads);
    // A sphere's volume; a seed mesh may be larger than the object (local flip).
    const double seed_volume = p.choices.seed_source == "mesh" ? 0.0 : enclosed_volume(p.seed);
    r.failure = failure_of(r.deform, r.report, p.deform, p.allow_border, seed_volume);
    // Vertices the float snap could not place stay in double precision: the
    // model is checked as a float format stores it too (the file must keep
    // the guarantees the report states).
    if (r.failure.empty() && r.deform.float_refused > 0) {
      const std::size_t crossing = pairs_crossing_when_rounded(r.mesh, p.deform.threads);
      if (crossing > 0)
        r.failure = std::to_string(r.deform.float_refused) +
                    " vertices could not be moved to float points without making faces cross, and rounded to float "
                    "(as PLY, STL, MeshLab and itk::Mesh<float> store it) the model has " +
                    std::to_string(crossing) + " self-intersecting face pairs: a bug, please report it";
    }
    if (r.failure.empty()) {
      const Volume& volume = *p.volume;
      const double t = p.deform.threshold;
      const bool brighter = p.deform.polarity == Polarity::object_brighter;
      r.contacts = find_self_contacts(r.mesh, volume.voxel_size(), [&](const Vec3& x) {
        const double v = volume.sample(x);
        return brighter ? v > t : v < t;
      }, p.deform.threads);
    }
    r.check_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - checks).count();
  } else {
    r.failure = "cancelled";
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

PipelineResult extract_surface(const Volume& volume, const PipelineOptions& options,
                               const PipelineObserver& observer) {
  return run_model(prepare_model(volume, options), observer);
}

void require_success(const PipelineResult& result) {
  if (!result.failure.empty()) throw ModelFailed(result.failure);
}

}  // namespace gdm
