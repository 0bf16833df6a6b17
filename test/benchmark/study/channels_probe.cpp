// Measures our GDM on the study's real scans (the same volumes as the study:
// averaged, padded, isolated) with and without refine_channels: faces, time,
// cycles, local refinement rounds, refused moves, volume, and the distance
// from the marching-cubes surface of the volume to the model. Not part of the
// study's report.
//
//   gdm_channels_probe --data ../shared/data --case ct-phantom|mri-skin|tooth-pulp|tooth-outer
//                      [--channels on|off] [--fill-cavities on|off] [--cap-handles on|off] [--threads N] [--lod A] [--out PREFIX] [--trace]
//
// --out writes PREFIX-<case>-<0|1>.ply and the volume as PREFIX-<case>.raw (a
// text line "nx ny nz sx sy sz ox oy oz", then floats); --trace prints the
// cycles (every 10th and those with splits) to stderr.
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstring>
#include <string>

#include "cases.h"
#include "gdm/deformer.h"
#include "gdm/mesh_io.h"
#include "gdm/mesh_checks.h"
#include "gdm/triangle_locator.h"
#include "marching_cubes_surface.h"
#include <algorithm>
#include <vector>

int main(int argc, char** argv) {
  std::string data = "../shared/data", only = "ct-phantom", out;
  int channels = -1, threads = 0;
  bool trace = false, fill = true, caps = true;
  double lod = 0.0;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&] { return std::string(argv[++i]); };
    if (a == "--data") data = value();
    else if (a == "--case") only = value();
    else if (a == "--channels") channels = value() == "on" ? 1 : 0;
    else if (a == "--threads") threads = std::stoi(value());
    else if (a == "--lod") lod = std::stod(value());
    else if (a == "--out") out = value();
    else if (a == "--trace") trace = true;
    else if (a == "--fill-cavities") fill = value() == "on";
    else if (a == "--cap-handles") caps = value() == "on";
  }
  study::CaseSet set = study::scan_cases(data);
  for (const study::Case& c : set.cases) {
    if (c.id != only) continue;
    const gdm::Volume volume(c.image.dims, c.image.values,
                             gdm::Vec3(c.image.spacing[0], c.image.spacing[1], c.image.spacing[2]),
                             gdm::Vec3(c.image.origin[0], c.image.origin[1], c.image.origin[2]));
    if (!out.empty()) {
      FILE* f = std::fopen((out + "-" + c.id + ".raw").c_str(), "wb");
      std::fprintf(f, "%d %d %d %g %g %g %g %g %g\n", c.image.dims[0], c.image.dims[1], c.image.dims[2], c.image.spacing[0],
                   c.image.spacing[1], c.image.spacing[2], c.image.origin[0], c.image.origin[1], c.image.origin[2]);
      std::fwrite(c.image.values.data(), sizeof(float), c.image.values.size(), f);
      std::fclose(f);
    }
    std::vector<gdm::Triangle> truth = gdm::test::marching_cubes(volume, c.threshold);
    for (int on : {0, 1}) {
      if (channels >= 0 && on != channels) continue;
      gdm::DeformOptions o;
      o.threshold = c.threshold;
      o.polarity = c.object_brighter ? gdm::Polarity::object_brighter : gdm::Polarity::object_darker;
      o.mode = c.mode;
      o.threads = threads;
      o.gap = c.gap;
      o.refine_channels = on;
      o.fill_cavities = fill;
      o.cap_handles = caps;
      if (lod > 0.0) o.lod_face_area = lod;
      gdm::Mesh mesh = study::seed_mesh(c, 0);
      const auto t0 = std::chrono::steady_clock::now();
      const std::clock_t cpu0 = std::clock();  // the process's CPU time, all threads: the deformation alone
      auto last = std::chrono::steady_clock::now();
      const gdm::DeformResult r = gdm::deform(mesh, volume, o, [&](const gdm::CycleReport& c) {
        const auto now = std::chrono::steady_clock::now();
        if (trace && (c.cycle % 10 == 0 || c.splits > 0))
          std::fprintf(stderr, "cycle %d stage %d: %zu faces, %zu evaluated, %zu moved, %zu splits, %.1f ms\n", c.cycle, c.stage,
                       c.faces, c.evaluated, c.moved, c.splits, 1e3 * std::chrono::duration<double>(now - last).count());
        last = now;
        return true;
      });
      const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      std::printf("%s refine_channels=%d: %zu faces, %.2f s, %d cycles, %d rounds, %zu asking faces, volume %.1f mm^3, %s\n",
                  c.id.c_str(), on, static_cast<std::size_t>(mesh.n_faces()), s, r.cycles, r.channel_rounds,
                  r.channel_faces, gdm::measure(mesh).volume, gdm::to_string(r.reason).c_str());
      std::printf("  deformation CPU time %.2f s\n", static_cast<double>(std::clock() - cpu0) / CLOCKS_PER_SEC);
      std::printf("  rejected moves %zu, flips %zu\n", r.rejected_moves, r.flips);
      const gdm::TriangleLocator model(gdm::triangles_of(mesh));
      std::vector<double> d;
      for (const auto& t : truth) d.push_back(model.distance(t[0]) / volume.voxel_size());
      std::sort(d.begin(), d.end());
      double mean = 0.0;
      std::size_t far = 0;
      for (double x : d) { mean += x; far += x > 2.0 ? 1 : 0; }
      std::printf("  truth->model mean %.3f p95 %.3f max %.2f voxels, %.2f %% of truth points beyond 2 voxels\n", mean / d.size(),
                  d[d.size() * 95 / 100], d.back(), 100.0 * far / d.size());
      // The other way: the model's vertices to the marching-cubes surface.
      // Where the model caps a handle or closes a filled cavity it is off
      // that surface by design (topology solid).
      const gdm::TriangleLocator reference(truth);
      std::vector<double> m;
      for (auto v : mesh.vertices()) m.push_back(reference.distance(gdm::to_eigen(mesh.point(v))) / volume.voxel_size());
      std::sort(m.begin(), m.end());
      double mm = 0.0;
      for (double x : m) mm += x;
      std::printf("  model->truth mean %.3f p95 %.3f max %.2f voxels (vertices); %zu handles, %zu cavities filled\n",
                  mm / m.size(), m[m.size() * 95 / 100], m.back(), r.handles, r.cavities);
      std::fflush(stdout);
      if (!out.empty()) gdm::write_mesh(mesh, out + "-" + c.id + "-" + std::to_string(on) + ".ply");
    }
  }
  for (const auto& s : set.skipped) std::printf("skipped %s\n", s.c_str());
}
