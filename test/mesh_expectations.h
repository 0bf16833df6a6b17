// Test helper: every guarantee of a gdm model, asserted together.
#pragma once

#include <gtest/gtest.h>

#include "gdm/mesh.h"
#include "gdm/mesh_checks.h"

namespace gdm::test {

// Closed, 2-manifold, genus 0, one component, no self-intersection, positive
// enclosed volume (outward orientation).
inline void expect_valid_closed_surface(const Mesh& mesh) {
  const MeshReport r = measure(mesh);
  EXPECT_TRUE(r.closed) << to_string(r);
  EXPECT_TRUE(r.two_manifold) << to_string(r);
  EXPECT_EQ(r.genus, 0) << to_string(r);
  EXPECT_EQ(r.components, 1) << to_string(r);
  EXPECT_EQ(r.self_intersections, 0u) << to_string(r);
  EXPECT_GT(r.volume, 0.0) << to_string(r);
}

}  // namespace gdm::test
