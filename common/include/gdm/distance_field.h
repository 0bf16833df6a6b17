// The field a shrink-wrap collapses onto: the unsigned distance to a triangle
// soup sampled on a regular grid, for gdm::deform in Mode::shrink
// (gdm/shrink_wrap.h). Triangles in, gdm::Volume out.
#pragma once

#include <functional>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/triangle_locator.h"
#include "gdm/volume.h"

namespace gdm {

struct DistanceFieldOptions {
  double cell_size = 1.0;  // grid spacing, mm (> 0)
  double offset = 1.0;     // the wrap settles on the surface at this distance from the input, mm (> 0)
  double padding = 0.0;    // extra room around `lo`..`hi`, mm (the seed sphere must fit)
  double closing = 0.0;    // radius of balls rolled in from outside, mm (>= 0; 0 = none): openings a ball
                           // cannot pass are spanned by the balls' smooth envelope
};

// With `closing` = r > 0 the free space is what balls of radius r reach from
// the grid's border without coming within `offset` of the input (centres
// flood-filled from the border, then an exact Euclidean distance transform of
// the grid): the value is offset + r - the distance to the nearest reachable
// centre, so the wrap settles on the balls' envelope, which spans holes and
// cavity openings the balls cannot pass instead of sinking into them.
// The grid covers [lo - padding, hi + padding] plus two cells on each side.
// Values are the unsigned distance to the nearest triangle, clamped at
// offset + 3 cells (the far field only needs to be "free"). The object is
// where the value is below `offset`: pass threshold = offset and
// Polarity::object_darker to gdm::deform. `progress(fraction)` may return false
// to cancel (then an empty volume is returned). Throws InvalidOption (cell
// size or offset not positive, no triangles, a grid over 400 million cells).
Volume distance_field(const std::vector<Triangle>& triangles, const Vec3& lo, const Vec3& hi,
                      const DistanceFieldOptions& options, const std::function<bool(double)>& progress = {});

// What distance_field would build, without building it (for cost estimates):
// the grid's cells per axis, and the number of point-triangle distances it
// would evaluate (each triangle's box of cells within the clamp). Throws as
// distance_field does for a bad cell size or offset; no cell limit.
struct DistanceFieldSize {
  Index3 dims = {0, 0, 0};
  double cells = 0.0;        // dims[0] * dims[1] * dims[2]
  double evaluations = 0.0;  // point-triangle distances
};
DistanceFieldSize distance_field_size(const std::vector<Triangle>& triangles, const Vec3& lo, const Vec3& hi,
                                      const DistanceFieldOptions& options);

}  // namespace gdm
