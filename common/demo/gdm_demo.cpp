// The core demo: grows a model inside a built-in phantom and prints what
// happened, cycle by cycle, and the checks of the result.
#include <chrono>
#include <cstdio>
#include <string>

#include "gdm/deformer.h"
#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"

#include <OpenMesh/Core/IO/MeshIO.hh>

int main(int argc, char** argv) {
  using namespace gdm;
  const std::string shape = argc > 1 ? argv[1] : "branching";
  const std::string out = argc > 2 ? argv[2] : "";
  phantoms::Grid grid;
  grid.dims = {64, 64, 64};
  phantoms::Sdf sdf;
  Vec3 seed_at = grid.center();
  if (shape == "sphere") {
    sdf = phantoms::sphere(grid.center(), 20.0);
  } else if (shape == "cube") {
    sdf = phantoms::difference(phantoms::box(Vec3(12, 12, 12), Vec3(52, 52, 52)),
                               phantoms::box(Vec3(32, 32, 32), Vec3(60, 60, 60)));
    seed_at = Vec3(24, 24, 24);
  } else if (shape == "tube") {
    sdf = phantoms::bent_tube(grid.center(), 18.0, 6.0, 1.5 * M_PI);
    seed_at = grid.center() + Vec3(18.0, 0.5, 0.0);
  } else if (shape == "bottle") {
    const Vec3 c = grid.center();
    const auto wall = phantoms::difference(phantoms::difference(phantoms::sphere(c, 20.0), phantoms::sphere(c, 16.0)),
                                           phantoms::capsule(c + Vec3(14, 0, 0), c + Vec3(22, 0, 0), 2.0));
    sdf = [wall](const Vec3& p) { return -wall(p); };
  } else {
    const Vec3 c = grid.center();
    sdf = phantoms::unite({phantoms::capsule(c + Vec3(0, 0, 18), c, 6.0),
                           phantoms::capsule(c, c + Vec3(14, 0, -18), 4.5),
                           phantoms::capsule(c, c + Vec3(-12, 8, -18), 4.5),
                           phantoms::capsule(c, c + Vec3(-4, -14, -16), 4.0)});
    seed_at = c + Vec3(0, 0, 10);
  }
  const Volume volume = phantoms::voxelize(grid, sdf);
  Mesh mesh = make_icosahedron(seed_at, 3.0);
  DeformOptions options;
  options.threshold = 125.0;
  for (int i = 3; i < argc; ++i) {
    const std::string kv = argv[i];
    const auto eq = kv.find('=');
    const std::string key = kv.substr(0, eq);
    const double value = std::stod(kv.substr(eq + 1));
    if (key == "a0") options.a0 = value;
    else if (key == "a1") options.a1 = value;
    else if (key == "a2") options.a2 = value;
    else if (key == "lod") options.lod_face_area = value;
    else if (key == "refine") options.global_refinements = static_cast<int>(value);
    else if (key == "rings") options.normal_rings = static_cast<int>(value);
    else if (key == "threads") options.threads = static_cast<int>(value);
    else if (key == "reach") options.reach = value;
    else if (key == "flips") options.improve_triangles = value != 0.0;
    else if (key == "tmax") options.max_topology_ratio = value;
    else if (key == "travel") options.refinement_travel = value;
    else if (key == "lodext") options.lod_topology_extent = value != 0.0;
    else if (key == "guard") options.prevent_self_intersection = value != 0.0;
    else std::fprintf(stderr, "unknown option %s\n", key.c_str());
  }
  const auto start = std::chrono::steady_clock::now();
  const DeformResult result = deform(mesh, volume, options, [](const CycleReport& r) {
    std::printf("cycle %3d stage %d  V %6zu F %6zu  evaluated %6zu moved %6zu splits %4zu  cost %.3f\n", r.cycle,
                r.stage, r.vertices, r.faces, r.evaluated, r.moved, r.splits, r.mean_cost);
    return true;
  });
  const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  std::printf("%s after %d cycles in %.1f ms; %zu moves vetoed, %zu flips\n", to_string(result.reason).c_str(),
              result.cycles, ms, result.rejected_moves, result.flips);
  std::printf("%s\n", to_string(measure(mesh)).c_str());
  const auto d = phantoms::vertex_distances(mesh, sdf, volume.voxel_size());
  double farthest = 0.0;
  for (auto v : mesh.vertices()) farthest = std::max(farthest, (to_eigen(mesh.point(v)) - grid.center()).norm());
  std::printf("farthest vertex from the centre: %.2f\n", farthest);
  std::printf("distance to the true surface (voxels): mean %.3f p95 %.3f max %.3f\n", d.mean, d.p95, d.max);
  std::printf("marching cubes: %zu triangles\n", phantoms::marching_cubes_triangle_count(volume, 125.0));
  if (!out.empty()) OpenMesh::IO::write_mesh(mesh, out);
  return 0;
}
