// Flood fill on a voxel grid by runs along x (scanline filling): the cavity
// fill (cavities.h) and the voxel topology (voxel_topology.h) flood most of
// their box several times, and a voxel-by-voxel flood spent most of its time
// recovering each voxel's coordinates from its index (three integer
// divisions) and pushing single voxels (issue 17). Here a run of passable
// voxels along x is marked at once and only its neighbouring rows are
// scanned, so each voxel is read a few times in memory order.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "gdm/volume.h"

namespace gdm {

// Marks every voxel of the n[0] x n[1] x n[2] grid (x fastest) that is
// connected to a seed through voxels for which passable(index) holds:
// 6-connected (faces), or 26-connected (faces, edges and corners) with
// `connect26`. The seeds are marked already (they need not be passable);
// a voxel marked before the call is never entered (it bounds the flood, as
// a wall would). passable must not depend on `marked`; it may be asked more
// than once for a voxel. The marks are the same as a voxel-by-voxel flood's.
template <typename Passable>
void flood_by_runs(const Index3& n, bool connect26, std::vector<char>& marked, const std::vector<std::size_t>& seeds,
                   Passable&& passable) {
  struct Run {
    int j, k, a, b;  // row (j, k), voxels a..b along x
  };
  const std::size_t nx = static_cast<std::size_t>(n[0]), ny = static_cast<std::size_t>(n[1]);
  const auto row = [&](int j, int k) { return nx * (static_cast<std::size_t>(j) + ny * static_cast<std::size_t>(k)); };
  std::vector<Run> runs;
  // The run through voxel x of row (j, k) (marked already): extended along
  // x over passable voxels not yet marked, marked, and queued.
  const auto take_run = [&](int j, int k, int x) {
    const std::size_t r = row(j, k);
    int a = x, b = x;
    while (a > 0 && !marked[r + static_cast<std::size_t>(a - 1)] && passable(r + static_cast<std::size_t>(a - 1)))
      marked[r + static_cast<std::size_t>(--a)] = 1;
    while (b < n[0] - 1 && !marked[r + static_cast<std::size_t>(b + 1)] && passable(r + static_cast<std::size_t>(b + 1)))
      marked[r + static_cast<std::size_t>(++b)] = 1;
    runs.push_back({j, k, a, b});
    return b;
  };
  for (const std::size_t c : seeds)
    take_run(static_cast<int>((c / nx) % ny), static_cast<int>(c / (nx * ny)), static_cast<int>(c % nx));
  while (!runs.empty()) {
    const Run r = runs.back();
    runs.pop_back();
    // Rows beside the run's: 4 (faces) or 8 (and edges); with corners the
    // run reaches one voxel further along x in them.
    for (int dk = -1; dk <= 1; ++dk)
      for (int dj = -1; dj <= 1; ++dj) {
        if ((dj == 0 && dk == 0) || (!connect26 && dj != 0 && dk != 0)) continue;
        const int j = r.j + dj, k = r.k + dk;
        if (j < 0 || k < 0 || j >= n[1] || k >= n[2]) continue;
        const int lo = connect26 ? std::max(0, r.a - 1) : r.a, hi = connect26 ? std::min(n[0] - 1, r.b + 1) : r.b;
        const std::size_t base = row(j, k);
        for (int x = lo; x <= hi; ++x) {
          const std::size_t c = base + static_cast<std::size_t>(x);
          if (marked[c] || !passable(c)) continue;
          marked[c] = 1;
          x = take_run(j, k, x);
        }
      }
  }
}

}  // namespace gdm
