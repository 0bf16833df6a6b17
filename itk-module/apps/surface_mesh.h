// The output mesh in plain arrays: what the writers and the report need,
// without ITK or OpenMesh types.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace gdm_cli {

struct SurfaceMesh {
  std::vector<std::array<double, 3>> points;        // physical coordinates, mm
  std::vector<std::array<std::uint32_t, 3>> faces;  // counterclockwise seen from outside
  std::vector<int> generation;                      // per point: the cycle that created it (section 6.4)
};

}  // namespace gdm_cli
