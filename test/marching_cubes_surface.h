// Test helper: the marching-cubes iso-surface of a volume as a triangle soup
// (the same cell polygons phantoms::marching_cubes_triangle_count counts);
// distances to it through gdm::TriangleLocator.
#pragma once

#include <array>
#include <vector>

#include "gdm/triangle_locator.h"
#include "gdm/volume.h"

namespace gdm::test {

using gdm::Triangle;

// Each cell's polygons (corners at the linearly interpolated crossings on
// the cell edges, ambiguous faces separating the corners at or above the
// threshold), fan-triangulated; physical coordinates.
std::vector<Triangle> marching_cubes(const Volume& volume, double threshold);

}  // namespace gdm::test
