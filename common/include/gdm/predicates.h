// Exact geometric predicates on double coordinates.
//
// orient2d / orient3d return a double whose SIGN is exactly the sign of the
// real-number determinant of their (double) inputs; the magnitude is only an
// approximation. A cheap floating-point evaluation is used when a forward
// error bound proves its sign; otherwise the determinant is evaluated exactly
// with floating-point expansion arithmetic. Exactness assumes no overflow and
// no underflow in intermediate products (coordinates with magnitudes roughly
// between 1e-70 and 1e70 are safe); inputs must be finite.
#pragma once

#include <array>

#include <Eigen/Core>

#include "gdm/mesh.h"

namespace gdm {

using Vec2 = Eigen::Vector2d;

// Sign of det[b - a, c - a] = (b - a) x (c - a): positive when a, b, c turn
// counterclockwise, negative when clockwise, zero exactly when collinear.
double orient2d(const Vec2& a, const Vec2& b, const Vec2& c);

// Sign of det[b - a, c - a, d - a] = ((b - a) x (c - a)) . (d - a): positive
// when d lies on the side of the plane abc that the normal (b - a) x (c - a)
// points to (above a triangle a, b, c that is counterclockwise seen from
// above), negative on the other side, zero exactly when the four points are
// coplanar. Note: this is the opposite sign of Shewchuk's orient3d.
double orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

// True when the closed segment pq and the closed triangle abc share at least
// one point (touching counts). Exact, including coplanar configurations and
// degenerate (zero-length segment, zero-area triangle) inputs.
bool segment_intersects_triangle(const Vec3& p, const Vec3& q, const Vec3& a,
                                 const Vec3& b, const Vec3& c);

// True when the closed triangles t1 and t2 share at least one point.
bool triangles_touch(const std::array<Vec3, 3>& t1,
                     const std::array<Vec3, 3>& t2);

// True when the triangle has zero area (its three corners are collinear or
// coincide), decided exactly.
bool is_degenerate_triangle(const Vec3& a, const Vec3& b, const Vec3& c);

// True when two faces of one mesh intersect other than in what their shared
// vertices allow: ids1 / ids2 are the mesh vertex ids of the corners, so that
// shared corners are known combinatorially (equal positions with different
// ids do NOT count as shared). See predicates.cpp for the per-case rules:
//  - no shared vertex: any contact is improper;
//  - one shared vertex: improper when the triangles meet anywhere but there;
//  - two shared vertices (an edge): improper only for a fold-over (apexes
//    coplanar with the edge and on the same side of it);
//  - three shared vertices (duplicate face): improper;
//  - a zero-area triangle is improper with anything it touches, shared
//    vertices included.
bool triangles_intersect_improperly(const std::array<Vec3, 3>& t1,
                                    const std::array<int, 3>& ids1,
                                    const std::array<Vec3, 3>& t2,
                                    const std::array<int, 3>& ids2);

// A triangle with what the predicate's floating-point filter computes of
// it, for a caller that tests one triangle against many (the intersection
// guard): the normal (p[1] - p[0]) x (p[2] - p[0]) and its length.
struct FilteredTriangle {
  std::array<Vec3, 3> p;
  std::array<int, 3> id;
  Vec3 normal;
  double length = 0.0;
  FilteredTriangle() = default;
  FilteredTriangle(const std::array<Vec3, 3>& points, const std::array<int, 3>& ids);
};

// The same answer as triangles_intersect_improperly(a.p, a.id, b.p, b.id),
// with the normals computed once. `scale`: at least the largest coordinate
// difference (any axis) between a.p[0] and a corner of either triangle (the
// extent of a box around both will do); a larger bound only makes the
// filter more cautious, never the answer different.
bool triangles_intersect_improperly(const FilteredTriangle& a, const FilteredTriangle& b, double scale);

}  // namespace gdm
