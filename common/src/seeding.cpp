#include "gdm/seeding.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "gdm/distance_transform.h"
#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/seed.h"

namespace gdm {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

}  // namespace

AutoSeed find_auto_seed(const Volume& volume, double threshold, Polarity polarity) {
  if (!std::isfinite(threshold))
    throw InvalidOption("seed auto: the threshold must be a finite number (got " + number(threshold) + ")");
  const Index3& n = volume.dims();
  const std::vector<float>& values = volume.values();
  if (values.empty()) throw InvalidVolume("seed auto: the volume is empty");
  const bool brighter = polarity == Polarity::object_brighter;
  const std::size_t count = values.size();
  const std::size_t sx = 1, sy = static_cast<std::size_t>(n[0]), sz = sy * static_cast<std::size_t>(n[1]);

  // The object side of T, strictly beyond it (as the core's image event).
  std::vector<char> side(count);
  for (std::size_t i = 0; i < count; ++i) {
    const double x = values[i];
    side[i] = brighter ? (x > threshold) : (x < threshold);
  }

  // 6-connected regions, labelled in raster order of their first voxel.
  std::vector<std::uint32_t> label(count, 0);
  std::vector<std::size_t> stack;
  AutoSeed seed;
  std::uint32_t best_label = 0;
  std::size_t best_size = 0;
  for (std::size_t start = 0; start < count; ++start) {
    if (!side[start] || label[start] != 0) continue;
    const auto id = static_cast<std::uint32_t>(++seed.regions);
    std::size_t size = 0;
    label[start] = id;
    stack.push_back(start);
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      ++size;
      const int i = static_cast<int>(c % sy);
      const int j = static_cast<int>((c / sy) % static_cast<std::size_t>(n[1]));
      const int k = static_cast<int>(c / sz);
      const auto visit = [&](std::size_t o) {
        if (side[o] && label[o] == 0) {
          label[o] = id;
          stack.push_back(o);
        }
      };
      if (i > 0) visit(c - sx);
      if (i + 1 < n[0]) visit(c + sx);
      if (j > 0) visit(c - sy);
      if (j + 1 < n[1]) visit(c + sy);
      if (k > 0) visit(c - sz);
      if (k + 1 < n[2]) visit(c + sz);
    }
    if (size > best_size) {  // ties: the region found first
      best_size = size;
      best_label = id;
    }
  }
  if (seed.regions == 0)
    throw InvalidSeed(std::string("seed auto: no voxel is ") + (brighter ? "above" : "below") + " the threshold " +
                      number(threshold) + " (values range from " + number(volume.min_value()) + " to " +
                      number(volume.max_value()) + "); check the threshold and the polarity");
  seed.region_voxels = best_size;

  // The region's contour, as itk::SignedMaurerDistanceMapImageFilter sees it:
  // region voxels with a voxel outside the region among their 26 neighbours
  // inside the image (the image border itself is no contour).
  std::vector<char> region(count), contour(count, 0);
  for (std::size_t c = 0; c < count; ++c) region[c] = label[c] == best_label;
  label = {};
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t c = static_cast<std::size_t>(i) + sy * static_cast<std::size_t>(j) + sz * static_cast<std::size_t>(k);
        if (!region[c]) continue;
        bool edge = false;
        for (int dk = -1; dk <= 1 && !edge; ++dk) {
          const int kk = k + dk;
          if (kk < 0 || kk >= n[2]) continue;
          for (int dj = -1; dj <= 1 && !edge; ++dj) {
            const int jj = j + dj;
            if (jj < 0 || jj >= n[1]) continue;
            for (int di = -1; di <= 1; ++di) {
              const int ii = i + di;
              if (ii < 0 || ii >= n[0]) continue;
              if (!region[static_cast<std::size_t>(ii) + sy * static_cast<std::size_t>(jj) + sz * static_cast<std::size_t>(kk)]) {
                edge = true;
                break;
              }
            }
          }
        }
        contour[c] = edge;
      }
  const std::vector<double> squared = squared_distance_to(contour, n, volume.spacing());

  // The deepest interior voxel, the volume's border counting as boundary too
  // ((index + 0.5) voxels from it); the first in raster order on ties.
  const Vec3& spacing = volume.spacing();
  double best = -1.0;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const std::size_t c = static_cast<std::size_t>(i) + sy * static_cast<std::size_t>(j) + sz * static_cast<std::size_t>(k);
        if (!region[c] || contour[c]) continue;
        // Rounded to float as ITK's distance map (a float image) rounds it: the
        // seeds of earlier gdm versions (ITK's pipeline) are reproduced bit for bit.
        double depth = static_cast<float>(std::sqrt(squared[c]));
        const int idx[3] = {i, j, k};
        for (int d = 0; d < 3; ++d) {
          const int lo = idx[d], hi = n[d] - 1 - idx[d];
          depth = std::min(depth, (static_cast<double>(std::min(lo, hi)) + 0.5) * spacing[d]);
        }
        if (depth > best) {
          best = depth;
          seed.index = {i, j, k};
        }
      }
  if (!(best > 0.0))
    throw InvalidSeed("seed auto: the largest region " + std::string(brighter ? "above" : "below") +
                      " the threshold (" + std::to_string(best_size) +
                      " voxels) has no interior voxel: it is too thin for a seed");
  seed.depth = best;
  // Half the depth, but never below kMinGrowingSeedRadius voxels (seeding.h)
  // while the depth allows: a seed smaller than the optimiser's smallest steps
  // (a quarter to one voxel, section 3.2) does not grow. The depth is measured
  // to the region's contour voxels, which lie inside the object themselves.
  seed.radius = std::max(0.5 * best, std::min(best, kMinGrowingSeedRadius * volume.voxel_size()));
  seed.center = volume.to_physical(Vec3(seed.index[0], seed.index[1], seed.index[2]));
  return seed;
}

Mesh make_volume_box(const Volume& volume, double inset_voxels) {
  const Index3& n = volume.dims();
  if (!std::isfinite(inset_voxels) || inset_voxels < 0.0)
    throw InvalidOption("volume box: the inset must be a finite number >= 0 voxels (got " + number(inset_voxels) + ")");
  for (int d = 0; d < 3; ++d)
    if (!(2.0 * inset_voxels < n[d] - 1))
      throw InvalidOption("volume box: an inset of " + number(inset_voxels) + " voxels leaves no box along axis " +
                          std::to_string(d) + " (" + std::to_string(n[d]) + " voxels)");
  Mesh box;
  std::array<Mesh::VertexHandle, 8> v;
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 index;
    for (int d = 0; d < 3; ++d) index[d] = (corner >> d) & 1 ? (n[d] - 1) - inset_voxels : inset_voxels;
    v[static_cast<std::size_t>(corner)] = box.add_vertex(to_point(volume.to_physical(index)));
  }
  // Corner c has bit d set when it is at the high end of axis d; these faces
  // are outward in index space.
  static const int faces[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                   {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  // Outward in physical space: flip when the direction cosines mirror.
  const bool mirrored = volume.direction().determinant() < 0.0;
  for (const auto& f : faces) {
    if (mirrored)
      box.add_face(v[static_cast<std::size_t>(f[0])], v[static_cast<std::size_t>(f[2])], v[static_cast<std::size_t>(f[1])]);
    else
      box.add_face(v[static_cast<std::size_t>(f[0])], v[static_cast<std::size_t>(f[1])], v[static_cast<std::size_t>(f[2])]);
  }
  return box;
}

Mesh make_enclosing_sphere(const Volume& volume, double threshold, Polarity polarity, int level,
                           double margin_voxels) {
  if (!std::isfinite(threshold)) throw InvalidOption("enclosing sphere: the threshold must be finite");
  const Index3& n = volume.dims();
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  const bool brighter = polarity == Polarity::object_brighter;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const double v = volume.at(i, j, k);
        if (brighter ? !(v >= threshold) : !(v <= threshold)) continue;
        const Vec3 p(i, j, k);
        lo = lo.cwiseMin(p);
        hi = hi.cwiseMax(p);
      }
  if (!(lo.array() <= hi.array()).all()) {
    lo = Vec3::Zero();
    hi = Vec3(n[0] - 1, n[1] - 1, n[2] - 1);
  }
  lo -= Vec3::Constant(margin_voxels);
  hi += Vec3::Constant(margin_voxels);
  // The sphere around the box's corners, in physical space.
  const Vec3 centre = volume.to_physical(0.5 * (lo + hi));
  double radius = 0.0;
  for (int corner = 0; corner < 8; ++corner) {
    Vec3 index;
    for (int d = 0; d < 3; ++d) index[d] = (corner >> d) & 1 ? hi[d] : lo[d];
    radius = std::max(radius, (volume.to_physical(index) - centre).norm());
  }
  return make_geodesic_sphere(centre, radius, level);
}

Mesh prepare_seed_mesh(const Mesh& mesh, bool* reversed) {
  if (reversed) *reversed = false;
  check_seed_mesh(mesh);  // non-empty, finite, triangles, closed, 2-manifold

  const double volume = enclosed_volume(mesh);
  Vec3 lo = Vec3::Constant(kInf), hi = Vec3::Constant(-kInf);
  for (auto vh : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(vh));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const double extent = (hi - lo).maxCoeff();
  if (!std::isfinite(volume) || !(extent > 0.0) || std::abs(volume) <= 1e-12 * extent * extent * extent)
    throw InvalidSeed("the seed mesh encloses no volume (" + number(volume) +
                      "): it is flat or degenerate");

  const std::size_t crossings = self_intersecting_pairs(mesh);
  if (crossings > 0)
    throw InvalidSeed("the seed mesh intersects itself: " + std::to_string(crossings) + " face pairs");

  if (volume > 0.0) return mesh;

  // Inward: the same vertices, every face with its order swapped.
  Mesh out;
  std::vector<Mesh::VertexHandle> handle(mesh.n_vertices());
  const auto generation = find_generation_property(mesh);
  OpenMesh::VPropHandleT<int> out_generation;
  if (generation.is_valid()) out.add_property(out_generation, "v:generation");
  for (auto vh : mesh.vertices()) {
    handle[static_cast<std::size_t>(vh.idx())] = out.add_vertex(mesh.point(vh));
    if (generation.is_valid()) out.property(out_generation, handle[static_cast<std::size_t>(vh.idx())]) = mesh.property(generation, vh);
  }
  for (auto fh : mesh.faces()) {
    std::array<Mesh::VertexHandle, 3> f;
    int i = 0;
    for (auto vh : mesh.fv_range(fh)) f[static_cast<std::size_t>(i++)] = handle[static_cast<std::size_t>(vh.idx())];
    if (!out.add_face(f[0], f[2], f[1]).is_valid())
      throw InvalidSeed("the seed mesh could not be reversed (face " + std::to_string(fh.idx()) + ")");
  }
  if (!(enclosed_volume(out) > 0.0)) throw InvalidSeed("the reversed seed mesh still encloses no positive volume");
  if (reversed) *reversed = true;
  return out;
}

}  // namespace gdm
