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
// cube_starts of a CubeColouring): the cubes split into contiguous runs of
// about equal numbers of items, one run per worker (at most `workers`, each
// numbered below it), each run's items in order.
template <class Body>
void run_colour(const std::vector<int>& items, const std::vector<std::size_t>& cube_starts, std::size_t workers,
                Body&& body) {
  const std::size_t cubes = cube_starts.size() - 1;
  workers = std::max<std::size_t>(1, std::min(workers, cubes));
  std::vector<std::size_t> first(workers + 1, cubes);
  first[0] = 0;
  for (std::size_t c = 0, w = 1; c < cubes && w < workers; ++c)
    if (cube_starts[c + 1] * workers >= w * items.size()) first[w++] = c + 1;
  const auto run = [&](std::size_t w) {
    for (std::size_t j = cube_starts[first[w]]; j < cube_starts[first[w + 1]]; ++j) body(items[j], w);
  };
  if (workers == 1)
    run(0);
  else
    detail::run_tasks(workers, static_cast<int>(workers), run);
}

}  // namespace gdm
