// Uniform-grid cells for spatial lookups (the intersection guard, obstacles):
// a point's cell at a given cell size, and a 64-bit key per cell.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>

#include "gdm/mesh.h"

namespace gdm {

using CellKey = std::uint64_t;

// 21 bits per axis, offset so that negative cells map to distinct keys.
inline CellKey cell_key(int x, int y, int z) {
  const auto u = [](int v) { return static_cast<CellKey>(static_cast<std::uint32_t>(v + (1 << 20)) & 0x1fffff); };
  return (u(x) << 42) | (u(y) << 21) | u(z);
}

inline std::array<int, 3> cell_of(const Vec3& p, double cell_size) {
  return {static_cast<int>(std::floor(p.x() / cell_size)), static_cast<int>(std::floor(p.y() / cell_size)),
          static_cast<int>(std::floor(p.z() / cell_size))};
}

}  // namespace gdm
