// Point-to-surface distance for the study's error figures (CGAL AABB tree).
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include "peer_cgal.h"

namespace study {

namespace {
using K = CGAL::Simple_cartesian<double>;
using Triangle = K::Triangle_3;
using Triangles = std::vector<Triangle>;
using Primitive = CGAL::AABB_triangle_primitive<K, Triangles::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;
}  // namespace

struct SurfaceDistance::Impl {
  Triangles triangles;
  Tree tree;
};

SurfaceDistance::SurfaceDistance(const Surface& s) : impl_(std::make_unique<Impl>()) {
  auto point = [&](int i) { return K::Point_3(s.points[i][0], s.points[i][1], s.points[i][2]); };
  impl_->triangles.reserve(s.faces.size());
  for (const auto& f : s.faces) {
    Triangle t(point(f[0]), point(f[1]), point(f[2]));
    if (!t.is_degenerate()) impl_->triangles.push_back(t);
  }
  impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
  if (!impl_->triangles.empty()) impl_->tree.accelerate_distance_queries();
}

SurfaceDistance::~SurfaceDistance() = default;

bool SurfaceDistance::empty() const { return impl_->triangles.empty(); }

double SurfaceDistance::operator()(const Point& p) const {
  return std::sqrt(impl_->tree.squared_distance(K::Point_3(p[0], p[1], p[2])));
}

}  // namespace study
