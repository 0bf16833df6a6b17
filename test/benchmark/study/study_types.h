// Plain data exchanged between the study's translation units. Each peer
// toolkit (VTK, ITK, CGAL) lives in its own translation unit behind functions
// that take and return these types, so that no translation unit includes two
// big toolkits (their Eigen copies and macros clash) and gdm headers stay out
// of the peers' units.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace study {

// A scalar volume, x fastest, axis-aligned (direction = identity); physical
// point of index i: origin + spacing .* i.
struct Image {
  std::array<int, 3> dims{0, 0, 0};
  std::array<double, 3> spacing{1.0, 1.0, 1.0};
  std::array<double, 3> origin{0.0, 0.0, 0.0};
  std::vector<float> values;
  double value(int i, int j, int k) const {
    return values[static_cast<std::size_t>(i) +
                  static_cast<std::size_t>(dims[0]) * (static_cast<std::size_t>(j) + static_cast<std::size_t>(dims[1]) * k)];
  }
};

using Point = std::array<double, 3>;

// An indexed triangle soup (it may be open, non-manifold or self-intersecting).
struct Surface {
  std::vector<Point> points;
  std::vector<std::array<int, 3>> faces;
  std::vector<int> generation;  // per point, only for gdm models (Fig. 11); empty otherwise
};

// What a peer run returns: the surface and its wall time.
struct PeerResult {
  Surface surface;
  double seconds = 0.0;
  std::string note;  // e.g. the parameter the run settled on
};

}  // namespace study
