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
};

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
// The wrap's field with bridging: `distance` (distance_field's output) where
// the input is within reach, and over openings that balls of radius `radius`
// coming from outside cannot pass (holes, the mouths of cavities) the balls'
// envelope, a smooth cap. The free space is the union of those balls: their
// centres are the cells farther than offset + radius from the input (an exact
// Euclidean distance transform of the grid from the cells within a cell of
// the input) that a flood fill from the grid's border reaches (the grid must
// reach offset + radius beyond the input: shrink_wrap pads it); the value is
// offset + radius + cell - (distance to the nearest reachable centre), and
// the result is the smaller of that and `distance`, so the wrap never stops
// farther from the input than the offset where balls do reach.
// Input points (`input`) the envelope would hide deeper than `hidden_depth`
// (mm; 0 = none) get no cap: within their depth plus the offset and two cells
// the plain distance decides (a cavity whose walls are input is entered,
// only true holes are capped); `reopened` gets the number of such regions.
Volume bridged_distance_field(const Volume& distance, double offset, double radius,
                              const std::vector<Vec3>& input = {}, double hidden_depth = 0.0,
                              std::size_t* reopened = nullptr);

// Reopens `field` (from bridged_distance_field) to `distance` within
// `radii[k]` of `points[k]`: the coverage rounds let the wrap down to input a
// cap hid.
void reopen_field(Volume& field, const Volume& distance, const std::vector<Vec3>& points,
                  const std::vector<double>& radii);

DistanceFieldSize distance_field_size(const std::vector<Triangle>& triangles, const Vec3& lo, const Vec3& hi,
                                      const DistanceFieldOptions& options);

}  // namespace gdm
