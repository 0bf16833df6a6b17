// Test helper: the rotated ellipsoid on 0.5 x 0.5 x 2 mm voxels (thick
// slices, direction cosines, an origin off zero) that the phantom tests and
// the fit tests share.
#pragma once

#include "gdm/phantoms.h"

namespace gdm::test {

struct AnisotropicEllipsoid {
  phantoms::Grid grid;
  Vec3 center;
  Vec3 radii;
};

inline AnisotropicEllipsoid anisotropic_ellipsoid() {
  AnisotropicEllipsoid e;
  e.grid.dims = {72, 64, 20};
  e.grid.spacing = Vec3(0.5, 0.5, 2.0);
  e.grid.origin = Vec3(-12.0, 30.0, 100.0);
  e.grid.direction = Eigen::AngleAxisd(0.4, Vec3(0.3, 0.2, 1.0).normalized()).toRotationMatrix();
  e.center = e.grid.center();
  e.radii = Vec3(13.0, 10.0, 12.0);
  return e;
}

}  // namespace gdm::test
