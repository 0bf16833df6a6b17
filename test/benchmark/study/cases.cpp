// See cases.h.
#include "cases.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <sstream>
#include <stdexcept>

#include "gdm/phantoms.h"
#include "gdm/seed.h"
#include "peer_itk.h"

namespace study {
namespace {

namespace ph = gdm::phantoms;
using gdm::Vec3;

constexpr double kBackground = 50.0, kContrast = 150.0;  // phantom values: 50 outside, 200 inside
constexpr double kThreshold = kBackground + kContrast / 2;

Image to_image(const gdm::Volume& v) {
  Image image;
  for (int a = 0; a < 3; ++a) {
    image.dims[a] = v.dims()[a];
    image.spacing[a] = v.spacing()[a];
    image.origin[a] = v.origin()[a];
  }
  image.values = v.values();
  return image;
}

Image sample_field(const ph::Grid& grid, const ph::Sdf& sdf) {
  Image image;
  image.dims = grid.dims;
  for (int a = 0; a < 3; ++a) {
    image.spacing[a] = grid.spacing[a];
    image.origin[a] = grid.origin[a];
  }
  image.values.resize(static_cast<std::size_t>(grid.dims[0]) * grid.dims[1] * grid.dims[2]);
  std::size_t i = 0;
  for (int z = 0; z < grid.dims[2]; ++z)
    for (int y = 0; y < grid.dims[1]; ++y)
      for (int x = 0; x < grid.dims[0]; ++x, ++i)
        image.values[i] = static_cast<float>(
            sdf(grid.origin + Vec3(x * grid.spacing.x(), y * grid.spacing.y(), z * grid.spacing.z())));
  return image;
}

Point pt(const Vec3& v) { return {v.x(), v.y(), v.z()}; }
Vec3 vec(const Point& p) { return {p[0], p[1], p[2]}; }

struct Shape {
  std::string name, id;
  ph::Grid grid;
  ph::Sdf sdf;
  std::function<double(const Vec3&)> distance;  // exact unsigned distance; defaults to |sdf|
  Vec3 seed;
};

std::vector<Shape> shapes(bool quick) {
  std::vector<Shape> s;
  ph::Grid g;
  const Vec3 c = g.center();
  s.push_back({"sphere", "sphere", g, ph::sphere(c, 20.0), {}, c});
  if (quick) return s;
  {
    ph::Grid a;
    a.dims = {64, 64, 32};
    a.spacing = Vec3(1.0, 1.0, 2.0);
    const Vec3 ac = a.center();
    const Vec3 radii(24, 16, 20);
    s.push_back({"ellipsoid, spacing 1x1x2", "ellipsoid", a, ph::ellipsoid(ac, radii),
                 [ac, radii](const Vec3& p) { return ph::distance_to_ellipsoid(p, ac, radii); }, ac});
  }
  s.push_back({"cube with a corner missing", "cube", g,
               ph::difference(ph::box(Vec3(12, 12, 12), Vec3(52, 52, 52)), ph::box(Vec3(32, 32, 32), Vec3(60, 60, 60))),
               {}, Vec3(24, 24, 24)});
  s.push_back({"bent tube", "tube", g, ph::bent_tube(c, 18.0, 6.0, 1.5 * M_PI), {}, c + Vec3(18.0, 0.5, 0.0)});
  s.push_back({"branching shape", "branching", g,
               ph::branching(c),
               {}, c + Vec3(0, 0, 10)});
  return s;
}

Case phantom_case(const Shape& shape, const std::string& variant, const gdm::Volume& volume) {
  Case k;
  k.group = "phantom";
  k.name = shape.name + ", " + variant;
  k.id = shape.id + "-" + variant;
  std::replace(k.id.begin(), k.id.end(), ' ', '-');
  k.image = to_image(volume);
  k.threshold = kThreshold;
  k.seed = pt(shape.seed);
  const auto sdf = shape.sdf;
  const auto distance = shape.distance;
  k.exact_distance = distance ? std::function<double(const Point&)>([distance](const Point& p) { return distance(vec(p)); })
                              : std::function<double(const Point&)>([sdf](const Point& p) { return std::abs(sdf(vec(p))); });
  k.signed_distance = [sdf, distance](const Point& p) {
    const double d = distance ? distance(vec(p)) : std::abs(sdf(vec(p)));
    return sdf(vec(p)) > 0.0 ? d : -d;
  };
  k.truth_field = sample_field(shape.grid, shape.sdf);
  k.truth_level = 0.0;
  return k;
}

// Voxels on the object-darker side of the threshold that are not 6-connected
// to `start` are set to a value on the other side (mirrored about the
// threshold): cavities are filled, or other dark regions hidden, so that
// every method sees the one object the case is about. Returns the size of the
// connected region.
std::size_t keep_dark_region(Image& image, double threshold, std::array<int, 3> start) {
  const auto& d = image.dims;
  const std::size_t n = image.values.size();
  std::vector<char> reached(n, 0);
  auto index = [&](int x, int y, int z) {
    return static_cast<std::size_t>(x) + static_cast<std::size_t>(d[0]) * (y + static_cast<std::size_t>(d[1]) * z);
  };
  std::vector<std::array<int, 3>> stack{start};
  reached[index(start[0], start[1], start[2])] = 1;
  std::size_t count = 0;
  while (!stack.empty()) {
    const auto p = stack.back();
    stack.pop_back();
    ++count;
    static const int offsets[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
    for (const auto& o : offsets) {
      const int x = p[0] + o[0], y = p[1] + o[1], z = p[2] + o[2];
      if (x < 0 || y < 0 || z < 0 || x >= d[0] || y >= d[1] || z >= d[2]) continue;
      const std::size_t i = index(x, y, z);
      if (reached[i] || image.values[i] >= threshold) continue;
      reached[i] = 1;
      stack.push_back({x, y, z});
    }
  }
  for (std::size_t i = 0; i < n; ++i)
    if (!reached[i] && image.values[i] < threshold) image.values[i] = static_cast<float>(2.0 * threshold - image.values[i]);
  return count;
}

// Pads the image with `pad` voxels of `value` on every side (closes surfaces cut by the field of view).
Image pad(const Image& in, int pad_by, float value) {
  Image out;
  for (int a = 0; a < 3; ++a) {
    out.dims[a] = in.dims[a] + 2 * pad_by;
    out.spacing[a] = in.spacing[a];
    out.origin[a] = in.origin[a] - pad_by * in.spacing[a];
  }
  out.values.assign(static_cast<std::size_t>(out.dims[0]) * out.dims[1] * out.dims[2], value);
  for (int z = 0; z < in.dims[2]; ++z)
    for (int y = 0; y < in.dims[1]; ++y)
      for (int x = 0; x < in.dims[0]; ++x)
        out.values[static_cast<std::size_t>(x + pad_by) +
                   static_cast<std::size_t>(out.dims[0]) * (y + pad_by + static_cast<std::size_t>(out.dims[1]) * (z + pad_by))] =
            static_cast<float>(in.value(x, y, z));
  return out;
}


// Averages blocks of f[0] x f[1] x f[2] voxels (to keep the study within its time budget).
Image average_blocks(const Image& in, std::array<int, 3> f) {
  Image out;
  for (int a = 0; a < 3; ++a) {
    out.dims[a] = in.dims[a] / f[a];
    out.spacing[a] = f[a] * in.spacing[a];
    out.origin[a] = in.origin[a] + 0.5 * (f[a] - 1) * in.spacing[a];
  }
  out.values.resize(static_cast<std::size_t>(out.dims[0]) * out.dims[1] * out.dims[2]);
  const double n = static_cast<double>(f[0]) * f[1] * f[2];
  std::size_t i = 0;
  for (int z = 0; z < out.dims[2]; ++z)
    for (int y = 0; y < out.dims[1]; ++y)
      for (int x = 0; x < out.dims[0]; ++x, ++i) {
        double sum = 0.0;
        for (int k = 0; k < f[2]; ++k)
          for (int j = 0; j < f[1]; ++j)
            for (int l = 0; l < f[0]; ++l) sum += in.value(f[0] * x + l, f[1] * y + j, f[2] * z + k);
        out.values[i] = static_cast<float>(sum / n);
      }
  return out;
}

// The voxel nearest the volume's centre whose neighbourhood of `radius` mm
// lies on the object's side of the threshold: where a seed of that radius fits.
std::array<int, 3> central_seed_voxel(const Image& image, double threshold, bool brighter, double radius) {
  const auto& d = image.dims;
  int r[3];
  for (int a = 0; a < 3; ++a) r[a] = std::max(1, static_cast<int>(std::ceil(radius / image.spacing[a])));
  auto inside = [&](int x, int y, int z) {
    const double v = image.value(x, y, z);
    return brighter ? v > threshold : v < threshold;
  };
  auto fits = [&](int x, int y, int z) {
    for (int k = -r[2]; k <= r[2]; ++k)
      for (int j = -r[1]; j <= r[1]; ++j)
        for (int i = -r[0]; i <= r[0]; ++i) {
          const int X = x + i, Y = y + j, Z = z + k;
          if (X < 0 || Y < 0 || Z < 0 || X >= d[0] || Y >= d[1] || Z >= d[2] || !inside(X, Y, Z)) return false;
        }
    return true;
  };
  const int cx = d[0] / 2, cy = d[1] / 2, cz = d[2] / 2;
  const int reach = std::max({d[0], d[1], d[2]}) / 2;
  for (int shell = 0; shell <= reach; ++shell)
    for (int z = std::max(0, cz - shell); z <= std::min(d[2] - 1, cz + shell); ++z)
      for (int y = std::max(0, cy - shell); y <= std::min(d[1] - 1, cy + shell); ++y)
        for (int x = std::max(0, cx - shell); x <= std::min(d[0] - 1, cx + shell); ++x) {
          if (std::max({std::abs(x - cx), std::abs(y - cy), std::abs(z - cz)}) != shell) continue;
          if (fits(x, y, z)) return {x, y, z};
        }
  throw std::runtime_error("no place for a seed inside the object");
}

}  // namespace

double Case::voxel_size() const { return std::min({image.spacing[0], image.spacing[1], image.spacing[2]}); }

CaseSet phantom_cases(bool quick, const PhantomNoise& noise) {
  CaseSet set;
  unsigned seed = noise.seed;
  for (const Shape& s : shapes(quick)) {
    const gdm::Volume clean = ph::voxelize(s.grid, s.sdf, kBackground, kContrast);
    set.cases.push_back(phantom_case(s, "clean", clean));
    if (quick) break;
    Case g = phantom_case(s, "Gaussian noise", ph::with_gaussian_noise(clean, noise.sigma, seed++));
    std::ostringstream note;
    note << "Gaussian noise, sigma " << noise.sigma << " (contrast " << kContrast << ")";
    g.note = note.str();
    set.cases.push_back(std::move(g));
    {
      // Salt and pepper: 10% of the inside voxels set to the background, 1% of the outside ones to the object.
      const gdm::Volume peppered = ph::with_pepper(clean, s.sdf, 0.10, kBackground, 1.0, seed++);
      std::vector<float> values = peppered.values();
      std::mt19937 rng(seed++);
      std::uniform_real_distribution<double> u(0.0, 1.0);
      std::size_t i = 0;
      for (int z = 0; z < s.grid.dims[2]; ++z)
        for (int y = 0; y < s.grid.dims[1]; ++y)
          for (int x = 0; x < s.grid.dims[0]; ++x, ++i)
            if (s.sdf(clean.to_physical(Vec3(x, y, z))) > 1.0 && u(rng) < 0.01)
              values[i] = static_cast<float>(kBackground + kContrast);
      Case p = phantom_case(s, "salt and pepper",
                            gdm::Volume(clean.dims(), std::move(values), clean.spacing(), clean.origin(), clean.direction()));
      p.note = "10% of the inside voxels at the background value, 1% of the outside ones at the object value";
      set.cases.push_back(std::move(p));
    }
    {
      // A hole in the wall: the shape is a dark cavity in a bright 4 mm wall with
      // a hole of radius 2 mm; the cavity is the object (grown from inside).
      Vec3 exit = s.seed;
      while (s.sdf(exit) < 0.0) exit.x() += 0.25;
      const ph::Sdf cavity = s.sdf;
      const ph::Sdf wall = ph::difference(
          ph::difference([cavity](const Vec3& p) { return cavity(p) - 4.0; }, cavity),
          ph::capsule(exit - Vec3(2, 0, 0), exit + Vec3(8, 0, 0), 2.0));
      Case h = phantom_case(s, "hole in the wall", ph::voxelize(s.grid, wall, kBackground, kContrast));
      h.object_brighter = false;
      // The hole is 4 mm across: our GDM runs with a gap two voxels wider.
      h.gap = 6.0;
      h.note = "dark cavity (the object) in a bright 4 mm wall with a 2 mm-radius hole at (" +
               std::to_string(static_cast<int>(exit.x())) + ", " + std::to_string(static_cast<int>(exit.y())) + ", " +
               std::to_string(static_cast<int>(exit.z())) + "); the truth is the cavity without the hole, our GDM runs "
               "with a gap of 6 mm (the hole's 4 mm diameter plus two voxels)";
      set.cases.push_back(std::move(h));
    }
  }
  return set;
}

CaseSet opening_cases(bool quick) {
  CaseSet set;
  constexpr double kNoise = 0.05;  // Gaussian noise, sigma 5 % of the contrast
  // Opened bottles: a dark spherical cavity of radius 15 voxels in a bright wall
  // 2 voxels thick, pierced along +x by a round opening of diameter d. The
  // cavity is the object; the truth is its sphere, the opening capped on it.
  for (const int d : quick ? std::vector<int>{4} : std::vector<int>{4, 8}) {
    ph::Grid g;
    g.dims = {48, 48, 48};
    const Vec3 c = g.center();
    const double inner = 15.0, outer = 17.0, half = 0.5 * d;
    const ph::Sdf shell = [c, inner, outer](const Vec3& p) {
      const double r = (p - c).norm();
      return std::max(r - outer, inner - r);
    };
    // The opening: the half cylinder of radius d / 2 from the centre along +x.
    const ph::Sdf opening = [c, half](const Vec3& p) {
      return std::max(std::hypot(p.y() - c.y(), p.z() - c.z()) - half, c.x() - p.x());
    };
    const gdm::Volume wall = ph::with_gaussian_noise(
        ph::voxelize(g, ph::difference(shell, opening), kBackground, kContrast), kNoise * kContrast, 40u + d);
    Case k = phantom_case({"opened bottle", "bottle", g, ph::sphere(c, inner), {}, c}, "d" + std::to_string(d), wall);
    k.group = "openings and channels";
    k.name = "opened bottle, opening " + std::to_string(d) + " voxels";
    k.object_brighter = false;
    k.gap = d + 2.0;
    k.note = "dark cavity of radius 15 voxels (the object) in a bright wall 2 voxels thick with a round opening " +
             std::to_string(d) + " voxels across along +x; Gaussian noise, sigma 5% of the contrast; the truth is the "
             "cavity's sphere, the opening capped on it; our GDM runs with a gap of " + std::to_string(d + 2) +
             " mm (the opening plus two voxels)";
    set.cases.push_back(std::move(k));
  }
  if (quick) return set;
  {
    // The channel phantom: a bright chamber (sphere of radius 9 voxels) with
    // three round channels 2, 3 and 4 voxels wide reaching 20 voxels beyond its
    // wall (along +x, +y and -z, round ends); our GDM at the defaults.
    ph::Grid g;
    g.dims = {72, 72, 72};
    const Vec3 o = g.center();
    const double chamber = 9.0, length = 20.0;
    const ph::Sdf sdf = ph::unite({ph::sphere(o, chamber), ph::capsule(o, o + Vec3(chamber + length - 1.0, 0, 0), 1.0),
                                   ph::capsule(o, o + Vec3(0, chamber + length - 1.5, 0), 1.5),
                                   ph::capsule(o, o - Vec3(0, 0, chamber + length - 2.0), 2.0)});
    const gdm::Volume v =
        ph::with_gaussian_noise(ph::voxelize(g, sdf, kBackground, kContrast), kNoise * kContrast, 61u);
    Case k = phantom_case({"channel phantom", "channels", g, sdf, {}, o}, "2-3-4", v);
    k.group = "openings and channels";
    k.name = "chamber with channels 2, 3 and 4 voxels wide";
    k.note = "bright chamber of radius 9 voxels with round channels 2, 3 and 4 voxels wide and 20 voxels long "
             "(+x, +y, -z); Gaussian noise, sigma 5% of the contrast; the truth is the analytic surface; our GDM at "
             "the defaults (no gap: every channel two voxels wide is open)";
    set.cases.push_back(std::move(k));
  }
  return set;
}

CaseSet scan_cases(const std::string& data_dir) {
  CaseSet set;
  namespace fs = std::filesystem;
  auto make = [&](const std::string& name, const std::string& id, const std::string& path, double threshold,
                  bool brighter, gdm::Mode mode, std::array<int, 3> seed_voxel, const std::string& note,
                  bool isolate, std::array<int, 3> block = {1, 1, 1}) {
    if (!fs::exists(path)) {
      set.skipped.push_back(name + ": " + path + " not found");
      return;
    }
    Image raw;
    try {
      raw = read_scan(path);
    } catch (const std::exception& e) {
      set.skipped.push_back(name + ": " + e.what());
      return;
    }
    const bool averaged = block[0] * block[1] * block[2] > 1;
    if (averaged) raw = average_blocks(raw, block);
    Case k;
    k.group = "scan";
    k.name = name;
    k.id = id;
    const float low = *std::min_element(raw.values.begin(), raw.values.end());
    const float high = *std::max_element(raw.values.begin(), raw.values.end());
    // Two voxels of background around the field of view close the surfaces it cuts.
    k.image = pad(raw, 2, brighter ? low : high);
    k.threshold = threshold;
    k.object_brighter = brighter;
    k.mode = mode;
    k.note = note + "; padded with 2 voxels of background";
    if (isolate) {
      // The dark side connected to the seed voxel (object darker) or to the
      // corner (object brighter: the background) is kept; other dark regions are filled.
      Image flipped = k.image;
      if (brighter) {
        const std::size_t n = keep_dark_region(flipped, threshold, {0, 0, 0});
        (void)n;
        k.note += "; dark regions not connected to the outside filled (cavities closed)";
      } else {
        const std::array<int, 3> s{seed_voxel[0] + 2, seed_voxel[1] + 2, seed_voxel[2] + 2};
        const std::size_t n = keep_dark_region(flipped, threshold, s);
        k.note += "; dark regions other than the seed's (" + std::to_string(n) + " voxels) set bright";
      }
      k.image = std::move(flipped);
    }
    if (seed_voxel[0] < 0) {
      try {
        const auto v = central_seed_voxel(k.image, threshold, brighter, k.seed_radius);
        seed_voxel = {v[0] - 2, v[1] - 2, v[2] - 2};
        k.note += "; seed at the voxel nearest the centre where the seed fits inside, (" + std::to_string(seed_voxel[0]) +
                  ", " + std::to_string(seed_voxel[1]) + ", " + std::to_string(seed_voxel[2]) + ")";
      } catch (const std::exception& e) {
        set.skipped.push_back(name + ": " + e.what());
        return;
      }
    }
    if (averaged)
      k.note += "; averaged in blocks of " + std::to_string(block[0]) + "x" + std::to_string(block[1]) + "x" +
                std::to_string(block[2]) + " voxels (to keep the study within its time budget)";
    for (int a = 0; a < 3; ++a) k.seed[a] = k.image.origin[a] + k.image.spacing[a] * (seed_voxel[a] + 2);
    k.truth_field = k.image;
    k.truth_level = threshold;
    (void)high;
    set.cases.push_back(std::move(k));
  };
  const std::string tooth = data_dir + "/tooth/tooth.mhd";
  make("tooth pulp (industrial CT)", "tooth-pulp", tooth, 115.0, false, gdm::Mode::grow, {50, 47, 95},
       "threshold 115, pulp darker than dentin, seed voxel (50, 47, 95)", true);
  // Outer surfaces: cavities are filled first, so the model grows from inside to the outer surface.
  make("tooth outer surface (industrial CT)", "tooth-outer", tooth, 115.0, true, gdm::Mode::grow, {-1, -1, -1},
       "threshold 115", true);
  make("CT head phantom (DICOM)", "ct-phantom", data_dir + "/ct-phantom-dicom/series", -400.0, true,
       gdm::Mode::grow, {-1, -1, -1}, "threshold -400 HU", true, {4, 4, 1});
  make("T1 MRI head, skin", "mri-skin", data_dir + "/mri-head-t1/chris_t1.nii.gz", 40.0, true, gdm::Mode::grow,
       {-1, -1, -1}, "threshold 40", true, {2, 2, 2});
  return set;
}

CaseSet topology_cases(const std::string& data_dir) {
  CaseSet set;
  constexpr double kNoise = 0.05;  // Gaussian noise, sigma 5 % of the contrast
  {
    // A hollow sphere: a bright shell 3 voxels thick (radii 11 and 14) around
    // an enclosed dark cavity, grown from a seed in the shell. Outer truth:
    // the sphere of radius 14; all surfaces: both spheres.
    ph::Grid g;
    g.dims = {40, 40, 40};
    const Vec3 c = g.center();
    const double inner = 11.0, outer = 14.0;
    const ph::Sdf shell = ph::difference(ph::sphere(c, outer), ph::sphere(c, inner));
    const gdm::Volume v =
        ph::with_gaussian_noise(ph::voxelize(g, shell, kBackground, kContrast), kNoise * kContrast, 150u);
    Case k = phantom_case({"hollow sphere", "topo-shell", g, shell, {}, c + Vec3(12.5, 0.0, 0.0)}, "3", v);
    k.group = "topology";
    k.name = "hollow sphere, shell 3 voxels";
    k.id = "topo-hollow-sphere";
    k.seed_radius = 1.2;  // inside the 3-voxel shell
    k.exact_distance = [c, inner, outer](const Point& p) {
      const double r = (vec(p) - c).norm();
      return std::min(std::abs(r - outer), std::abs(r - inner));
    };
    k.outer_distance = [c, outer](const Point& p) { return std::abs((vec(p) - c).norm() - outer); };
    k.note = "bright spherical shell, radii 11 and 14 voxels, around an enclosed dark cavity (genus 0, two surfaces); "
             "Gaussian noise, sigma 5% of the contrast; seed in the shell at (+12.5, 0, 0) from the centre, radius 1.2 mm";
    k.truth_note = "outer: the sphere of radius 14; all: both spheres";
    k.truth_components = 2;
    k.truth_genus = 0;
    set.cases.push_back(std::move(k));
  }
  for (const int holes : {1, 2}) {
    // The tori of the topology tests (phantoms::tori): genus 1 and 2, grown
    // from a seed in the tube. The outer surface is the whole surface (no cavity).
    const ph::Tori t = ph::tori(holes);
    const gdm::Volume v = ph::with_gaussian_noise(ph::voxelize(t.grid, t.sdf, kBackground, kContrast),
                                                  kNoise * kContrast, 170u + static_cast<unsigned>(holes));
    const std::string name = holes == 1 ? "torus" : "double torus";
    Case k = phantom_case({name, "topo", t.grid, t.sdf, {}, t.centres.front() + Vec3(0.0, -t.R, 0.0)},
                          holes == 1 ? "torus" : "double-torus", v);
    k.group = "topology";
    k.name = name + " (genus " + std::to_string(holes) + ")";
    k.seed_radius = 1.5;
    const auto sdf = t.sdf;
    k.outer_distance = [sdf](const Point& p) { return std::abs(sdf(vec(p))); };
    char geometry[160];
    std::snprintf(geometry, sizeof geometry, "%s: tube radius %g voxels around circles of radius %g", name.c_str(), t.r, t.R);
    k.note = std::string(geometry) + (holes == 2 ? ", two side by side, their tubes merging" : "") +
             " (genus " + std::to_string(holes) + "); Gaussian noise, sigma 5% of the contrast; seed in the tube, radius 1.5 mm";
    k.truth_note = "outer = all: the tori's surface (a cap across a hole counts as error)";
    k.truth_components = 1;
    k.truth_genus = holes;
    set.cases.push_back(std::move(k));
  }
  {
    // The whole tooth from a seed in the dentin: no cavity filled for the
    // peers (the pulp chamber stays in the volume), padded like the scans.
    namespace fs = std::filesystem;
    const std::string path = data_dir + "/tooth/tooth.mhd";
    const std::string name = "whole tooth from the dentin (industrial CT)";
    if (!fs::exists(path)) {
      set.skipped.push_back(name + ": " + path + " not found (the shared data is absent)");
      return set;
    }
    Image raw;
    try {
      raw = read_scan(path);
    } catch (const std::exception& e) {
      set.skipped.push_back(name + ": " + e.what());
      return set;
    }
    const float low = *std::min_element(raw.values.begin(), raw.values.end());
    Case k;
    k.group = "topology";
    k.name = name;
    k.id = "topo-tooth";
    k.image = pad(raw, 2, low);
    k.threshold = 115.0;
    k.object_brighter = true;
    const std::array<int, 3> seed_voxel{56, 56, 70};
    for (int a = 0; a < 3; ++a) k.seed[a] = k.image.origin[a] + k.image.spacing[a] * (seed_voxel[a] + 2);
    k.truth_field = k.image;
    k.truth_level = k.threshold;
    k.note = "threshold 115, object brighter, seed voxel (56, 56, 70) in the dentin; no cavity filled, the pulp chamber "
             "left in the volume; padded with 2 voxels of background";
    k.truth_note = "all: the iso-surface of the 2x-upsampled volume at 115 (every component); outer: its component "
                   "with the largest extent";
    set.cases.push_back(std::move(k));
  }
  return set;
}

CaseSet volume_scaling_cases(bool quick) {
  CaseSet set;
  const std::vector<int> sizes = quick ? std::vector<int>{48} : std::vector<int>{64, 128, 256, 512};
  for (int n : sizes) {
    ph::Grid g;
    g.dims = {n, n, n};
    const Vec3 c = g.center();
    const auto sdf = ph::sphere(c, 20.0);
    Case k = phantom_case({"sphere r 20", "sphere", g, sdf, {}, c}, std::to_string(n) + "^3", ph::voxelize(g, sdf, kBackground, kContrast));
    k.group = "scaling: volume size";
    k.name = "sphere of radius 20 in " + std::to_string(n) + "^3";
    k.id = "volume-" + std::to_string(n);
    k.truth_field = Image();  // exact distance only; the coverage is not needed for the timing series
    set.cases.push_back(std::move(k));
  }
  return set;
}

CaseSet area_scaling_cases(bool quick) {
  CaseSet set;
  if (quick) return set;
  for (double r : {10.0, 20.0, 40.0, 70.0}) {
    ph::Grid g;
    g.dims = {160, 160, 160};
    const Vec3 c = g.center();
    const auto sdf = ph::sphere(c, r);
    Case k = phantom_case({"sphere", "sphere", g, sdf, {}, c}, "r", ph::voxelize(g, sdf, kBackground, kContrast));
    k.group = "scaling: surface area";
    k.name = "sphere of radius " + std::to_string(static_cast<int>(r)) + " in 160^3";
    k.id = "area-" + std::to_string(static_cast<int>(r));
    k.truth_field = Image();
    set.cases.push_back(std::move(k));
  }
  return set;
}

gdm::Mesh seed_mesh(const Case& c, int level) {
  if (c.mode == gdm::Mode::grow) return gdm::make_geodesic_sphere(vec(c.seed), c.seed_radius, level);
  // An ellipsoid inscribed in the volume, 1.5 voxels inside its border.
  gdm::Mesh mesh = gdm::make_geodesic_sphere(Vec3::Zero(), 1.0, 3);
  Vec3 center, radii;
  for (int a = 0; a < 3; ++a) {
    center[a] = c.image.origin[a] + 0.5 * (c.image.dims[a] - 1) * c.image.spacing[a];
    radii[a] = (0.5 * (c.image.dims[a] - 1) - 1.5) * c.image.spacing[a];
  }
  for (auto v : mesh.vertices()) {
    const auto p = mesh.point(v);
    mesh.set_point(v, gdm::to_point(center + Vec3(p[0] * radii[0], p[1] * radii[1], p[2] * radii[2])));
  }
  return mesh;
}

}  // namespace study
