// Many moves at once, each still seen by the checks after it (issue 17):
// space cut into cubes wider than any one move's check reads, each cube
// coloured by the parities of its coordinates. Two cubes of one colour are
// a cube apart, so the moves of one colour's cubes may run on several
// threads at once while each cube's moves go one at a time in order; the
// outcome is that of one thread taking the colours, cubes and moves in
// that order, whatever the number of threads.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <cstddef>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/parallel.h"

namespace gdm {

// A round with fewer moves than this makes them in vertex order on one
// thread (the deformation cycles' and the fit's): below it the threads
// gain little, and the models of small inputs stay as they were.
constexpr std::size_t kMovesByCubes = 4096;

// The same for the sub-voxel fit's passes (surface_fit.h). Its moves are
// small and mostly accepted: an accepted move's answer does not depend on
// the order, so by cubes the models change only where the guard refuses
// some moves. Measured on gdm_core_benchmark with 2 threads (two series of
// runs alternating with 4096, README "The fit's moves on the threads"): the
// fit 5 to 10 % faster on the cube and the branching (their passes move
// 2,700 down to 60 vertices); no change on one thread (issue 17).
constexpr std::size_t kFitMovesByCubes = 256;

struct CubeColouring {
  // Per colour, the items cube after cube (cubes in a fixed order, each
  // cube's items ascending), and where each cube's run starts, then the end.
  std::array<std::vector<int>, 8> items;
  std::array<std::vector<std::size_t>, 8> cube_starts;
};

// Groups `items` (ascending; item k at points[k]) by cubes `width` wide.
CubeColouring colour_by_cubes(const std::vector<int>& items, const std::vector<Vec3>& points, double width);

// Calls body(item, worker) for every item of one colour (items and
// cube_starts of a CubeColouring), each cube's items in order on one worker
// (numbered below `workers`; no two run at once with the same number). The
// cubes go out in blocks of about equal numbers of items, kBlocksPerThread
// per worker, each to the next worker free: the cubes of one colour are
// independent, so which worker takes which changes nothing but the time
// (a fixed split into one run per worker left one thread idle for a
// seventh of the T1 head's cycles by cubes, where the moves' costs differ).
// What the body leaves per worker must therefore not depend on the order of
// the cubes: keep results per item (as the deformer keeps each move's wake
// request, applied afterwards in the colour's order) or add them up.
template <class Body>
void run_colour(const std::vector<int>& items, const std::vector<std::size_t>& cube_starts, std::size_t workers,
                Body&& body) {
  const std::size_t cubes = cube_starts.size() - 1;
  workers = std::max<std::size_t>(1, std::min(workers, cubes));
  if (workers == 1) {
    for (std::size_t j = cube_starts[0]; j < cube_starts[cubes]; ++j) body(items[j], std::size_t{0});
    return;
  }
  const std::size_t per_block = std::max<std::size_t>(1, items.size() / (workers * detail::kBlocksPerThread));
  std::vector<std::size_t> first{0};  // each block's first cube, then the end
  for (std::size_t c = 0; c < cubes; ++c)
    if (cube_starts[c + 1] - cube_starts[first.back()] >= per_block) first.push_back(c + 1);
  if (first.back() != cubes) first.push_back(cubes);
  std::atomic<std::size_t> next{0};
  detail::run_tasks(workers, static_cast<int>(workers), [&](std::size_t w) {
    for (std::size_t b = next.fetch_add(1, std::memory_order_relaxed); b + 1 < first.size();
         b = next.fetch_add(1, std::memory_order_relaxed))
      for (std::size_t j = cube_starts[first[b]]; j < cube_starts[first[b + 1]]; ++j) body(items[j], w);
  });
}

}  // namespace gdm
