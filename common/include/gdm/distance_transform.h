// The exact squared Euclidean distance transform on a voxel grid
// (Felzenszwalb and Huttenlocher's separable lower envelope of parabolas),
// with anisotropic spacing: used by the automatic seed (seeding.h) and by the
// gap gate (passage.h).
#pragma once

#include <vector>

#include "gdm/volume.h"

namespace gdm {

// Squared distance (mm^2) of every voxel of an n[0] x n[1] x n[2] grid (x
// fastest) to the nearest voxel where `sites` is set, exact; infinite where
// there is no site at all. The lines of each axis are independent: they run on
// `threads` workers (0 = all cores), and the result does not depend on it.
std::vector<double> squared_distance_to(const std::vector<char>& sites, const Index3& n, const Vec3& spacing,
                                        int threads = 0);

}  // namespace gdm
