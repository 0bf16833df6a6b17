// ITK peers (BinaryMask3DMeshSource, DeformableSimplexMesh3DBalloonForceFilter)
// and the readers of the real scans. No gdm, VTK or CGAL header here.
#pragma once

#include <array>
#include <string>

#include "study_types.h"

namespace study {

void set_itk_threads(int threads);

// Marching cubes on the thresholded mask (value > threshold when the object is
// brighter, value < threshold otherwise).
PeerResult run_itk_binary_mask(const Image& image, double threshold, bool object_brighter);

// ITK's deformable simplex mesh with the balloon force: a sphere of
// `resolution` (RegularSphereMeshSource: 8 * 4^resolution triangles, dual to
// the simplex mesh) at `seed` (mm) inflates for `iterations` steps under the
// gradient of an edge map (Gaussian gradient magnitude, sigma 1 voxel, scaled
// to [0, 1]). The filter works in index units, so it runs on the image's
// index grid and the result is mapped back to physical space.
struct SimplexOptions {
  int resolution = 4;        // sphere subdivisions
  std::array<double, 3> radii{3.0, 3.0, 3.0};  // seed ellipsoid semi-axes, voxels
  int iterations = 300;      // deformation steps
  double alpha = 0.2;        // internal force weight (ITK's typical range 0.01..0.3)
  double beta = 0.5;         // external (edge) force weight
  double gamma = 0.05;       // reference metrics update
  double kappa = 0.05;       // balloon force (negative: deflate from outside)
  double sigma = 1.0;        // Gaussian scale of the edge map, voxels
};
PeerResult run_itk_simplex(const Image& image, const Point& seed, const SimplexOptions& options);

// Reads a scan (any file ITK reads, or a DICOM directory) as float, resampled
// to nothing: the grid is kept, the direction must be (close to) axis aligned
// up to flips, which are undone. Throws std::runtime_error with the reason.
Image read_scan(const std::string& path);

}  // namespace study
