#include "gdm/voxel_topology.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdlib>

#include "gdm/voxel_flood.h"

namespace gdm {

namespace {

// Eight times the share of the cubical complex that one lattice point owns,
// by the 2 x 2 x 2 voxels around it (bit dx + 2 dy + 4 dz for the voxel on
// the +x side when dx = 1, and so on): the point itself when any voxel is
// set (1), each of its six edges when one of the four voxels along it is
// (-1/2, an edge has two ends), each of its twelve faces when one of the two
// voxels beside it is (+1/4, a face has four corners), each voxel set (-1/8).
std::array<int, 256> window_table() {
  std::array<int, 256> table{};
  const auto bit = [](int dx, int dy, int dz) { return 1 << (dx + 2 * dy + 4 * dz); };
  for (int config = 0; config < 256; ++config) {
    const auto set = [&](int dx, int dy, int dz) { return (config & bit(dx, dy, dz)) != 0; };
    int eight = config ? 8 : 0;
    for (int side = 0; side < 2; ++side) {  // the edges: along x (y, z) on the `side` half
      bool x = false, y = false, z = false;
      for (int a = 0; a < 2; ++a)
        for (int b = 0; b < 2; ++b) {
          x = x || set(side, a, b);
          y = y || set(a, side, b);
          z = z || set(a, b, side);
        }
      eight -= 4 * (int(x) + int(y) + int(z));
    }
    for (int a = 0; a < 2; ++a)  // the faces: normal z in quadrant (a, b) of the xy plane, and so on
      for (int b = 0; b < 2; ++b) {
        const bool normal_z = set(a, b, 0) || set(a, b, 1);
        const bool normal_y = set(a, 0, b) || set(a, 1, b);
        const bool normal_x = set(0, a, b) || set(1, a, b);
        eight += 2 * (int(normal_x) + int(normal_y) + int(normal_z));
      }
    eight -= __builtin_popcount(static_cast<unsigned>(config));
    table[static_cast<std::size_t>(config)] = eight;
  }
  return table;
}

std::size_t index(const Index3& n, int i, int j, int k) {
  return static_cast<std::size_t>(i) +
         static_cast<std::size_t>(n[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(n[1]) * static_cast<std::size_t>(k));
}

}  // namespace

std::array<std::ptrdiff_t, 27> neighbour_offsets(const Index3& n) {
  const std::ptrdiff_t sx = 1, sy = n[0], sz = static_cast<std::ptrdiff_t>(n[0]) * n[1];
  std::array<std::ptrdiff_t, 27> offset{};
  for (int s = 0; s < 27; ++s) offset[static_cast<std::size_t>(s)] = (s % 3 - 1) * sx + ((s / 3) % 3 - 1) * sy + (s / 9 - 1) * sz;
  return offset;
}

SimplePointTest::SimplePointTest() {
  const auto d = [](int s) { return std::array<int, 3>{s % 3 - 1, (s / 3) % 3 - 1, s / 9 - 1}; };
  for (int s = 0; s < 27; ++s) {
    if (s == kCentre) continue;
    const auto a = d(s);
    const int l1 = std::abs(a[0]) + std::abs(a[1]) + std::abs(a[2]);
    n26_ |= 1u << s;
    if (l1 <= 2) n18_ |= 1u << s;
    if (l1 == 1) faces_ |= 1u << s;
    for (int t = 0; t < 27; ++t) {
      if (t == kCentre || t == s) continue;
      const auto b = d(t);
      const int dx = std::abs(a[0] - b[0]), dy = std::abs(a[1] - b[1]), dz = std::abs(a[2] - b[2]);
      if (std::max({dx, dy, dz}) > 1) continue;
      adjacent26_[static_cast<std::size_t>(s)] |= 1u << t;
      if (dx + dy + dz == 1) adjacent6_[static_cast<std::size_t>(s)] |= 1u << t;
    }
  }
}

int SimplePointTest::components(std::uint32_t set, const std::array<std::uint32_t, 27>& adjacency,
                                std::uint32_t must_meet) {
  int count = 0;
  while (set & must_meet) {
    std::uint32_t component = set & must_meet & (~(set & must_meet) + 1u);  // lowest such bit
    std::uint32_t frontier = component;
    while (frontier) {
      std::uint32_t grown = 0;
      for (std::uint32_t f = frontier; f; f &= f - 1u) grown |= adjacency[static_cast<std::size_t>(__builtin_ctz(f))];
      frontier = grown & set & ~component;
      component |= frontier;
    }
    set &= ~component;
    ++count;
  }
  return count;
}

std::int64_t euler_characteristic(const std::vector<char>& set, const Index3& n) {
  static const std::array<int, 256> table = window_table();
  const std::vector<char> empty(static_cast<std::size_t>(n[0]), 0);
  // Row (j, k) of the grid, or an empty row outside it.
  const auto row = [&](int j, int k) {
    return (j < 0 || k < 0 || j >= n[1] || k >= n[2]) ? empty.data() : set.data() + index(n, 0, j, k);
  };
  std::int64_t eight = 0;
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j) {
      // The window's four rows: bit 2 dy + 4 dz names row (j - 1 + dy, k - 1 + dz).
      const char* rows[4] = {row(j - 1, k - 1), row(j, k - 1), row(j - 1, k), row(j, k)};
      if (rows[0] == empty.data() && rows[1] == empty.data() && rows[2] == empty.data() && rows[3] == empty.data()) continue;
      // Bit 2 r + 1 (voxel i of row r) becomes bit 2 r (voxel i - 1) at the
      // next window.
      int config = 0;
      for (int i = 0; i <= n[0]; ++i) {
        config = (config >> 1) & 0x55;
        if (i < n[0])
          for (int r = 0; r < 4; ++r)
            if (rows[r][i]) config |= 1 << (2 * r + 1);
        eight += table[static_cast<std::size_t>(config)];
      }
    }
  return eight / 8;
}

VoxelTopology voxel_topology(const std::vector<char>& set, const Index3& n) {
  VoxelTopology t;
  t.euler = euler_characteristic(set, n);
  const std::size_t count = set.size();
  std::vector<char> seen(count, 0);
  std::vector<std::size_t> seeds;
  const auto in_set = [&](std::size_t m) { return set[m] != 0; };
  const auto free = [&](std::size_t m) { return set[m] == 0; };
  for (std::size_t c = 0; c < count; ++c) {
    if (!set[c] || seen[c]) continue;
    ++t.pieces;
    seen[c] = 1;
    seeds.assign(1, c);
    flood_by_runs(n, true, seen, seeds, in_set);
  }
  // The complement reached from the border, then each pocket left.
  seeds.clear();
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const bool border = i == 0 || j == 0 || k == 0 || i == n[0] - 1 || j == n[1] - 1 || k == n[2] - 1;
        if (!border) {
          i = n[0] - 2;  // jump to the row's last voxel
          continue;
        }
        const std::size_t c = index(n, i, j, k);
        if (set[c] || seen[c]) continue;
        seen[c] = 1;
        seeds.push_back(c);
      }
  flood_by_runs(n, false, seen, seeds, free);
  for (std::size_t c = 0; c < count; ++c) {
    if (set[c] || seen[c]) continue;
    ++t.cavities;
    seen[c] = 1;
    seeds.assign(1, c);
    flood_by_runs(n, false, seen, seeds, free);
  }
  return t;
}

}  // namespace gdm
