#include "gdm/surface_fit.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>

#include <Eigen/Cholesky>

#include "gdm/intersection_guard.h"
#include "gdm/parallel.h"
#include "gdm/space_blocks.h"

namespace gdm {

namespace {

// A polynomial of degree at most 3 in t, lowest coefficient first.
using Cubic = std::array<double, 4>;

double evaluate(const Cubic& a, double t) { return ((a[3] * t + a[2]) * t + a[1]) * t + a[0]; }

// a + f (b - a) for f affine in t (f0 + f1 t): one degree more than a, b.
Cubic lerp(const Cubic& a, const Cubic& b, double f0, double f1) {
  Cubic r{};
  for (int k = 0; k < 4; ++k) {
    const double diff = b[static_cast<std::size_t>(k)] - a[static_cast<std::size_t>(k)];
    r[static_cast<std::size_t>(k)] += a[static_cast<std::size_t>(k)] + f0 * diff;
    if (k < 3) r[static_cast<std::size_t>(k) + 1] += f1 * diff;
  }
  return r;
}

// The trilinear field along the continuous-index line c0 + t d, in the grid
// cell that holds the line's point at t: each interpolation weight is affine
// in t, so the field is a cubic there (the cell chosen as Volume::sample
// chooses it). False when that point is outside the grid.
bool cell_cubic(const Volume& volume, const Vec3& c0, const Vec3& d, double t, Cubic& out) {
  const Index3& n = volume.dims();
  const Vec3 c = c0 + t * d;
  int base[3];
  for (int a = 0; a < 3; ++a) {
    if (!(c[a] >= 0.0 && c[a] <= n[a] - 1)) return false;
    int b = static_cast<int>(c[a]);
    if (b >= n[a] - 1) b = n[a] - 2;
    base[a] = b;
  }
  const std::size_t sx = 1, sy = static_cast<std::size_t>(n[0]), sz = sy * static_cast<std::size_t>(n[1]);
  const float* p = volume.values().data() + base[0] * sx + base[1] * sy + base[2] * sz;
  const double fx0 = c0[0] - base[0], fy0 = c0[1] - base[1], fz0 = c0[2] - base[2];
  // Along x the differences of neighbours in float, as Volume::sample takes
  // them: the cubic is the field sample() gives, up to double rounding.
  const auto along_x = [&](std::size_t o) {
    const double diff = static_cast<double>(p[o + sx] - p[o]);
    return Cubic{p[o] + fx0 * diff, d[0] * diff, 0.0, 0.0};
  };
  const Cubic c00 = along_x(0), c10 = along_x(sy), c01 = along_x(sz), c11 = along_x(sz + sy);
  out = lerp(lerp(c00, c10, fy0, d[1]), lerp(c01, c11, fy0, d[1]), fz0, d[2]);
  return true;
}

// The crossing of the threshold nearest `near` in the bracket between t
// values `near` and `far` (both inside the grid, the field's signs there
// differing), solved on the field's cubic in each cell the segment passes
// through rather than by sampling the volume again: empty when rounding
// leaves the cubics without a sign change (the caller then samples).
std::optional<double> crossing_on_cubics(const Volume& volume, double threshold, const Vec3& p, const Vec3& dir,
                                         double near, double far) {
  const Vec3 c0 = volume.to_continuous_index(p);
  const Vec3 d = volume.to_continuous_index(p + dir) - c0;
  // Where the segment crosses a cell boundary, as fractions of the way from
  // near to far (at most one per axis for a bracket of a quarter voxel, a
  // few in general).
  std::array<double, 8> cut{};
  std::size_t cuts = 0;
  cut[cuts++] = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double from = c0[a] + near * d[a], to = c0[a] + far * d[a];
    if (from == to) continue;
    for (double k = std::floor(std::min(from, to)) + 1.0; k < std::max(from, to); k += 1.0) {
      if (cuts == cut.size() - 1) return std::nullopt;  // a bracket over many cells: the caller samples
      cut[cuts++] = (k - from) / (to - from);
    }
  }
  std::sort(cut.begin() + 1, cut.begin() + static_cast<std::ptrdiff_t>(cuts));
  cut[cuts++] = 1.0;
  const double tolerance = 1e-12 * std::abs(far - near);
  for (std::size_t k = 0; k + 1 < cuts; ++k) {
    double lo = near + cut[k] * (far - near), hi = near + cut[k + 1] * (far - near);
    if (lo == hi) continue;
    Cubic g;
    if (!cell_cubic(volume, c0, d, 0.5 * (lo + hi), g)) return std::nullopt;
    g[0] -= threshold;
    double glo = evaluate(g, lo), ghi = evaluate(g, hi);
    if (glo == 0.0) return lo;
    if ((glo <= 0.0) == (ghi <= 0.0) && ghi != 0.0) continue;
    if (ghi == 0.0) return hi;
    // Newton on the cubic from the secant point, kept inside the bracket
    // (a step that leaves it bisects): quadratic convergence, three or four
    // steps to the precision of the doubles.
    double t = (lo * ghi - hi * glo) / (ghi - glo);
    for (int it = 0; it < 60; ++it) {
      const double gt = evaluate(g, t);
      if (gt == 0.0) return t;
      if ((gt <= 0.0) == (glo <= 0.0)) {
        lo = t;
        glo = gt;
      } else {
        hi = t;
      }
      const double slope = (3.0 * g[3] * t + 2.0 * g[2]) * t + g[1];
      double next = t - gt / slope;
      if (!((next - lo) * (next - hi) < 0.0)) next = 0.5 * (lo + hi);  // also a zero or NaN slope
      if (!(std::abs(next - t) > tolerance)) return next;
      t = next;
    }
    return t;
  }
  return std::nullopt;
}

}  // namespace

std::optional<double> find_crossing(const Volume& volume, double threshold, const Vec3& p, const Vec3& dir,
                                    double max_mm, double step_mm) {
  const auto g = [&](double t) { return volume.sample(p + t * dir) - threshold; };
  // Inside the grid, and the value there (one index transform for both).
  const auto inside = [&](double t, double& gt) {
    if (!volume.sample_inside(p + t * dir, gt)) return false;
    gt -= threshold;
    return true;
  };
  double g0;
  if (!inside(0.0, g0)) return std::nullopt;
  if (g0 == 0.0) return 0.0;
  // Bracket: walk out on both sides at once, nearest crossing first.
  double lo = 0.0, glo = g0, hi = 0.0, ghi = 0.0;
  bool found = false;
  double prev_t[2] = {0.0, 0.0}, prev_g[2] = {g0, g0};
  bool alive[2] = {true, true};
  for (int k = 1; !found && (alive[0] || alive[1]); ++k) {
    const double t = std::min(k * step_mm, max_mm);
    for (int side = 0; side < 2 && !found; ++side) {
      if (!alive[side]) continue;
      const double ts = side == 0 ? t : -t;
      double gs;
      if (!inside(ts, gs)) {
        alive[side] = false;
        continue;
      }
      if ((gs <= 0.0) != (prev_g[side] <= 0.0) || gs == 0.0) {
        lo = prev_t[side];
        glo = prev_g[side];
        hi = ts;
        ghi = gs;
        found = true;
      }
      prev_t[side] = ts;
      prev_g[side] = gs;
    }
    if (t >= max_mm) break;
  }
  if (!found) return std::nullopt;
  if (ghi == 0.0) return hi;
  if (const auto t = crossing_on_cubics(volume, threshold, p, dir, lo, hi)) return t;
  // Illinois regula falsi: one step on a linear field, superlinear otherwise.
  int last_side = 0;
  for (int it = 0; it < 60; ++it) {
    const double t = (lo * ghi - hi * glo) / (ghi - glo);
    const double gt = g(t);
    if (gt == 0.0 || std::abs(hi - lo) < 1e-9 * step_mm) return t;
    if ((gt <= 0.0) == (glo <= 0.0)) {
      lo = t;
      glo = gt;
      if (last_side == -1) ghi *= 0.5;
      last_side = -1;
    } else {
      hi = t;
      ghi = gt;
      if (last_side == 1) glo *= 0.5;
      last_side = 1;
    }
    if (std::abs(gt) < 1e-10 * (std::abs(glo) + std::abs(ghi))) return t;
  }
  return (lo * ghi - hi * glo) / (ghi - glo);
}

namespace {

Vec3 pos(const Mesh& mesh, Mesh::VertexHandle v) { return to_eigen(mesh.point(v)); }

// Per-thread scratch of the per-vertex kernels below: they run for every
// vertex of every pass, and their lists were allocated afresh each time.
struct Scratch {
  std::vector<int> vertices, faces;
};
Scratch& scratch() {
  thread_local Scratch s;
  return s;
}

// The unit normal over the faces within `rings` rings of v (section 7), from
// the faces' normals of the pass (`face_normals`, face_area_normal() of each:
// every face is in the sums of a dozen vertices).
Vec3 smoothed_normal(const Mesh& mesh, Mesh::VertexHandle v, int rings, const std::vector<Vec3>& face_normals) {
  Scratch& s = scratch();
  vertices_within(mesh, v, rings - 1, s.vertices);
  faces_around(mesh, s.vertices, s.faces);
  Vec3 n = Vec3::Zero();
  for (int f : s.faces) n += face_normals[static_cast<std::size_t>(f)];
  const double len = n.norm();
  return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
}

// The quadratic height field h(x, y) = c0 + c1 x + c2 y + c3 x^2 + c4 x y +
// c5 y^2 fitted by least squares to the vertices within `rings` rings of v
// (v left out; they stay in scratch().vertices) in the tangent frame (t1, t2)
// of n, in coordinates scaled by the ring's extent (keeps the normal
// equations well conditioned whatever the units). False when the ring is too
// small or the fit fails.
struct RingQuadric {
  Eigen::Matrix<double, 6, 1> c;
  double extent = 0.0;
  Vec3 t1, t2;
  // The row of the normal equations for ring vertex w, and its height.
  Eigen::Matrix<double, 6, 1> row(const Mesh& mesh, const Vec3& p, const Vec3& n, int w, double& height) const {
    const Vec3 q = (pos(mesh, Mesh::VertexHandle(w)) - p) / extent;
    const double x = q.dot(t1), y = q.dot(t2);
    height = q.dot(n);
    Eigen::Matrix<double, 6, 1> r;
    r << 1.0, x, y, x * x, x * y, y * y;
    return r;
  }
};
bool fit_ring_quadric(const Mesh& mesh, Mesh::VertexHandle v, const Vec3& n, int rings, RingQuadric& quadric) {
  std::vector<int>& ring = scratch().vertices;
  vertices_within(mesh, v, rings, ring);
  ring.erase(std::find(ring.begin(), ring.end(), v.idx()));
  if (ring.size() < 9) return false;
  const Vec3 p = pos(mesh, v);
  quadric.t1 = n.unitOrthogonal();
  quadric.t2 = n.cross(quadric.t1);
  quadric.extent = 0.0;
  for (int w : ring) quadric.extent = std::max(quadric.extent, (pos(mesh, Mesh::VertexHandle(w)) - p).norm());
  if (quadric.extent <= 0.0) return false;
  Eigen::Matrix<double, 6, 6> ata = Eigen::Matrix<double, 6, 6>::Zero();
  Eigen::Matrix<double, 6, 1> ath = Eigen::Matrix<double, 6, 1>::Zero();
  for (int w : ring) {
    double height = 0.0;
    const Eigen::Matrix<double, 6, 1> row = quadric.row(mesh, p, n, w, height);
    // The lower triangle of row row^T added by hand: the same sums as
    // selfadjointView().rankUpdate(row), without its general product
    // kernel's overhead for a 6 x 6 matrix (a third of this function).
    for (int r = 0; r < 6; ++r)
      for (int c = 0; c <= r; ++c) ata(r, c) += row[r] * row[c];
    ath += row * height;
  }
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(ata.selfadjointView<Eigen::Lower>());
  if (ldlt.info() != Eigen::Success || !ldlt.isPositive()) return false;
  quadric.c = ldlt.solve(ath);
  return true;
}

// The height (mm, along n) of v above the quadratic height field fitted by
// least squares to its 2-ring in the tangent frame of n: zero wherever the
// surface is locally a quadric (a sphere, a cylinder, an ellipsoid to second
// order), so drawing a vertex toward it smooths noise without the shrinkage
// of Laplacian smoothing. NaN when the ring is too small to fit.
double height_above_quadric(const Mesh& mesh, Mesh::VertexHandle v, const Vec3& n) {
  RingQuadric quadric;
  if (!fit_ring_quadric(mesh, v, n, 2, quadric)) return std::numeric_limits<double>::quiet_NaN();
  const double c0 = quadric.c[0];
  return std::isfinite(c0) ? -c0 * quadric.extent : std::numeric_limits<double>::quiet_NaN();
}

// Beyond the paper (issue 16): the crossing of the trilinear field is not the
// crossing of the field the voxels sample. Along each index axis a the
// interpolation is linear, so on a field with second derivative H_aa it is
// off by f_a (1 - f_a) H_aa / 2 at fraction f_a of the cell (exact for a
// quadratic field: the mixed terms are bilinear and interpolated exactly).
// On an edge profile across a curved surface the part of H that is the
// surface's curvature, K (the Hessian of the signed distance, 1/mm,
// tangential), moves the crossing by
//   dt = sum_a f_a (1 - f_a) j_a^T K j_a / 2   (mm, outward),
// j_a the physical step of index axis a: a sphere of radius r voxels on a
// cubic grid has its trilinear crossing up to 1 / (4 r) voxel inside. The
// profile's own curvature along the normal is left out: it is the data's,
// not the surface's. K is taken from the model (its 3-ring fitted by a
// quadratic height field), not from second differences of the voxels, which
// amplify the noise and, near an edge of the object, see the edge's bend on
// the flat faces beside it. Only where that quadric fits the ring within
// kQuadricResidual: a crease or a corner (a box's edges) is no quadric, and
// the crease pass (creases.h) places those vertices.
constexpr int kCurvatureRings = 3;
// The pass from which the crossings are corrected, the curvature taken once
// per vertex then: the deformed model's rings are rough at first (from the
// third pass on, most of a sphere's rings were no quadric within
// kQuadricResidual and the gain was a third); by the fifth they are fitted.
constexpr int kCurvaturePass = 4;
constexpr double kQuadricResidual = 0.04;  // voxels, RMS

// The curvature terms of v: q_a = j_a^T K j_a (mm), K from the quadratic
// height field fitted by least squares to v's kCurvatureRings rings in the
// tangent frame of n. False when the ring is too small or the quadric does
// not fit it within kQuadricResidual.
bool curvature_terms(const Mesh& mesh, Mesh::VertexHandle v, const Vec3& n, const Volume& volume, Vec3& q) {
  RingQuadric quadric;
  if (!fit_ring_quadric(mesh, v, n, kCurvatureRings, quadric) || !quadric.c.allFinite()) return false;
  const Eigen::Matrix<double, 6, 1>& c = quadric.c;
  const std::vector<int>& ring = scratch().vertices;
  const Vec3 p = pos(mesh, v);
  double residual = 0.0;
  for (int w : ring) {
    double height = 0.0;
    const double e = quadric.row(mesh, p, n, w, height).dot(c) - height;
    residual += e * e;
  }
  const double extent = quadric.extent;
  if (std::sqrt(residual / static_cast<double>(ring.size())) * extent > kQuadricResidual * volume.voxel_size()) return false;
  // Height h(x, y) = extent (c3 (x/e)^2 + c4 (x/e)(y/e) + c5 (y/e)^2) + ...: its
  // Hessian [[2 c3, c4], [c4, 2 c5]] / extent; K = -Hess(h) (n outward).
  const double hxx = 2.0 * c[3] / extent, hxy = c[4] / extent, hyy = 2.0 * c[5] / extent;
  const Vec3 &t1 = quadric.t1, &t2 = quadric.t2;
  const Eigen::Matrix3d k =
      -(hxx * t1 * t1.transpose() + hxy * (t1 * t2.transpose() + t2 * t1.transpose()) + hyy * t2 * t2.transpose());
  for (int a = 0; a < 3; ++a) {
    Vec3 e = Vec3::Zero();
    e[a] = 1.0;
    const Vec3 j = volume.to_physical(e) - volume.to_physical(Vec3::Zero());
    q[a] = j.dot(k * j);
  }
  return true;
}

// The correction dt above at crossing x, from v's terms q: mm along the
// outward normal; none beyond half a voxel (not a second-order effect).
double trilinear_bias(const Volume& volume, const Vec3& x, const Vec3& q) {
  const Vec3 c = volume.to_continuous_index(x);
  double dt = 0.0;
  for (int a = 0; a < 3; ++a) {
    const double f = c[a] - std::floor(c[a]);
    dt += 0.5 * f * (1.0 - f) * q[a];
  }
  return std::abs(dt) < 0.5 * volume.voxel_size() ? dt : 0.0;
}

// Rounds of averaging each vertex's offset with its 1-ring's mean: one
// averages the image noise over two rings; more leave the deformation's
// high-frequency stair-steps uncorrected (measured: worse on every phantom).
constexpr int kOffsetSmoothing = 1;

struct Sample {
  Vec3 point;
  double weight;  // how far the sample moves when the vertex moves by one
};

}  // namespace

FitResult fit_to_threshold(Mesh& mesh, const Volume& volume, double threshold, const FitOptions& o,
                           std::vector<Vec3>& origin) {
  FitResult result;
  const double voxel = volume.voxel_size();
  const double max_move = o.max_distance * voxel;
  const double search = o.search * voxel, step = 0.25 * voxel;
  for (std::size_t i = origin.size(); i < mesh.n_vertices(); ++i)
    origin.push_back(pos(mesh, Mesh::VertexHandle(static_cast<int>(i))));
  const int threads = resolve_thread_count(o.threads);
  std::unique_ptr<IntersectionGuard> guard;
  std::vector<double> offset(mesh.n_vertices(), 0.0), smoothed;
  std::vector<Vec3> normal(mesh.n_vertices(), Vec3::Zero());
  std::vector<Vec3> face_normals;  // per pass: face_area_normal() of every face
  // Per vertex, the face that refused its last move (-1: none): the guard
  // tries it first. A vertex pressed against another sheet of the model is
  // refused by the same face at its half and quarter steps and in the next
  // passes; the answer does not depend on the hint (intersection_guard.h).
  std::vector<int> blocker(mesh.n_vertices(), -1);
  std::vector<char> has(mesh.n_vertices(), 0);
  std::vector<double> own(mesh.n_vertices(), 0.0);  // the vertex's own crossing distance (NaN: none)
  // Per vertex, the curvature terms of its crossings' correction, from the
  // model as the fit finds it (the curvature hardly changes over the passes):
  // 0 not yet known, 1 known, 2 none (no quadric there).
  std::vector<char> curvature_state(o.curvature_correction ? mesh.n_vertices() : 0, 0);
  std::vector<Vec3> curvature(o.curvature_correction ? mesh.n_vertices() : 0, Vec3::Zero());
  // Only vertices near a move are evaluated again: the rest already fit.
  std::vector<char> active(mesh.n_vertices(), 1), moved(mesh.n_vertices(), 0);
  // A move shorter than this is not made (FitOptions::still).
  const double still = std::max(0.0, o.still) * voxel;
  // The pass's moves: the vertices, each one's target, and whether it has one.
  std::vector<int> movers;
  std::vector<Vec3> goal(mesh.n_vertices(), Vec3::Zero());
  std::vector<char> moving(mesh.n_vertices(), 0);
  std::vector<IntersectionGuard::Checker> checkers;  // per thread, for moves by cubes
  std::vector<char> face_listed;                     // per face: listed among the moves' faces (all 0 between uses)
  for (int pass = 0; pass < o.passes; ++pass) {
    face_normals.resize(mesh.n_faces());
    parallel_for(mesh.n_faces(), threads, [&](std::size_t f) {
      const Mesh::FaceHandle h(static_cast<int>(f));
      const bool gone = mesh.has_face_status() && mesh.status(h).deleted();
      face_normals[f] = gone ? Vec3::Zero() : face_area_normal(mesh, h);
    });
    // 1. Every vertex's offset from the positions at the start of the pass:
    //    the weighted mean of the signed distances from its samples to the
    //    crossing. At the fixed point the surface around each vertex lies on
    //    the crossings on average (no chord bias, no curvature shrinkage).
    parallel_for(mesh.n_vertices(), threads, [&](std::size_t i) {
      const Mesh::VertexHandle v(static_cast<int>(i));
      has[i] = 0;
      if (mesh.has_vertex_status() && mesh.status(v).deleted()) return;
      if (mesh.is_isolated(v)) return;
      if (!active[i]) {
        offset[i] = 0.0;  // it and its neighbours stayed put: it still fits
        has[i] = 1;
        return;
      }
      const Vec3 n = smoothed_normal(mesh, v, o.normal_rings, face_normals);
      normal[i] = n;
      if (n.isZero()) return;
      const Vec3 p = pos(mesh, v);
      thread_local std::vector<Sample> samples;
      samples.clear();
      samples.push_back({p, 1.0});
      for (auto f : mesh.vf_range(v)) {
        Vec3 c = Vec3::Zero();
        for (auto w : mesh.fv_range(f)) c += pos(mesh, w);
        samples.push_back({c / 3.0, 1.0 / 3.0});
      }
      for (auto w : mesh.vv_range(v)) samples.push_back({0.5 * (p + pos(mesh, w)), 0.5});
      double num = 0.0, den = 0.0;
      own[i] = std::numeric_limits<double>::quiet_NaN();
      bool corrected = false;
      if (o.curvature_correction && pass >= kCurvaturePass) {
        if (curvature_state[i] == 0) curvature_state[i] = curvature_terms(mesh, v, n, volume, curvature[i]) ? 1 : 2;
        corrected = curvature_state[i] == 1;
      }
      for (const auto& s : samples) {
        auto d = find_crossing(volume, threshold, s.point, n, search, step);
        if (!d) continue;
        if (corrected) *d += trilinear_bias(volume, s.point + *d * n, curvature[i]);
        if (&s == &samples.front()) own[i] = *d;
        num += s.weight * *d;
        den += s.weight;
      }
      if (den <= 0.0) return;
      offset[i] = num / den;
      has[i] = 1;
    });
    // 2. Offsets averaged with their 1-ring's: noise is averaged over two
    //    rings; a constant offset (the quarter-voxel shortfall) passes whole.
    //    (Each vertex's new offset from the old ones only: on the threads.)
    smoothed = offset;
    for (int it = 0; it < kOffsetSmoothing; ++it) {
      std::vector<double> next = smoothed;
      parallel_for(mesh.n_vertices(), threads, [&](std::size_t i) {
        if (!has[i]) return;  // deleted and isolated vertices have none
        double s = 0.0;
        int k = 0;
        for (auto w : mesh.vv_range(Mesh::VertexHandle(static_cast<int>(i))))
          if (has[w.idx()]) {
            s += smoothed[w.idx()];
            ++k;
          }
        next[i] = k ? 0.5 * (smoothed[i] + s / k) : smoothed[i];
      });
      smoothed.swap(next);
    }
    //    The part h of a vertex's own offset that its ring does not share
    //    is kept in proportion h^2 / (h^2 + noise^2) (a Wiener-like
    //    shrinkage): on a clean image a lone vertex the deformation left a
    //    quarter voxel off is fitted within a few passes; on a noisy one the
    //    ring's mean decides, as before.
    if (o.noise >= 0.0)
      for (auto v : mesh.vertices()) {
        if (!has[v.idx()]) continue;
        const double h = offset[v.idx()] - smoothed[v.idx()];
        const double n2 = o.noise * o.noise;
        const double base = smoothed[v.idx()], given = base + h * h / (h * h + n2 + 1e-300) * h;
        // ... never past the vertex's own crossing (a corner stays inside).
        const double d = own[v.idx()];
        if (std::isnan(d))
          continue;
        else if (given > base)
          smoothed[v.idx()] = std::min(given, std::max(base, d));
        else
          smoothed[v.idx()] = std::max(given, std::min(base, d));
      }
    //    Beyond the data: where a vertex stands above the quadric through
    //    its 2-ring by little more than the noise explains, its offset is
    //    drawn toward that quadric (weight s^2 / (s^2 + h^2)). The offsets
    //    alone reach a fixed point where every vertex fits its own noisy
    //    samples; this gives the fit a smoothness prior that costs nothing
    //    on a quadric surface and lets real features (h >> s) stand.
    if (o.regularization > 0.0 && o.noise > 0.0) {
      const double s2 = std::pow(o.regularization * o.noise, 2);
      std::vector<double> height(mesh.n_vertices(), std::numeric_limits<double>::quiet_NaN());
      parallel_for(mesh.n_vertices(), threads, [&](std::size_t i) {
        if (has[i] && active[i] && !normal[i].isZero())
          height[i] = height_above_quadric(mesh, Mesh::VertexHandle(static_cast<int>(i)), normal[i]);
      });
      for (std::size_t i = 0; i < height.size(); ++i) {
        if (std::isnan(height[i])) continue;
        const double h2 = height[i] * height[i], w = o.quadric_step * s2 / (s2 + h2);
        smoothed[i] = (1.0 - w) * smoothed[i] - w * height[i];
      }
    }
    double sum2 = 0.0;
    std::size_t count = 0;
    for (auto v : mesh.vertices())
      if (has[v.idx()]) {
        sum2 += smoothed[v.idx()] * smoothed[v.idx()];
        ++count;
      }
    result.last_pass_rms = count ? std::sqrt(sum2 / static_cast<double>(count)) : 0.0;
    // 3. The moves, in vertex order, each checked by the guard. Every
    //    accepted move registers the faces' new boxes, so the grid covers
    //    the current faces without a margin for the travel: a small margin
    //    keeps the candidate lists short.
    //    One guard for all passes, its grid refreshed between them: only
    //    the faces a move touched are registered again (a rebuild every
    //    pass was a tenth of the fit, issue 17); it offers the exact tests
    //    every face a fresh guard would, so each yes/no is the same.
    if (o.prevent_self_intersection) {
      if (guard)
        guard->prepare_moves();
      else
        guard = std::make_unique<IntersectionGuard>(mesh, 0.05 * voxel, 1e-6 * voxel * voxel);
    }
    std::fill(moved.begin(), moved.end(), 0);
    //    Each vertex's target, from where the pass began (a vertex moves
    //    only by its own move).
    movers.clear();
    double travel = 0.0;
    for (auto v : mesh.vertices()) {
      if (!has[v.idx()] || !active[v.idx()]) continue;
      const Vec3 p = pos(mesh, v);
      Vec3 target = p + o.over_relaxation * smoothed[v.idx()] * normal[v.idx()];
      const Vec3& anchor = origin[v.idx()];
      const auto vi = static_cast<std::size_t>(v.idx());
      const double bound =
          vi < o.vertex_max_distance.size() && o.vertex_max_distance[vi] > 0.0 ? o.vertex_max_distance[vi] : max_move;
      if ((target - anchor).norm() > bound) target = anchor + (target - anchor).normalized() * bound;
      if ((target - p).norm() < still) continue;  // already there: spare the guard
      movers.push_back(v.idx());
      moving[vi] = 1;
      goal[vi] = target;
      travel = std::max(travel, (target - p).norm());
    }
    //    A move tries its full length, then half, then a quarter.
    const auto try_move = [&](int i, IntersectionGuard::Checker* checker, std::size_t& moves, std::size_t& rejected) {
      const Mesh::VertexHandle v(i);
      const auto vi = static_cast<std::size_t>(i);
      const Vec3 p = pos(mesh, v), target = goal[vi];
      for (int attempt = 0; attempt < 3; ++attempt) {
        const Vec3 q = p + (target - p) * std::ldexp(1.0, -attempt);
        if (!volume.contains(q)) continue;  // vertices stay inside the grid
        const bool safe =
            !guard || (checker ? guard->move_is_safe(v, q, blocker[vi], *checker) : guard->move_is_safe(v, q, blocker[vi]));
        if (safe) {
          blocker[vi] = -1;
          mesh.set_point(v, to_point(q));
          moved[vi] = (q - p).norm() > still;
          if (guard && !checker)
            for (auto f : mesh.vf_range(v)) guard->note_face(f);
          ++moves;
          return;
        }
        blocker[vi] = checker ? checker->last_blocking_face : guard->last_blocking_face();
      }
      ++rejected;
    };
    if (!guard || movers.size() < kFitMovesByCubes) {
      for (int i : movers) try_move(i, nullptr, result.moves, result.rejected);
    } else {
      //  Many moves: by cubes of space (space_blocks.h), the cubes of a
      //  colour on the threads at once. Each face around a move is first
      //  registered with the box of every place its corners may go this
      //  pass, so no move leaves the grid behind and the checks only read
      //  it; each answer is the guard's yes or no over the same faces.
      //  The faces around the moves, each once, ascending.
      std::vector<int>& faces = scratch().faces;
      faces.clear();
      face_listed.resize(mesh.n_faces(), 0);
      for (int i : movers)
        for (auto f : mesh.vf_range(Mesh::VertexHandle(i))) list_once(f.idx(), faces, face_listed);
      sort_listed(faces, face_listed);
      for (int f : faces) {
        Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
        for (auto w : mesh.fv_range(Mesh::FaceHandle(f))) {
          const Vec3 a = pos(mesh, w);
          const Vec3 b = moving[static_cast<std::size_t>(w.idx())] ? goal[static_cast<std::size_t>(w.idx())] : a;
          lo = lo.cwiseMin(a).cwiseMin(b);
          hi = hi.cwiseMax(a).cwiseMax(b);
        }
        guard->note_box(f, lo, hi);
      }
      std::vector<Vec3> at;
      at.reserve(movers.size());
      for (int i : movers) at.push_back(pos(mesh, Mesh::VertexHandle(i)));
      // A vertex within reach of a check may have moved its travel into it.
      const CubeColouring cubes = colour_by_cubes(movers, at, std::max(guard->reach() + 2.0 * travel, voxel));
      checkers.resize(static_cast<std::size_t>(threads));
      std::vector<std::size_t> moves(checkers.size(), 0), rejected(checkers.size(), 0);
      for (std::size_t c = 0; c < 8; ++c)
        run_colour(cubes.items[c], cubes.cube_starts[c], checkers.size(),
                   [&](int i, std::size_t w) { try_move(i, &checkers[w], moves[w], rejected[w]); });
      for (std::size_t w = 0; w < checkers.size(); ++w) {
        guard->absorb(checkers[w]);
        result.moves += moves[w];
        result.rejected += rejected[w];
      }
    }
    for (int i : movers) moving[static_cast<std::size_t>(i)] = 0;
    if (std::find(moved.begin(), moved.end(), 1) == moved.end()) break;  // a fixed point: nothing left to do
    parallel_for(mesh.n_vertices(), threads, [&](std::size_t i) {
      const Mesh::VertexHandle v(static_cast<int>(i));
      if (mesh.has_vertex_status() && mesh.status(v).deleted()) return;
      char a = moved[i];
      for (auto w : mesh.vv_range(v)) a |= moved[w.idx()];
      active[i] = a;
    });
  }
  return result;
}

}  // namespace gdm
