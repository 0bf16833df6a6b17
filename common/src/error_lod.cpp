#include "gdm/error_lod.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

#include "gdm/parallel.h"
#include "gdm/predicates.h"
#include "gdm/resampler.h"
#include "gdm/surface_fit.h"

namespace gdm {

namespace {

// The median of the values that are not NaN (x reordered, NaNs dropped); 0
// when there is none.
double median_of_numbers(std::vector<double>& x) {
  x.erase(std::remove_if(x.begin(), x.end(), [](double t) { return std::isnan(t); }), x.end());
  if (x.empty()) return 0.0;
  const auto mid = x.begin() + static_cast<long>(x.size() / 2);
  std::nth_element(x.begin(), mid, x.end());
  return *mid;
}

Vec3 pos(const Mesh& mesh, Mesh::VertexHandle v) { return to_eigen(mesh.point(v)); }

// How far the threshold surface leaves the triangle abc, from seven points
// spread over it (centroid, edge midpoints, and half-way from the centroid to
// each corner), each measured along the triangle's normal to the crossing.
// The mean signed distance keeps what is systematic (a curved surface lies
// on one side of a flat face) and averages the image noise that would make a
// largest-distance criterion split everywhere; the largest distance catches
// a face straddling a crease or a thin part, where signed distances cancel.
// Both infinite when a point finds no crossing.
// Standard errors of the face's mean distance that the image noise may
// explain before a face counts as deviating (measured: 2 leaves the noisy
// sphere and branching tube too coarse, 0 splits on the ellipsoid's noise).
constexpr double kMeanNoise = 1.0;

struct Deviation {
  double mean = 0.0;     // |mean signed distance|, mm
  double largest = 0.0;  // largest |distance|, mm
  double noise = 0.0;    // standard deviation of one distance expected from the image noise, mm
  double cells = 1.0;    // independent noise values the seven points see (1..7)
  // The deviation compared with a tolerance: the mean, or a third of the
  // largest distance (which noise alone rarely reaches), each less what the
  // image noise explains (kMeanNoise standard errors of the mean, three
  // standard deviations of one distance): a face is not split to follow
  // noise, and flat parts can still be collapsed in a noisy image.
  double value() const {
    return std::max({0.0, mean - kMeanNoise * noise / std::sqrt(cells), (largest - 3.0 * noise) / 3.0});
  }
};

// How many voxel cells the plane of a face of `area` (mm^2) with unit normal
// u crosses: a plane crosses (sum_i |u_i| s_i) / (s_x s_y s_z) cells per mm^2
// (u_i in the grid's axes). Noise is independent from cell to cell, so this
// counts the independent noise values behind the face's distances.
double noise_cells(const Volume& volume, const Vec3& u, double area) {
  const Vec3 s = volume.spacing();
  const Vec3 m = volume.direction().transpose() * u;
  const double per_mm2 = (m.cwiseAbs().dot(s)) / (s.x() * s.y() * s.z());
  return std::clamp(area * per_mm2, 1.0, 7.0);
}

Deviation triangle_deviation(const Vec3& a, const Vec3& b, const Vec3& c, const Volume& volume, double threshold,
                             double search_mm, double noise_mm, double* residuals = nullptr) {
  const double inf = std::numeric_limits<double>::infinity();
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  if (!(len > 0.0)) return {inf, inf};
  const Vec3 u = n / len;
  const double step = std::min(0.25 * volume.voxel_size(), search_mm);
  const Vec3 g = (a + b + c) / 3.0;
  double d[7];
  int count = 0;
  for (const Vec3& s : {g, Vec3(0.5 * (a + b)), Vec3(0.5 * (b + c)), Vec3(0.5 * (c + a)), Vec3(0.5 * (g + a)),
                        Vec3(0.5 * (g + b)), Vec3(0.5 * (g + c))}) {
    const auto t = find_crossing(volume, threshold, s, u, search_mm, step);
    if (!t) return {inf, inf};
    d[count++] = *t;
  }
  double sum = 0.0, largest = 0.0;
  for (double x : d) {
    sum += x;
    largest = std::max(largest, std::abs(x));
  }
  const double mean = sum / count;
  if (residuals)
    for (int i = 0; i < count; ++i) residuals[i] = d[i] - mean;
  return {std::abs(mean), largest, noise_mm, noise_mm > 0.0 ? noise_cells(volume, u, 0.5 * len) : 1.0};
}

struct Tri {
  std::array<Vec3, 3> p;
  std::array<int, 3> id;
};

// Face f with vertex `from` replaced by `to` (at `to_pos`).
Tri face_tri(const Mesh& mesh, Mesh::FaceHandle f, int from = -1, int to = -1, const Vec3& to_pos = Vec3::Zero()) {
  Tri t;
  int i = 0;
  for (auto v : mesh.fv_range(f)) {
    const bool replaced = v.idx() == from;
    t.id[i] = replaced ? to : v.idx();
    t.p[i] = replaced ? to_pos : pos(mesh, v);
    ++i;
  }
  return t;
}

}  // namespace

double face_deviation(const Mesh& mesh, Mesh::FaceHandle f, const Volume& volume, double threshold,
                      double search_mm, double noise_mm) {
  auto it = mesh.cfv_iter(f);
  const Vec3 a = pos(mesh, *it), b = pos(mesh, *++it), c = pos(mesh, *++it);
  return triangle_deviation(a, b, c, volume, threshold, search_mm, noise_mm).value();
}

double estimate_crossing_noise(const Mesh& mesh, const Volume& volume, double threshold, double search_mm,
                               int threads) {
  // Each face's seven residuals in its own slots, the faces on the threads
  // at once (it was a sequential pass of seven crossings per face: about
  // half a second on the T1 head's 410,000 faces); the median is that of
  // the same numbers for any thread count.
  constexpr std::size_t kPoints = 7;
  std::vector<double> r(kPoints * mesh.n_faces(), std::numeric_limits<double>::quiet_NaN());
  parallel_for(mesh.n_faces(), resolve_thread_count(threads), [&](std::size_t i) {
    const Mesh::FaceHandle f(static_cast<int>(i));
    if (mesh.has_face_status() && mesh.status(f).deleted()) return;
    auto it = mesh.cfv_iter(f);
    const Vec3 a = pos(mesh, *it), b = pos(mesh, *++it), c = pos(mesh, *++it);
    double res[kPoints];
    if (!std::isfinite(triangle_deviation(a, b, c, volume, threshold, search_mm, 0.0, res).mean)) return;
    for (std::size_t k = 0; k < kPoints; ++k) r[kPoints * i + k] = std::abs(res[k]);
  });
  // Median absolute residual of a normal law is 0.6745 sigma; a residual
  // from the mean of seven has 6/7 of one distance's variance.
  return median_of_numbers(r) / 0.6745 * std::sqrt(7.0 / 6.0);
}

double estimate_edge_noise(const Mesh& mesh, const Volume& volume, double voxel_noise, int threads) {
  if (!(voxel_noise > 0.0)) return 0.0;
  const double v = volume.voxel_size();
  std::vector<double> slope(mesh.n_faces(), std::numeric_limits<double>::quiet_NaN());
  parallel_for(mesh.n_faces(), resolve_thread_count(threads), [&](std::size_t i) {
    const Mesh::FaceHandle f(static_cast<int>(i));
    if (mesh.has_face_status() && mesh.status(f).deleted()) return;
    auto it = mesh.cfv_iter(f);
    const Vec3 a = pos(mesh, *it), b = pos(mesh, *++it), c = pos(mesh, *++it);
    const Vec3 cross = (b - a).cross(c - a);
    if (!(cross.norm() > 0.0)) return;
    const Vec3 n = cross.normalized(), m = (a + b + c) / 3.0;
    double above = 0.0, below = 0.0;
    if (volume.sample_inside(m + 0.5 * v * n, above) && volume.sample_inside(m - 0.5 * v * n, below))
      slope[i] = std::abs(above - below) / v;
  });
  const double median_slope = median_of_numbers(slope);
  // A trilinear sample is a weighted mean of eight voxels: over a cell, the
  // weights' squares sum to (2/3)^3 on average, so its noise is
  // sqrt(8/27) of one voxel's.
  return median_slope > 0.0 ? std::sqrt(8.0 / 27.0) * voxel_noise / median_slope : 0.0;
}

std::size_t split_deviating_faces(Mesh& mesh, const Volume& volume, double threshold, double tolerance_mm,
                                  double min_edge_mm, int generation, double noise_mm) {
  const double search = std::max(3.0 * tolerance_mm, 1.5 * volume.voxel_size());
  return split_longest_edges(mesh, generation, [&](Mesh::FaceHandle f, Mesh::HalfedgeHandle longest) {
    if (mesh.calc_edge_length(longest) <= min_edge_mm) return false;
    // A face with no crossing within reach is not near the surface (a part
    // the deformation did not reach): not the level of detail's business.
    const double deviation = face_deviation(mesh, f, volume, threshold, search, noise_mm);
    return deviation > tolerance_mm && std::isfinite(deviation);
  });
}

bool collapse_keeps_topology(Mesh& mesh, Mesh::HalfedgeHandle h) {
  if (mesh.is_boundary(mesh.edge_handle(h)) || !mesh.is_collapse_ok(h)) return false;
  const auto v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
  const auto a = mesh.to_vertex_handle(mesh.next_halfedge_handle(h));
  const auto b = mesh.to_vertex_handle(mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h)));
  if (a == b) return false;
  // Link condition: link(v0) ∩ link(v1) = link(edge) = {a, b}.
  std::vector<int> n0;
  for (auto w : mesh.vv_range(v0)) n0.push_back(w.idx());
  int shared = 0;
  for (auto w : mesh.vv_range(v1))
    if (std::find(n0.begin(), n0.end(), w.idx()) != n0.end()) {
      if (w != a && w != b) return false;
      ++shared;
    }
  if (shared != 2) return false;
  // a and b each lose an edge; the merged vertex has val(v0) + val(v1) - 4.
  return mesh.valence(a) > 3 && mesh.valence(b) > 3 && mesh.valence(v0) + mesh.valence(v1) >= 7;
}

CollapseChecker::CollapseChecker(const Mesh& mesh, double cell_size) : mesh_(&mesh) { rebuild(cell_size); }

void CollapseChecker::rebuild(double cell_size) { grid_.rebuild(*mesh_, cell_size, 0.0); }

void CollapseChecker::note_vertex(Mesh::VertexHandle v) {
  for (auto f : mesh_->vf_range(v)) grid_.insert(*mesh_, f);
}

namespace {

// A face a collapse moves, before and after: not degenerate, turned by less
// than the angle whose cosine is min_cos, and no new angle below min_angle
// or below the face's own smallest angle when that was already lower (never
// worse).
bool moved_face_ok(const Tri& before, const Tri& after, double min_cos, double min_angle) {
  const Vec3 nb = (before.p[1] - before.p[0]).cross(before.p[2] - before.p[0]);
  const Vec3 na = (after.p[1] - after.p[0]).cross(after.p[2] - after.p[0]);
  if (is_degenerate_triangle(after.p[0], after.p[1], after.p[2])) return false;
  if (!(nb.norm() > 0.0) || na.normalized().dot(nb.normalized()) < min_cos) return false;
  const double floor_angle = std::min(min_angle, smallest_angle(before.p[0], before.p[1], before.p[2]));
  return smallest_angle(after.p[0], after.p[1], after.p[2]) >= floor_angle;
}

}  // namespace

bool CollapseChecker::geometry_ok(Mesh::HalfedgeHandle h, const CollapseOptions& o) {
  const Mesh& mesh = *mesh_;
  const auto v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
  const Vec3 p1 = pos(mesh, v1);
  const auto gone0 = mesh.face_handle(h), gone1 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
  const double min_cos = std::cos(o.max_normal_change * M_PI / 180.0);
  std::vector<Tri> created;
  for (auto f : mesh.vf_range(v0)) {
    if (f == gone0 || f == gone1) continue;
    const Tri after = face_tri(mesh, f, v0.idx(), v1.idx(), p1);
    if (!moved_face_ok(face_tri(mesh, f), after, min_cos, o.min_angle)) return false;
    created.push_back(after);
  }
  for (const Tri& t : created) {
    const Vec3 lo = t.p[0].cwiseMin(t.p[1]).cwiseMin(t.p[2]), hi = t.p[0].cwiseMax(t.p[1]).cwiseMax(t.p[2]);
    bool clear = true;
    grid_.for_each_near(lo, hi, [&](int g) {
      const Mesh::FaceHandle fg(g);
      if (!clear || (mesh.has_face_status() && mesh.status(fg).deleted()) || fg == gone0 || fg == gone1) return;
      const Tri other = face_tri(mesh, fg, v0.idx(), v1.idx(), p1);
      if (other.id == t.id) return;  // the triangle itself
      const Vec3 olo = other.p[0].cwiseMin(other.p[1]).cwiseMin(other.p[2]);
      const Vec3 ohi = other.p[0].cwiseMax(other.p[1]).cwiseMax(other.p[2]);
      if ((olo.array() > hi.array()).any() || (ohi.array() < lo.array()).any()) return;
      if (triangles_intersect_improperly(t.p, t.id, other.p, other.id)) clear = false;
    });
    if (!clear) return false;
  }
  return true;
}

bool CollapseChecker::geometry_ok(Mesh::HalfedgeHandle h, const CollapseOptions& o, const Vec3& target) {
  return geometry_ok(h, o, target, scratch_);
}

bool CollapseChecker::geometry_ok(Mesh::HalfedgeHandle h, const CollapseOptions& o, const Vec3& target,
                                  Scratch& s) const {
  const Mesh& mesh = *mesh_;
  const auto v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
  const auto gone0 = mesh.face_handle(h), gone1 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
  const double min_cos = std::cos(o.max_normal_change * M_PI / 180.0);
  // Face f after the collapse: v0 and v1 both become v1 at `target`.
  const auto moved = [&](Mesh::FaceHandle f) {
    Tri t;
    int i = 0;
    for (auto v : mesh.fv_range(f)) {
      const bool merged = v == v0 || v == v1;
      t.id[i] = merged ? v1.idx() : v.idx();
      t.p[i] = merged ? target : pos(mesh, v);
      ++i;
    }
    return t;
  };
  s.created.clear();
  s.moved.clear();
  const bool all_kept = for_each_face_moved_by_collapse(mesh, h, [&](Mesh::FaceHandle f) {
    const Tri after = moved(f);
    if (!moved_face_ok(face_tri(mesh, f), after, min_cos, o.min_angle)) return false;
    s.created.emplace_back(after.p, after.id);
    s.moved.push_back(f.idx());
    return true;
  });
  if (!all_kept) return false;
  return moved_faces_clear(gone0, gone1, s);
}

bool CollapseChecker::moved_faces_clear(Mesh::FaceHandle gone0, Mesh::FaceHandle gone1, Scratch& s) const {
  const Mesh& mesh = *mesh_;
  const std::vector<int>& moved = s.moved;
  const std::vector<FilteredTriangle>& created = s.created;
  std::vector<Vec3>& box_lo = s.lo;  // each moved face's box
  std::vector<Vec3>& box_hi = s.hi;
  const auto box_of = [](const std::array<Vec3, 3>& p, Vec3& lo, Vec3& hi) {
    lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
    hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
  };
  const auto apart = [](const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
    return (alo.array() > bhi.array()).any() || (ahi.array() < blo.array()).any();
  };
  const auto scale = [](const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
    return (ahi.cwiseMax(bhi) - alo.cwiseMin(blo)).maxCoeff();
  };
  box_lo.resize(created.size());
  box_hi.resize(created.size());
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t i = 0; i < created.size(); ++i) {
    box_of(created[i].p, box_lo[i], box_hi[i]);
    lo = lo.cwiseMin(box_lo[i]);
    hi = hi.cwiseMax(box_hi[i]);
  }
  // The moved faces among themselves (the grid holds their old boxes).
  for (std::size_t i = 0; i < created.size(); ++i)
    for (std::size_t j = i + 1; j < created.size(); ++j)
      if (!apart(box_lo[i], box_hi[i], box_lo[j], box_hi[j]) &&
          triangles_intersect_improperly(created[i], created[j],
                                         scale(box_lo[i], box_hi[i], box_lo[j], box_hi[j])))
        return false;
  // Then every other face near them, found by one look at the grid over
  // their common box and tested against each moved face its box meets.
  if (++s.stamp == 0) {
    std::fill(s.stamps.begin(), s.stamps.end(), 0u);
    s.stamp = 1;
  }
  return !grid_.any_near_once(lo, hi, s.stamps, s.stamp, [&](int g) {
    const Mesh::FaceHandle fg(g);
    if ((mesh.has_face_status() && mesh.status(fg).deleted()) || fg == gone0 || fg == gone1) return false;
    if (std::find(moved.begin(), moved.end(), g) != moved.end()) return false;
    const Tri t = face_tri(mesh, fg);  // not around the collapsed edge: it keeps its place
    Vec3 olo, ohi;
    box_of(t.p, olo, ohi);
    if (apart(olo, ohi, lo, hi)) return false;
    std::optional<FilteredTriangle> other;  // built for the first moved face its box meets
    for (std::size_t i = 0; i < created.size(); ++i) {
      if (apart(olo, ohi, box_lo[i], box_hi[i])) continue;
      if (!other) other.emplace(t.p, t.id);
      if (triangles_intersect_improperly(created[i], *other, scale(olo, ohi, box_lo[i], box_hi[i])))
        return true;
    }
    return false;
  });
}

std::size_t collapse_flat_edges(Mesh& mesh, const Volume* volume, double threshold, const CollapseOptions& o) {
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();
  std::vector<std::pair<double, int>> order;
  double sum = 0.0;
  for (auto e : mesh.edges()) {
    const double len = mesh.calc_edge_length(e);
    sum += len;
    order.emplace_back(len, e.idx());
  }
  if (order.empty()) return 0;
  std::sort(order.begin(), order.end());
  CollapseChecker checker(mesh, 2.0 * sum / static_cast<double>(order.size()));
  std::size_t collapses = 0;
  for (const auto& [len, ei] : order) {
    if (len >= o.max_length) break;  // shortest first: the rest are longer
    const Mesh::EdgeHandle e(ei);
    if (mesh.status(e).deleted()) continue;
    if (o.only_edges && !(*o.only_edges)[static_cast<std::size_t>(ei)]) continue;
    // Earlier collapses lengthen their neighbours' edges: the limit holds for the edge as it is now.
    if (o.max_length < std::numeric_limits<double>::infinity() && mesh.calc_edge_length(e) >= o.max_length) continue;
    for (int side = 0; side < 2; ++side) {
      const auto h = mesh.halfedge_handle(e, side);
      if (o.removable && !(*o.removable)[static_cast<std::size_t>(mesh.from_vertex_handle(h).idx())]) continue;
      if (!collapse_keeps_topology(mesh, h)) continue;
      if (!checker.geometry_ok(h, o)) continue;
      if (volume && o.tolerance > 0.0) {
        const auto v0 = mesh.from_vertex_handle(h), v1 = mesh.to_vertex_handle(h);
        const auto gone0 = mesh.face_handle(h), gone1 = mesh.face_handle(mesh.opposite_halfedge_handle(h));
        bool within = true;
        for (auto f : mesh.vf_range(v0)) {
          if (f == gone0 || f == gone1) continue;
          const Tri t = face_tri(mesh, f, v0.idx(), v1.idx(), pos(mesh, v1));
          if (triangle_deviation(t.p[0], t.p[1], t.p[2], *volume, threshold, o.search, o.noise).value() > o.tolerance) {
            within = false;
            break;
          }
        }
        if (!within) continue;
      }
      const auto kept = mesh.to_vertex_handle(h);
      mesh.collapse(h);
      checker.note_vertex(kept);
      ++collapses;
      break;
    }
  }
  return collapses;
}

}  // namespace gdm
