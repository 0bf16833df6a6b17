// Triangles the model must never cross (beyond the paper). The paper's model
// samples the image at its vertices only, so a face can pass through a feature
// thinner than an edge, such as the rim of an open scanned surface; a
// shrink-wrap then leaves that feature poking out. With an obstacle, every
// vertex move and every edge flip is also checked, with exact predicates,
// against these triangles: what starts inside the model stays inside.
#pragma once

#include <array>
#include <vector>

#include "gdm/face_grid.h"
#include "gdm/mesh.h"

namespace gdm {

class Obstacle {
 public:
  using Triangle = std::array<Vec3, 3>;

  // Degenerate triangles (segments, points) are kept: a point cloud is an obstacle too.
  explicit Obstacle(std::vector<Triangle> triangles);

  // Does the triangle (a, b, c) touch any obstacle triangle?
  bool blocks(const Triangle& t) const;

  // Would moving v to p make one of its faces touch the obstacle?
  bool blocks_move(const Mesh& mesh, Mesh::VertexHandle v, const Vec3& p) const;

  std::size_t size() const { return triangles_.size(); }

 private:
  std::vector<Triangle> triangles_;
  FaceGrid grid_;  // over the triangles' boxes, no margin (the obstacle does not move)
};

}  // namespace gdm
