// Is the object cut by the scan? A growing model that reaches the volume's
// border has either leaked (wrong polarity or threshold, an opening in the
// wall: the seed's region is then the background, which wraps the whole
// scan) or follows an object the scan cuts (a head cut at the neck, a phantom
// longer than the series): its region meets the border on a small part of it.
// Measured on ../shared/data at Otsu's threshold, the seed's region covers
// 0.8 to 8 % of the border's voxels when it is the object and 92 to 100 % when
// it is the background, so a quarter tells them apart with room either side.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "gdm/cost_terms.h"  // Polarity
#include "gdm/volume.h"

namespace gdm {

// The most of the border's voxels an object cut by the scan may cover.
constexpr double kCutByScanBorderFraction = 0.25;

struct BorderContact {
  bool measured = false;                   // false: the seed voxel is not on the object's side of T
  bool complete = true;                    // false: the fill stopped once the region covered too much of the border
  std::size_t region_voxels = 0;           // voxels of the seed's region visited
  std::size_t border_voxels = 0;           // of them, on the volume's two outermost layers (within a voxel
                                           // of its edge)
  std::size_t border_total = 0;            // voxels of the two outermost layers
  std::array<std::size_t, 6> per_side{};   // region voxels on the sides -x, +x, -y, +y, -z, +z (index axes)

  // border_voxels / border_total.
  double fraction() const;
  // The region touches the border on at most kCutByScanBorderFraction of it.
  bool cut_by_scan() const;
  // "-z (1,234 voxels), +x (56 voxels)": the sides the region touches.
  std::string sides_text() const;
};

// The 6-connected region strictly on the object's side of T that holds
// voxel `seed`, and where it meets the volume's border. The fill stops as
// soon as the region covers more than `stop_fraction` of the border (it is
// then the background; `complete` is false), so it visits the object only
// when the object is what the seed is in.
BorderContact measure_border_contact(const Volume& volume, const Index3& seed, double threshold, Polarity polarity,
                                     double stop_fraction = kCutByScanBorderFraction);

}  // namespace gdm
