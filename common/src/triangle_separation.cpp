#include "gdm/triangle_separation.h"

#include <algorithm>
#include <cmath>

namespace gdm {

int separated_by_an_axis(const std::array<Vec3, 3>& t1, const std::array<int, 3>& ids1,
                         const std::array<Vec3, 3>& t2, const std::array<int, 3>& ids2) {
  for (const auto* ids : {&ids1, &ids2})
    if ((*ids)[0] == (*ids)[1] || (*ids)[1] == (*ids)[2] || (*ids)[0] == (*ids)[2]) return -1;
  // The shared vertex, if any (more than one: the exact code decides).
  int s1 = -1, s2 = -1, shared = 0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (ids1[i] == ids2[j]) {
        s1 = i;
        s2 = j;
        ++shared;
      }
  if (shared > 1) return -1;
  if (shared == 1 && t1[s1] != t2[s2]) return -1;
  // Coordinates relative to t1[0]; `scale` bounds their size.
  std::array<Vec3, 3> a, b;
  double scale = 0.0;
  for (int i = 0; i < 3; ++i) {
    a[i] = t1[i] - t1[0];
    b[i] = t2[i] - t1[0];
    scale = std::max({scale, a[i].cwiseAbs().maxCoeff(), b[i].cwiseAbs().maxCoeff()});
  }
  if (!(scale > 0.0) || !std::isfinite(scale)) return -1;
  // The differences above round by up to an ulp of the coordinates, not of
  // the triangles: far from the origin, tiny triangles are left to the exact
  // code (below 1e-4 of the coordinates' size the rounding could reach the
  // margin; above it, it stays 10x below).
  double magnitude = 0.0;
  for (int i = 0; i < 3; ++i) magnitude = std::max({magnitude, t1[i].cwiseAbs().maxCoeff(), t2[i].cwiseAbs().maxCoeff()});
  if (!(scale > 1e-4 * magnitude)) return -1;
  const Vec3 n1 = (a[1] - a[0]).cross(a[2] - a[0]), n2 = (b[1] - b[0]).cross(b[2] - b[0]);
  if (!(n1.norm() > 1e-6 * scale * scale) || !(n2.norm() > 1e-6 * scale * scale)) return -1;
  // Whether the plane normal to `axis` (a vector taken as exact: only the
  // dot products round, by far less than the margin) separates them: every
  // corner of one strictly on one side, of the other strictly on the other;
  // a shared corner lies on the plane, which then meets each triangle there
  // alone.
  const auto separates = [&](const Vec3& axis) {
    const double length = axis.norm();
    if (!(length > 1e-9 * scale * scale)) return false;
    const double margin = 1e-10 * length * scale;
    double lo1 = INFINITY, hi1 = -INFINITY, lo2 = INFINITY, hi2 = -INFINITY;
    for (int i = 0; i < 3; ++i) {
      if (i != s1) {
        const double d = axis.dot(a[i]);
        lo1 = std::min(lo1, d);
        hi1 = std::max(hi1, d);
      }
      if (i != s2) {
        const double d = axis.dot(b[i]);
        lo2 = std::min(lo2, d);
        hi2 = std::max(hi2, d);
      }
    }
    if (shared == 1) {
      const double d = axis.dot(a[s1]);
      return (hi1 < d - margin && lo2 > d + margin) || (hi2 < d - margin && lo1 > d + margin);
    }
    return hi1 + margin < lo2 || hi2 + margin < lo1;
  };
  // In-plane edge normals first (coplanar neighbours), then edge x edge.
  for (int i = 0; i < 3; ++i) {
    if (separates(n1.cross(a[(i + 1) % 3] - a[i])) || separates(n2.cross(b[(i + 1) % 3] - b[i]))) return 0;
  }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (separates((a[(i + 1) % 3] - a[i]).cross(b[(j + 1) % 3] - b[j]))) return 0;
  return -1;
}

}  // namespace gdm
