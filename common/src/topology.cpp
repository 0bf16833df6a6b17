#include "gdm/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <unordered_set>
#include <vector>

#include "gdm/cell_hash.h"
#include "gdm/deformer.h"
#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/seed.h"
#include "gdm/distance_transform.h"

namespace gdm {

std::string to_string(Topology topology) {
  return topology == Topology::exact ? "exact" : "solid";
}

bool euler_consistent(int euler, int components, int genus, bool closed) {
  if (!closed || components < 1 || genus < 0) return false;
  const int twice_genus = 2 * components - euler;
  return twice_genus >= 0 && twice_genus % 2 == 0 && twice_genus / 2 == genus;
}

namespace {

// Voxels are x fastest; 6-neighbour offsets.
constexpr std::array<std::array<int, 3>, 6> kSix{{{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}}};

struct Region {
  std::vector<std::size_t> voxels;  // in raster order of discovery (breadth-first from the first)
  Index3 lo{0, 0, 0}, hi{0, 0, 0};  // inclusive box
};

std::size_t linear(const Index3& n, int i, int j, int k) {
  return static_cast<std::size_t>(i) + static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) +
                                                                        static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k));
}

// The enclosed cavities the fill filled: 6-connected regions of background
// that never touch the volume's border and whose every voxel was filled
// (a region with an unfilled voxel is reached by the outside: a pocket behind
// narrow openings, or background of another object). Raster order of their
// first voxel.
std::vector<Region> enclosed_regions(const Volume& volume, const Volume& filled, double t, bool brighter,
                                     std::size_t* narrow_pockets) {
  const Index3 n = volume.dims();
  const std::vector<float>& v = volume.values();
  const std::vector<float>& f = filled.values();
  // Strictly on the background's side, as the fill counts it (a voxel at T is neither side there).
  const auto background = [&](std::size_t i) { return brighter ? v[i] < t : v[i] > t; };
  std::vector<char> seen(v.size(), 0);
  std::vector<Region> regions;
  std::vector<std::size_t> queue;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t start = linear(n, i, j, k);
        if (seen[start] || v[start] == f[start] || !background(start)) continue;
        Region r;
        r.lo = r.hi = {i, j, k};
        bool enclosed = true;
        queue.assign(1, start);
        seen[start] = 1;
        for (std::size_t q = 0; q < queue.size(); ++q) {
          const std::size_t at = queue[q];
          const int x = static_cast<int>(at % n[0]);
          const int y = static_cast<int>((at / n[0]) % n[1]);
          const int z = static_cast<int>(at / (static_cast<std::size_t>(n[0]) * n[1]));
          if (v[at] == f[at]) enclosed = false;  // background the fill left open
          if (x == 0 || y == 0 || z == 0 || x == n[0] - 1 || y == n[1] - 1 || z == n[2] - 1) enclosed = false;
          const Index3 p{x, y, z};
          for (int a = 0; a < 3; ++a) {
            r.lo[a] = std::min(r.lo[a], p[a]);
            r.hi[a] = std::max(r.hi[a], p[a]);
          }
          for (const auto& d : kSix) {
            const int xi = x + d[0], yi = y + d[1], zi = z + d[2];
            if (xi < 0 || yi < 0 || zi < 0 || xi >= n[0] || yi >= n[1] || zi >= n[2]) continue;
            const std::size_t next = linear(n, xi, yi, zi);
            if (seen[next] || !background(next)) continue;
            seen[next] = 1;
            queue.push_back(next);
          }
        }
        if (queue.size() < kCavitySpeckVoxels) continue;
        if (!enclosed) {
          // Filled voxels in a region the outside reaches: a pocket behind
          // narrow openings (or a handle's membrane); left to `solid`.
          bool any_filled = false;
          for (std::size_t at : queue) any_filled = any_filled || v[at] != f[at];
          if (any_filled && narrow_pockets) ++*narrow_pockets;
          continue;
        }
        r.voxels = queue;
        regions.push_back(std::move(r));
      }
  return regions;
}

// A box around the region with a margin, the region's voxels as they are and
// every other voxel on the object's side of T (background outside the region
// mirrored about T): the region is the only part of it on the cavity's side.
// `centre` and `depth` (mm): the region's voxel farthest from every voxel
// outside it (the first in raster order on ties), and that distance.
Volume cavity_volume(const Volume& volume, const Region& r, double t, bool brighter, Vec3& centre, double& depth) {
  const Index3 n = volume.dims();
  constexpr int kMargin = 4;
  Index3 lo, hi, m;
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::max(0, r.lo[a] - kMargin);
    hi[a] = std::min(n[a] - 1, r.hi[a] + kMargin);
    m[a] = hi[a] - lo[a] + 1;
  }
  std::vector<char> inside(static_cast<std::size_t>(m[0]) * m[1] * m[2], 0);
  for (std::size_t at : r.voxels) {
    const int x = static_cast<int>(at % n[0]) - lo[0];
    const int y = static_cast<int>((at / n[0]) % n[1]) - lo[1];
    const int z = static_cast<int>(at / (static_cast<std::size_t>(n[0]) * n[1])) - lo[2];
    inside[linear(m, x, y, z)] = 1;
  }
  {
    std::vector<char> sites(inside.size());
    for (std::size_t i = 0; i < inside.size(); ++i) sites[i] = inside[i] ? 0 : 1;
    const std::vector<double> d2 = squared_distance_to(sites, m, volume.spacing());
    std::size_t best = 0;
    double deepest = -1.0;
    for (std::size_t i = 0; i < d2.size(); ++i)
      if (inside[i] && d2[i] > deepest) deepest = d2[i], best = i;
    depth = std::sqrt(std::max(0.0, deepest));
    const Vec3 at(static_cast<double>(lo[0] + static_cast<int>(best % m[0])),
                  static_cast<double>(lo[1] + static_cast<int>((best / m[0]) % m[1])),
                  static_cast<double>(lo[2] + static_cast<int>(best / (static_cast<std::size_t>(m[0]) * m[1]))));
    centre = volume.to_physical(at);
  }
  // The smallest step past T on the object's side, for background exactly at T.
  const double range = std::max(1e-6, volume.max_value() - volume.min_value());
  const double nudge = (brighter ? 1.0 : -1.0) * 1e-3 * range;
  std::vector<float> values(inside.size());
  for (int k = 0; k < m[2]; ++k)
    for (int j = 0; j < m[1]; ++j)
      for (int i = 0; i < m[0]; ++i) {
        const std::size_t here = linear(m, i, j, k);
        const double value = volume.at(lo[0] + i, lo[1] + j, lo[2] + k);
        const bool object = brighter ? value > t : value < t;
        double out = value;
        if (!inside[here] && !object) {
          out = 2.0 * t - value;
          if (!(brighter ? out > t : out < t)) out = t + nudge;
        }
        values[here] = static_cast<float>(out);
      }
  Volume cavity(m, std::move(values), volume.spacing(), volume.to_physical(Vec3(lo[0], lo[1], lo[2])),
                volume.direction());
  // Past the box counts as the object (the cavity's background).
  cavity.set_outside_value(t + (brighter ? 1.0 : -1.0) * range);
  return cavity;
}

// Appends `part` to `mesh` with every face reversed (normals into the cavity).
void append_reversed(Mesh& mesh, const Mesh& part) {
  std::vector<Mesh::VertexHandle> map(part.n_vertices());
  const OpenMesh::VPropHandleT<int> to = find_generation_property(mesh);
  const OpenMesh::VPropHandleT<int> from = find_generation_property(part);
  for (auto v : part.vertices()) {
    map[v.idx()] = mesh.add_vertex(part.point(v));
    if (to.is_valid()) mesh.property(to, map[v.idx()]) = from.is_valid() ? part.property(from, v) : 0;
  }
  for (auto f : part.faces()) {
    std::array<Mesh::VertexHandle, 3> t;
    int c = 0;
    for (auto v : part.fv_range(f)) t[c++] = map[v.idx()];
    mesh.add_face(t[0], t[2], t[1]);
  }
}

// How many times the closed mesh winds around p: the sum of its faces' signed
// solid angles over 4 pi (van Oosterom and Strackee's formula for a
// triangle's solid angle). 1 inside a closed outward surface, 0 outside.
double winding_number(const Mesh& mesh, const Vec3& p) {
  double total = 0.0;
  for (auto f : mesh.faces()) {
    auto it = mesh.cfv_iter(f);
    const Vec3 a = to_eigen(mesh.point(*it)) - p, b = to_eigen(mesh.point(*++it)) - p, c = to_eigen(mesh.point(*++it)) - p;
    const double la = a.norm(), lb = b.norm(), lc = c.norm();
    const double numerator = a.dot(b.cross(c));
    const double denominator = la * lb * lc + a.dot(b) * lc + b.dot(c) * la + c.dot(a) * lb;
    total += 2.0 * std::atan2(numerator, denominator);
  }
  return total / (4.0 * M_PI);
}

// The vertices of `after` at the volume's border (within a voxel of it, as
// the deformer counts them) not near a border vertex of `before` (in a cell
// of `reach` next to one of them): where `after` touches the border and
// `before` did not. The model deformed again after its handles were opened
// is a new mesh: its vertices at the cut faces of a scan that cuts the
// object are not those of before, nor as many (T1 head: 10,099 before, 10,238
// after, all on the same cut faces; CT series 17,465 and 17,490), so a count
// compared with before's refused every opening there.
std::size_t new_border_vertices(const Mesh& before, const Mesh& after, const Volume& volume, double reach) {
  std::unordered_set<CellKey> cells;
  for (auto v : before.vertices()) {
    const Vec3 p = to_eigen(before.point(v));
    if (volume.contains(p, 1.0)) continue;
    const auto c = cell_of(p, reach);
    cells.insert(cell_key(c[0], c[1], c[2]));
  }
  std::size_t n = 0;
  for (auto v : after.vertices()) {
    const Vec3 p = to_eigen(after.point(v));
    if (volume.contains(p, 1.0)) continue;
    const auto c = cell_of(p, reach);
    bool near = false;
    for (int dx = -1; dx <= 1 && !near; ++dx)
      for (int dy = -1; dy <= 1 && !near; ++dy)
        for (int dz = -1; dz <= 1 && !near; ++dz) near = cells.count(cell_key(c[0] + dx, c[1] + dy, c[2] + dz)) > 0;
    n += near ? 0 : 1;
  }
  return n;
}

}  // namespace

CavitySurfaces add_cavity_surfaces(
    Mesh& mesh, const CavitySurfaceInput& input,
    const std::function<bool(Mesh& seed, const Volume& cavity_volume, Polarity cavity_polarity)>& grow) {
  CavitySurfaces out;
  if (!input.volume || !input.fill || !input.fill->applied) return out;
  const Volume& volume = *input.volume;
  const double t = input.threshold;
  const bool brighter = input.polarity == Polarity::object_brighter;
  std::vector<Region> regions = enclosed_regions(volume, input.fill->volume, t, brighter, &out.narrow_pockets);
  // Largest first; ties keep raster order.
  std::stable_sort(regions.begin(), regions.end(),
                   [](const Region& a, const Region& b) { return a.voxels.size() > b.voxels.size(); });
  const Polarity cavity_polarity = brighter ? Polarity::object_darker : Polarity::object_brighter;
  for (const Region& r : regions) {
    Vec3 centre;
    double depth = 0.0;
    const Volume cavity = cavity_volume(volume, r, t, brighter, centre, depth);
    if (depth < 1.5 * volume.voxel_size()) {
      ++out.not_modelled;  // no voxel off the cavity's wall: too thin for a seed
      continue;
    }
    Mesh part = make_geodesic_sphere(centre, 0.5 * depth, 1);
    if (!grow(part, cavity, cavity_polarity) ||
        (input.max_faces > 0 && out.added_faces + part.n_faces() > input.max_faces)) {
      ++out.not_modelled;
      continue;
    }
    // Inside the outer model, or it is no cavity of the model: an outer model
    // that did not reach the object's surface (held at its seed) encloses
    // nothing. The two are free of crossings below, so one vertex tells.
    if (part.n_vertices() == 0 || std::abs(winding_number(mesh, to_eigen(part.point(*part.vertices_begin())))) < 0.5) {
      ++out.not_modelled;
      continue;
    }
    Mesh joined = mesh;
    append_reversed(joined, part);
    std::vector<Mesh::FaceHandle> added;
    for (std::size_t f = mesh.n_faces(); f < joined.n_faces(); ++f) added.emplace_back(static_cast<int>(f));
    if (faces_meet_mesh(joined, added)) {  // the cavity's model meets the outer one (or itself)
      ++out.not_modelled;
      continue;
    }
    mesh = std::move(joined);
    ++out.added;
    out.added_faces += part.n_faces();
  }
  return out;
}

void add_cavity_components(Mesh& mesh, const Volume& volume, const CavityFill& fill, const DeformOptions& options,
                           DeformResult& result, const DeformObserver& observer) {
  result.topology = options.topology;
  if (options.topology != Topology::exact || !fill.applied) return;
  if (result.reason != StopReason::converged) return;
  if (result.handles > 0) {
    // Each cap opened into a tube, fitted to the hole's wall by one more run
    // (no global refinement: the model is at its level of detail already).
    Mesh opened = mesh;
    const OpenedHandles h = open_handles(opened, volume, fill);
    if (h.opened > 0) {
      DeformOptions o = options;
      o.topology = Topology::solid;
      o.fill_cavities = false;  // h.volume holds the fill without the opened membranes
      o.global_refinements = 0;
      o.gap = 0.0;              // the gate's volume is `volume` already
      const DeformResult r = deform(opened, h.volume, o, observer);
      if (r.reason == StopReason::cancelled) {
        result.reason = StopReason::cancelled;
        result.cycles += r.cycles;
        return;
      }
      // Kept when it converged and touches the volume's border only where
      // the model did (within two of its mean edges): no leak through a hole.
      if (r.reason == StopReason::converged &&
          new_border_vertices(mesh, opened, volume, 2.0 * mean_edge_length(mesh)) == 0) {
        mesh = std::move(opened);
        result.handles_opened = h.opened;
        result.cycles += r.cycles;
        result.rejected_moves += r.rejected_moves;
        result.faces_below_min_angle = r.faces_below_min_angle;
        result.float_refused += r.float_refused;
      }
    }
  }
  CavitySurfaceInput input;
  input.volume = &volume;
  input.fill = &fill;
  input.threshold = options.threshold;
  input.polarity = options.polarity;
  input.max_faces = options.max_faces > mesh.n_faces() ? options.max_faces - mesh.n_faces() : 1;
  bool cancelled = false;  // a cavity's run was cancelled: no further cavity is grown
  const CavitySurfaces s = add_cavity_surfaces(mesh, input, [&](Mesh& seed, const Volume& cavity, Polarity polarity) {
    DeformOptions o = options;
    o.mode = Mode::grow;  // from a seed in the cavity, when the outer model shrank too
    o.polarity = polarity;
    o.topology = Topology::solid;
    o.face_budget = 0;        // the budget is the outer model's
    o.stop_at_border = true;  // the box's border lies outside the cavity: reaching it is a leak
    o.gap = 0.0;
    o.global_refinements = options.global_refinements;
    if (cancelled) return false;
    const DeformResult r = deform(seed, cavity, o, observer);
    cancelled = r.reason == StopReason::cancelled;
    return r.reason == StopReason::converged && r.border_vertices == 0;
  });
  if (cancelled) result.reason = StopReason::cancelled;
  result.cavity_components = s.added;
  result.cavity_component_faces = s.added_faces;
  result.cavities_not_modelled = s.not_modelled;
  result.faces = mesh.n_faces();
}

std::string topology_summary(const DeformResult& r) {
  if (r.topology != Topology::exact) return {};
  std::string s = "topology exact: " + std::to_string(r.cavity_components) + " enclosed cavit" +
                  (r.cavity_components == 1 ? "y" : "ies") + " as its own closed component, normals into the cavity (" +
                  std::to_string(r.cavity_component_faces) + " faces)";
  if (r.cavities_not_modelled > 0)
    s += "; " + std::to_string(r.cavities_not_modelled) + " enclosed cavit" +
         (r.cavities_not_modelled == 1 ? "y" : "ies") + " left filled (too thin, or its model failed or met the outer one)";
  if (r.cavities_behind_openings > 0)
    s += "; " + std::to_string(r.cavities_behind_openings) +
         " pocket(s) behind narrow openings filled as in solid (not enclosed)";
  if (r.handles > 0)
    s += "; " + std::to_string(r.handles_opened) + " of " + std::to_string(r.handles) +
         " handle(s) opened into a tube through the hole (genus +" + std::to_string(r.handles_opened) + ")" +
         (r.handles_opened < r.handles ? ", the others capped as in solid" : "");
  return s;
}

}  // namespace gdm
