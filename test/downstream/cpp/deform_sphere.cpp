// Deforms a seed sphere in a small phantom (a ball of radius 8 mm in a 40^3
// volume of 0.5 mm voxels), through gdm::core (gdm::deform, gdm::measure)
// and gdm::pipeline (Otsu's threshold, the mesh writer).
//   deform_sphere [out.ply]   exit 0 when the mesh is closed, genus 0, without
//                             self-intersections and holds the ball's volume
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <vector>

#include "gdm/deformer.h"
#include "gdm/mesh_checks.h"
#include "gdm/mesh_io.h"
#include "gdm/seed.h"
#include "gdm/volume.h"
#include "gdm/volume_ops.h"

int main(int argc, char** argv) {
  const int n = 40;
  const double spacing = 0.5, radius = 8.0;
  const double centre = (n - 1) * spacing / 2.0;
  std::vector<float> values(static_cast<std::size_t>(n) * n * n);
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const double r = std::sqrt(std::pow(i * spacing - centre, 2) + std::pow(j * spacing - centre, 2) +
                                   std::pow(k * spacing - centre, 2));
        // 200 inside, 0 outside, a one-voxel linear edge
        const double t = std::min(1.0, std::max(0.0, (radius - r) / spacing + 0.5));
        values[static_cast<std::size_t>(i) + static_cast<std::size_t>(n) * (j + static_cast<std::size_t>(n) * k)] =
            static_cast<float>(200.0 * t);
      }
  const gdm::Volume volume({n, n, n}, values, gdm::Vec3::Constant(spacing));

  gdm::DeformOptions options;
  options.threshold = gdm::otsu_threshold(volume);  // gdm::pipeline
  gdm::Mesh mesh = gdm::make_icosahedron(gdm::Vec3::Constant(centre), 2.0);
  const gdm::DeformResult result = gdm::deform(mesh, volume, options);
  const gdm::MeshReport report = gdm::measure(mesh);
  const double expected = 4.0 / 3.0 * M_PI * radius * radius * radius;
  std::cout << "threshold " << options.threshold << ", " << gdm::to_string(result.reason) << " after "
            << result.cycles << " cycles: " << gdm::to_string(report) << "; volume " << report.volume
            << " mm^3 (ball " << expected << ")" << std::endl;
  if (argc > 1) gdm::write_mesh(mesh, argv[1]);

  const bool ok = result.reason == gdm::StopReason::converged && report.closed && report.two_manifold &&
                  report.genus == 0 && report.self_intersections == 0 &&
                  std::abs(report.volume - expected) < 0.05 * expected;
  std::cout << (ok ? "OK" : "FAILED") << std::endl;
  return ok ? EXIT_SUCCESS : EXIT_FAILURE;
}
