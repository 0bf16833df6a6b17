// Exact orientation predicates (floating-point filter + expansion arithmetic)
// and the exact segment / triangle intersection tests built on them.
#include "gdm/predicates.h"
#include "gdm/triangle_separation.h"

#include <algorithm>
#include <cmath>

namespace gdm {
namespace {

// ---------------------------------------------------------------------------
// Floating-point expansion arithmetic.
//
// An expansion is an array of doubles, ordered by increasing magnitude and
// pairwise non-overlapping, whose exact (real) sum is the value represented.
// Zero components are removed as they appear (except that an expansion always
// keeps at least one component), so the last component carries the sign.
// All of this relies on IEEE round-to-nearest double arithmetic without
// extended precision (true on x86-64 SSE2 and AArch64) and on no overflow or
// underflow.
// ---------------------------------------------------------------------------

constexpr double kEpsilon = 0x1p-53;  // half an ulp of 1.0: unit round-off

// x + y == a + b exactly, x = fl(a + b).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  y = (a - a_virtual) + (b - b_virtual);
}

// x + y == a + b exactly, x = fl(a + b); requires |a| >= |b| (or a == 0).
inline void fast_two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  y = b - (x - a);
}

// x + y == a * b exactly, x = fl(a * b). std::fma rounds once, so the
// residual a * b - x is computed exactly.
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// h = e + b. h may be the same array as e. h needs room for elen + 1.
int grow_expansion(int elen, const double* e, double b, double* h) {
  double q = b;
  int hlen = 0;
  for (int i = 0; i < elen; ++i) {
    const double ei = e[i];  // read before h[hlen] (hlen <= i) is written
    double sum, tail;
    two_sum(q, ei, sum, tail);
    if (tail != 0.0) h[hlen++] = tail;
    q = sum;
  }
  if (q != 0.0 || hlen == 0) h[hlen++] = q;
  return hlen;
}

// h = e + f by growing e with every component of f (quadratic but simple;
// exact predicates only reach this on near-degenerate inputs). h may be the
// same array as e but not as f. h needs room for elen + flen.
int expansion_sum(int elen, const double* e, int flen, const double* f,
                  double* h) {
  if (h != e) std::copy(e, e + elen, h);
  int hlen = elen;
  for (int i = 0; i < flen; ++i) hlen = grow_expansion(hlen, h, f[i], h);
  return hlen;
}

// h = e * b. h must not overlap e; it needs room for 2 * elen.
int scale_expansion(int elen, const double* e, double b, double* h) {
  int hlen = 0;
  double q, tail;
  two_product(e[0], b, q, tail);
  if (tail != 0.0) h[hlen++] = tail;
  for (int i = 1; i < elen; ++i) {
    double product_high, product_low, sum;
    two_product(e[i], b, product_high, product_low);
    two_sum(q, product_low, sum, tail);
    if (tail != 0.0) h[hlen++] = tail;
    // |product_high| >= |sum| because the components of e do not overlap.
    fast_two_sum(product_high, sum, q, tail);
    if (tail != 0.0) h[hlen++] = tail;
  }
  if (q != 0.0 || hlen == 0) h[hlen++] = q;
  return hlen;
}

constexpr int kScratch = 64;  // enough for any scale_expansion below

// h = e * f as the sum over the components of f of e * f[j]. h must not
// overlap e or f; it needs room for 2 * elen * flen + 1. elen <= kScratch/2.
int expansion_product(int elen, const double* e, int flen, const double* f,
                      double* h) {
  double scaled[kScratch];
  h[0] = 0.0;
  int hlen = 1;
  for (int j = 0; j < flen; ++j) {
    const int slen = scale_expansion(elen, e, f[j], scaled);
    hlen = expansion_sum(hlen, h, slen, scaled, h);
  }
  return hlen;
}

// An approximation of the value of e with exactly the sign of e.
double expansion_estimate(int elen, const double* e) {
  double sum = 0.0;
  for (int i = 0; i < elen; ++i) sum += e[i];
  const double top = e[elen - 1];  // the largest component has e's sign
  if ((sum > 0.0) != (top > 0.0) || (sum < 0.0) != (top < 0.0)) return top;
  return sum;
}

// A difference a - b held exactly as an expansion of one or two components.
struct Diff {
  double v[2];
  int n;
};

inline Diff exact_diff(double a, double b) {
  Diff d;
  double x, y;
  two_sum(a, -b, x, y);
  if (y != 0.0) {
    d.v[0] = y;
    d.v[1] = x;
    d.n = 2;
  } else {
    d.v[0] = x;
    d.n = 1;
  }
  return d;
}

// h = p * q - r * s for two-component inputs; h needs room for 18.
int exact_minor(const Diff& p, const Diff& q, const Diff& r, const Diff& s,
                double* h) {
  double left[9], right[9];
  const int llen = expansion_product(p.n, p.v, q.n, q.v, left);
  int rlen = expansion_product(r.n, r.v, s.n, s.v, right);
  for (int i = 0; i < rlen; ++i) right[i] = -right[i];
  return expansion_sum(llen, left, rlen, right, h);
}

double orient2d_exact(const Vec2& a, const Vec2& b, const Vec2& c) {
  const Diff bx = exact_diff(b.x(), a.x()), by = exact_diff(b.y(), a.y());
  const Diff cx = exact_diff(c.x(), a.x()), cy = exact_diff(c.y(), a.y());
  double det[18];
  const int n = exact_minor(bx, cy, by, cx, det);
  return expansion_estimate(n, det);
}

double orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c,
                      const Vec3& d) {
  Diff B[3], C[3], D[3];
  for (int k = 0; k < 3; ++k) {
    B[k] = exact_diff(b[k], a[k]);
    C[k] = exact_diff(c[k], a[k]);
    D[k] = exact_diff(d[k], a[k]);
  }
  // Cofactor expansion along B: sum over k of B[k] * (C x D)[k].
  double total[3 * 72 + 1];
  int tlen = 1;
  total[0] = 0.0;
  for (int k = 0; k < 3; ++k) {
    const int k1 = (k + 1) % 3, k2 = (k + 2) % 3;
    double minor[18], term[72];
    const int mlen = exact_minor(C[k1], D[k2], C[k2], D[k1], minor);
    const int termlen = expansion_product(mlen, minor, B[k].n, B[k].v, term);
    tlen = expansion_sum(tlen, total, termlen, term, total);
  }
  return expansion_estimate(tlen, total);
}

// ---------------------------------------------------------------------------
// Intersection helpers.
// ---------------------------------------------------------------------------

inline int sign_of(double x) { return (x > 0.0) - (x < 0.0); }

// Projection dropping coordinate k, keeping the other two in cyclic order so
// that orient2d of a projected triangle has the sign of the normal's k-th
// component. Projected coordinates are input doubles: predicates stay exact.
inline Vec2 drop_axis(const Vec3& p, int k) {
  return Vec2(p[(k + 1) % 3], p[(k + 2) % 3]);
}

// Exact signs of the normal components of triangle abc are those of its three
// projected orientations. Returns the axis whose |orient2d| estimate is
// largest (its exact value is nonzero unless the triangle is degenerate), or
// -1 when all three are exactly zero (zero-area triangle).
int dominant_normal_axis(const Vec3& a, const Vec3& b, const Vec3& c) {
  int best = -1;
  double best_abs = 0.0;
  for (int k = 0; k < 3; ++k) {
    const double o = std::abs(
        orient2d(drop_axis(a, k), drop_axis(b, k), drop_axis(c, k)));
    if (o > best_abs) {
      best_abs = o;
      best = k;
    }
  }
  return best;
}

// Lexicographic order (x, then y). On a line it is a monotone order along
// the line, whatever the line's direction.
inline bool lex_less(const Vec2& a, const Vec2& b) {
  return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
}

// Closed 2D segments pq and rs (either may be a single point) meet.
bool segments_intersect_2d(const Vec2& p, const Vec2& q, const Vec2& r,
                           const Vec2& s) {
  const int o1 = sign_of(orient2d(p, q, r)), o2 = sign_of(orient2d(p, q, s));
  const int o3 = sign_of(orient2d(r, s, p)), o4 = sign_of(orient2d(r, s, q));
  if (o1 * o2 > 0 || o3 * o4 > 0) return false;  // strictly one side
  if (o1 != 0 || o2 != 0 || o3 != 0 || o4 != 0) return true;
  // All four points collinear: compare intervals along the common line.
  const Vec2& pq_lo = lex_less(q, p) ? q : p;
  const Vec2& pq_hi = lex_less(q, p) ? p : q;
  const Vec2& rs_lo = lex_less(s, r) ? s : r;
  const Vec2& rs_hi = lex_less(s, r) ? r : s;
  return !lex_less(pq_hi, rs_lo) && !lex_less(rs_hi, pq_lo);
}

// Point p in the closed 2D triangle abc, which must have nonzero area.
bool point_in_triangle_2d(const Vec2& p, const Vec2& a, const Vec2& b,
                          const Vec2& c) {
  const int s = sign_of(orient2d(a, b, c));
  return sign_of(orient2d(a, b, p)) * s >= 0 &&
         sign_of(orient2d(b, c, p)) * s >= 0 &&
         sign_of(orient2d(c, a, p)) * s >= 0;
}

// Closed 2D segment pq meets closed 2D triangle abc (any shape).
bool segment_intersects_triangle_2d(const Vec2& p, const Vec2& q,
                                    const Vec2& a, const Vec2& b,
                                    const Vec2& c) {
  if (orient2d(a, b, c) != 0.0) {
    // Convex region: the segment meets it iff an endpoint is inside or the
    // segment crosses the boundary.
    if (point_in_triangle_2d(p, a, b, c) || point_in_triangle_2d(q, a, b, c))
      return true;
  }
  // A zero-area triangle is the union of its edges.
  return segments_intersect_2d(p, q, a, b) ||
         segments_intersect_2d(p, q, b, c) || segments_intersect_2d(p, q, c, a);
}

// Closed 3D segments pq and rs meet. If they are not coplanar they cannot.
// If they are, all four points lie in a plane (or a line, or a point) and at
// least one coordinate projection is injective on it; a 3D intersection
// shows in every projection and an intersection in an injective projection
// lifts back to 3D, so "meet in all three projections" is exact.
bool segments_intersect_3d(const Vec3& p, const Vec3& q, const Vec3& r,
                           const Vec3& s) {
  if (orient3d(p, q, r, s) != 0.0) return false;
  for (int k = 0; k < 3; ++k) {
    if (!segments_intersect_2d(drop_axis(p, k), drop_axis(q, k),
                               drop_axis(r, k), drop_axis(s, k)))
      return false;
  }
  return true;
}

}  // namespace

double orient2d(const Vec2& a, const Vec2& b, const Vec2& c) {
  const double left = (b.x() - a.x()) * (c.y() - a.y());
  const double right = (b.y() - a.y()) * (c.x() - a.x());
  const double det = left - right;
  // Forward error of the plain evaluation is below about 3 eps (|left| +
  // |right|); 8 eps leaves a wide margin for the rounding of the bound.
  const double bound = 8.0 * kEpsilon * (std::abs(left) + std::abs(right));
  if (det > bound || -det > bound) return det;
  return orient2d_exact(a, b, c);
}

double orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double bx = b.x() - a.x(), by = b.y() - a.y(), bz = b.z() - a.z();
  const double cx = c.x() - a.x(), cy = c.y() - a.y(), cz = c.z() - a.z();
  const double dx = d.x() - a.x(), dy = d.y() - a.y(), dz = d.z() - a.z();
  const double cydz = cy * dz, czdy = cz * dy;
  const double czdx = cz * dx, cxdz = cx * dz;
  const double cxdy = cx * dy, cydx = cy * dx;
  const double det =
      bx * (cydz - czdy) + by * (czdx - cxdz) + bz * (cxdy - cydx);
  // Semi-static filter: the error of the plain evaluation is below about
  // 7 eps times the permanent (the same expression with absolute values);
  // 16 eps leaves a wide margin for the rounding of the bound itself.
  const double permanent = std::abs(bx) * (std::abs(cydz) + std::abs(czdy)) +
                           std::abs(by) * (std::abs(czdx) + std::abs(cxdz)) +
                           std::abs(bz) * (std::abs(cxdy) + std::abs(cydx));
  const double bound = 16.0 * kEpsilon * permanent;
  if (det > bound || -det > bound) return det;
  return orient3d_exact(a, b, c, d);
}

bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c) {
  return dominant_normal_axis(a, b, c) < 0;
}

bool segment_intersects_triangle(const Vec3& p, const Vec3& q, const Vec3& a,
                                 const Vec3& b, const Vec3& c) {
  const int axis = dominant_normal_axis(a, b, c);
  if (axis < 0) {
    // Zero-area triangle: it is the union of its three edges.
    return segments_intersect_3d(p, q, a, b) ||
           segments_intersect_3d(p, q, b, c) ||
           segments_intersect_3d(p, q, c, a);
  }
  const int sp = sign_of(orient3d(a, b, c, p));
  const int sq = sign_of(orient3d(a, b, c, q));
  if (sp * sq > 0) return false;  // both endpoints strictly on one side
  if (sp == 0 && sq == 0) {
    // Coplanar: the projection dropping the dominant normal axis is
    // injective on the plane, so the 2D test on projections is exact.
    return segment_intersects_triangle_2d(
        drop_axis(p, axis), drop_axis(q, axis), drop_axis(a, axis),
        drop_axis(b, axis), drop_axis(c, axis));
  }
  // The segment meets the plane in exactly one point X. The signs of the
  // tetrahedra (p, q, edge) tell on which side of each edge line X lies,
  // all with the same orientation: X is in the closed triangle iff they do
  // not disagree strictly (they cannot all vanish: X is on at most two edge
  // lines of a non-degenerate triangle).
  const int s1 = sign_of(orient3d(p, q, a, b));
  const int s2 = sign_of(orient3d(p, q, b, c));
  const int s3 = sign_of(orient3d(p, q, c, a));
  const bool any_positive = s1 > 0 || s2 > 0 || s3 > 0;
  const bool any_negative = s1 < 0 || s2 < 0 || s3 < 0;
  return !(any_positive && any_negative);
}

bool triangles_touch(const std::array<Vec3, 3>& t1,
                     const std::array<Vec3, 3>& t2) {
  // Two closed triangles meet iff an edge of one meets the other: if they
  // cross, the intersection's end points lie on edges; if one contains the
  // other (coplanar), the inner one's edges are inside the outer one.
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (segment_intersects_triangle(t1[i], t1[j], t2[0], t2[1], t2[2]))
      return true;
    if (segment_intersects_triangle(t2[i], t2[j], t1[0], t1[1], t1[2]))
      return true;
  }
  return false;
}

namespace {

// A floating-point filter for triangles_intersect_improperly: returns 0 when
// one triangle's plane provably separates the other triangle's unshared
// corners from it (all strictly on one side, by a margin far above rounding
// error), so the pair cannot meet improperly; -1 when it cannot tell (the
// exact code then decides; so it does for a nearly degenerate triangle).
// n1, n2: the normals (p1 - p0) x (p2 - p0) of t1, t2, len1, len2 their
// lengths; `scale` at least max |q - t1[0]| (infinity norm) over the corners
// q of both: the margins grow with it (a larger bound is more cautious,
// never wrong).
int separated_by_a_plane(const std::array<Vec3, 3>& t1, const std::array<int, 3>& ids1, const Vec3& n1, double len1,
                         const std::array<Vec3, 3>& t2, const std::array<int, 3>& ids2, const Vec3& n2, double len2,
                         double scale) {
  if (!(scale > 0.0) || !std::isfinite(scale)) return -1;
  const double least = 1e-6 * scale * scale;
  if (!(len1 > least) || !(len2 > least)) return -1;  // a (nearly) degenerate triangle goes to the exact code
  const auto plane_separates = [&](const std::array<Vec3, 3>& a, const Vec3& n, double n_norm,
                                   const std::array<Vec3, 3>& b, const std::array<int, 3>& ida,
                                   const std::array<int, 3>& idb) {
    const double margin = 1e-10 * n_norm * scale;
    int side = 0;
    for (int j = 0; j < 3; ++j) {
      if (idb[j] == ida[0] || idb[j] == ida[1] || idb[j] == ida[2]) continue;  // a shared corner
      const double d = n.dot(b[j] - a[0]);
      const int s = d > margin ? 1 : (d < -margin ? -1 : 0);
      if (s == 0 || (side != 0 && s != side)) return false;
      side = s;
    }
    return side != 0;
  };
  if (plane_separates(t1, n1, len1, t2, ids1, ids2) || plane_separates(t2, n2, len2, t1, ids2, ids1)) return 0;
  return -1;
}

// The same with everything computed here (scale: the least bound).
int separated_by_a_plane(const std::array<Vec3, 3>& t1, const std::array<int, 3>& ids1,
                         const std::array<Vec3, 3>& t2, const std::array<int, 3>& ids2) {
  double scale = 0.0;
  for (const auto* t : {&t1, &t2})
    for (const auto& p : *t) scale = std::max(scale, (p - t1[0]).cwiseAbs().maxCoeff());
  const Vec3 n1 = (t1[1] - t1[0]).cross(t1[2] - t1[0]), n2 = (t2[1] - t2[0]).cross(t2[2] - t2[0]);
  return separated_by_a_plane(t1, ids1, n1, n1.norm(), t2, ids2, n2, n2.norm(), scale);
}

// triangles_intersect_improperly once the plane filter could not tell.
bool intersect_improperly_after_the_plane_filter(const std::array<Vec3, 3>& t1, const std::array<int, 3>& ids1,
                                                 const std::array<Vec3, 3>& t2, const std::array<int, 3>& ids2) {
  if (const int quick = separated_by_an_axis(t1, ids1, t2, ids2); quick >= 0) return quick != 0;

  // Degenerate triangles: a zero-area face has no well-defined side, so it
  // counts as intersecting anything it touches, including a neighbour it only
  // shares vertices with (shared vertices always touch).
  if (is_degenerate_triangle(t1[0], t1[1], t1[2]) ||
      is_degenerate_triangle(t2[0], t2[1], t2[2]))
    return triangles_touch(t1, t2);

  // Shared corners, by vertex id: shared1[i] / shared2[j] mark corners of
  // t1 / t2 that appear in the other triangle.
  bool shared1[3] = {false, false, false}, shared2[3] = {false, false, false};
  int shared = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      if (ids1[i] == ids2[j]) {
        if (!shared1[i]) ++shared;
        shared1[i] = true;
        shared2[j] = true;
      }
    }
  }

  // No shared vertex: any contact at all is an intersection.
  if (shared == 0) return triangles_touch(t1, t2);

  // Same three vertices (duplicate face): they coincide entirely.
  if (shared >= 3) return true;

  if (shared == 1) {
    // One shared vertex v. Let Y1 (Y2) be where a ray from v leaves t1 (t2):
    // always a point of the edge opposite v. If the triangles share a point
    // X != v, the intersection (convex) contains segment vX, and along the
    // ray through X the nearer of Y1, Y2 lies in both triangles: so the
    // opposite edge of one of them touches the other. Conversely an opposite
    // edge does not contain v, so its touching the other triangle is an
    // intersection besides v. This covers both the transversal case and the
    // coplanar case, including an edge from v lying in the plane of the
    // other triangle with its direction inside (or on the boundary of) the
    // other's angle at v: that edge's far end, or the other's opposite
    // edge, is then caught.
    int i1 = 0, i2 = 0;
    while (!shared1[i1]) ++i1;
    while (!shared2[i2]) ++i2;
    const Vec3& p1 = t1[(i1 + 1) % 3];
    const Vec3& q1 = t1[(i1 + 2) % 3];
    const Vec3& p2 = t2[(i2 + 1) % 3];
    const Vec3& q2 = t2[(i2 + 2) % 3];
    return segment_intersects_triangle(p1, q1, t2[0], t2[1], t2[2]) ||
           segment_intersects_triangle(p2, q2, t1[0], t1[1], t1[2]);
  }

  // Two shared vertices u, v (a shared edge), apexes a (t1) and b (t2).
  // Non-coplanar: the planes meet only in line uv and each triangle meets
  // that line exactly in edge uv, so the contact is the shared edge: fine.
  // Coplanar with a, b on opposite sides of uv: contact is edge uv: fine.
  // Coplanar with a, b on the same side: the faces overlap (fold-over).
  int ia = 0, ib = 0;
  while (shared1[ia]) ++ia;
  while (shared2[ib]) ++ib;
  const Vec3& u = t1[(ia + 1) % 3];
  const Vec3& v = t1[(ia + 2) % 3];
  const Vec3& a = t1[ia];
  const Vec3& b = t2[ib];
  if (orient3d(u, v, a, b) != 0.0) return false;
  // Project on the plane of t1's dominant normal axis (injective there).
  const int axis = dominant_normal_axis(t1[0], t1[1], t1[2]);
  const Vec2 u2 = drop_axis(u, axis), v2 = drop_axis(v, axis);
  const int side_a = sign_of(orient2d(u2, v2, drop_axis(a, axis)));
  const int side_b = sign_of(orient2d(u2, v2, drop_axis(b, axis)));
  // side_a != 0 (t1 is not degenerate); side_b != 0 (t2 is not degenerate
  // and lies in the same plane).
  return side_a == side_b;
}

}  // namespace

bool triangles_intersect_improperly(const std::array<Vec3, 3>& t1,
                                    const std::array<int, 3>& ids1,
                                    const std::array<Vec3, 3>& t2,
                                    const std::array<int, 3>& ids2) {
  if (const int quick = separated_by_a_plane(t1, ids1, t2, ids2); quick >= 0) return quick != 0;
  return intersect_improperly_after_the_plane_filter(t1, ids1, t2, ids2);
}

FilteredTriangle::FilteredTriangle(const std::array<Vec3, 3>& points, const std::array<int, 3>& ids)
    : p(points), id(ids), normal((points[1] - points[0]).cross(points[2] - points[0])), length(normal.norm()) {}

bool triangles_intersect_improperly(const FilteredTriangle& a, const FilteredTriangle& b, double scale) {
  if (separated_by_a_plane(a.p, a.id, a.normal, a.length, b.p, b.id, b.normal, b.length, scale) >= 0) return false;
  return intersect_improperly_after_the_plane_filter(a.p, a.id, b.p, b.id);
}

}  // namespace gdm
