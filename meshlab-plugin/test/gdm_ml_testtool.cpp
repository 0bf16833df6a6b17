// Inputs and checks for the MeshLab plugin's tests.
//   gdm_ml_testtool inputs <dir>      writes the phantom volume and the meshes
//   gdm_ml_testtool check <mesh> [--closed] [--manifold] [--genus g]
//       [--no-self-intersection] [--faces lo hi] [--phantom-sphere maxvox]
//       [--covers input.ply tol] [--no-contact input.ply] [--quality]
//   gdm_ml_testtool wrap <input> <output> <cell> <tolerance> [coverage rounds]
//       gdm::shrink_wrap (the shrink-wrap filter's work) outside MeshLab, its notes and time
// Exit code 0 when every requested check passes; prints the measurements.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <OpenMesh/Core/IO/MeshIO.hh>

#include "filter_parameters.h"
#include "gdm/mesh_io.h"
#include "gdm/float_snap.h"
#include "gdm/mesh_checks.h"
#include "gdm/obstacle.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"
#include "gdm/shrink_wrap.h"
#include "gdm/triangle_locator.h"
#include "wrap_pyramids.h"

void write_volume(const gdm::Volume& volume, const std::string& path);

namespace {

// The phantom: an ellipsoid in a 48 x 44 x 40 grid, spacing 1 x 1 x 1.25 mm,
// away from the origin (physical coordinates must survive the round trip).
gdm::phantoms::Grid phantom_grid() {
  gdm::phantoms::Grid g;
  g.dims = {48, 44, 40};
  g.spacing = gdm::Vec3(1.0, 1.0, 1.25);
  g.origin = gdm::Vec3(-30.0, 12.0, 100.0);
  return g;
}
const gdm::Vec3 kRadii(15.0, 12.0, 16.0);

bool write(const gdm::Mesh& mesh, const std::string& path,
           OpenMesh::IO::Options options = OpenMesh::IO::Options::Default) {
  if (!OpenMesh::IO::write_mesh(mesh, path, options)) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    return false;
  }
  return true;
}

// Deletes the faces whose centroid satisfies `cut`; drops isolated vertices.
template <typename Cut>
gdm::Mesh without_faces(gdm::Mesh mesh, Cut cut) {
  mesh.request_face_status();
  mesh.request_edge_status();
  mesh.request_vertex_status();
  for (auto f : mesh.faces()) {
    gdm::Vec3 c = gdm::Vec3::Zero();
    for (auto v : mesh.fv_range(f)) c += gdm::to_eigen(mesh.point(v)) / 3.0;
    if (cut(c)) mesh.delete_face(f, true);
  }
  mesh.garbage_collection();
  return mesh;
}

// A block of 30 x 20 x 10 mm whose top is the height field z = -depth for
// |x| < width / 2, z = 0 elsewhere (a slot along y), sampled in steps of
// 0.5 mm (the slot's walls slope over one step); the bottom and the sides are
// added as separate pieces (a soup: the wrap does not need them joined).
gdm::Mesh slot_block(double width, double depth) {
  gdm::Mesh mesh;
  const double step = 0.5, half = 0.5 * width, bottom = -10.0;
  const int nx = 61, ny = 41;
  const auto top = [&](double x) { return std::abs(x) < half ? -depth : 0.0; };
  const auto quad = [&](const gdm::Vec3& a, const gdm::Vec3& b, const gdm::Vec3& c, const gdm::Vec3& d) {
    const auto va = mesh.add_vertex(gdm::to_point(a)), vb = mesh.add_vertex(gdm::to_point(b)),
               vc = mesh.add_vertex(gdm::to_point(c)), vd = mesh.add_vertex(gdm::to_point(d));
    mesh.add_face(va, vb, vc);
    mesh.add_face(va, vc, vd);
  };
  std::vector<gdm::Mesh::VertexHandle> grid;
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = -15.0 + step * i, y = -10.0 + step * j;
      grid.push_back(mesh.add_vertex(gdm::Mesh::Point(x, y, top(x))));
    }
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i) {
      const auto a = grid[j * nx + i], b = grid[j * nx + i + 1], c = grid[(j + 1) * nx + i + 1],
                 d = grid[(j + 1) * nx + i];
      mesh.add_face(a, b, c);
      mesh.add_face(a, c, d);
    }
  quad({-15, -10, bottom}, {-15, 10, bottom}, {15, 10, bottom}, {15, -10, bottom});
  for (int i = 0; i + 1 < nx; ++i) {  // the sides along x follow the slot's profile
    const double x0 = -15.0 + step * i, x1 = x0 + step;
    quad({x0, -10, bottom}, {x1, -10, bottom}, {x1, -10, top(x1)}, {x0, -10, top(x0)});
    quad({x1, 10, bottom}, {x0, 10, bottom}, {x0, 10, top(x0)}, {x1, 10, top(x1)});
  }
  quad({15, -10, bottom}, {15, 10, bottom}, {15, 10, 0}, {15, -10, 0});
  quad({-15, 10, bottom}, {-15, -10, bottom}, {-15, -10, 0}, {-15, 10, 0});
  return mesh;
}

int inputs(const std::string& dir) {
  const auto grid = phantom_grid();
  const gdm::Vec3 c = grid.center();
  const gdm::Volume volume = gdm::phantoms::voxelize(grid, gdm::phantoms::ellipsoid(c, kRadii));
  write_volume(volume, dir + "/phantom.mha");
  // A seed inside the ellipsoid, off centre.
  if (!write(gdm::make_geodesic_sphere(c + gdm::Vec3(3, -2, 2), 4.0, 1), dir + "/seed_inside.off")) return 1;
  // An open seed: the same sphere without its top cap.
  const gdm::Vec3 sc = c + gdm::Vec3(3, -2, 2);
  if (!write(without_faces(gdm::make_geodesic_sphere(sc, 4.0, 1), [&](const gdm::Vec3& p) { return p.z() > sc.z() + 3.0; }),
             dir + "/seed_open.off"))
    return 1;
  // A non-manifold seed: two closed tetrahedra sharing one vertex (a bow tie), written by hand.
  {
    std::ofstream off(dir + "/seed_nonmanifold.off");
    const double x = c.x(), y = c.y(), z = c.z();
    off << "OFF\n7 8 0\n";
    off << x << " " << y << " " << z << "\n";
    off << x + 3 << " " << y << " " << z << "\n" << x << " " << y + 3 << " " << z << "\n" << x << " " << y << " " << z + 3 << "\n";
    off << x - 3 << " " << y << " " << z << "\n" << x << " " << y - 3 << " " << z << "\n" << x << " " << y << " " << z - 3 << "\n";
    off << "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
    off << "3 0 4 5\n3 0 6 4\n3 0 5 6\n3 4 6 5\n";
  }
  // The wrap input: a sphere of radius 20 with a hole (a cap of radius ~2)
  // and a small separate sphere beside it, in one file.
  {
    gdm::Mesh big = gdm::make_geodesic_sphere(gdm::Vec3(0, 0, 0), 20.0, 4);
    big = without_faces(big, [](const gdm::Vec3& p) { return p.z() > 19.9; });
    const gdm::Mesh small = gdm::make_geodesic_sphere(gdm::Vec3(27.0, 0, 0), 4.0, 2);
    std::vector<gdm::Mesh::VertexHandle> map;
    for (auto v : small.vertices()) map.push_back(big.add_vertex(small.point(v)));
    for (auto f : small.faces()) {
      std::vector<gdm::Mesh::VertexHandle> fv;
      for (auto v : small.fv_range(f)) fv.push_back(map[v.idx()]);
      big.add_face(fv);
    }
    const auto r = gdm::measure(big);
    std::printf("wrap input: %s\n", gdm::to_string(r).c_str());
    if (!write(big, dir + "/wrap_input.ply")) return 1;
    // The same input as a noisy scan: every vertex jittered by a Gaussian of
    // 0.3 mm per axis (fixed seed), so faces tilt and the holes' rims fray.
    std::mt19937 rng(7);
    std::normal_distribution<double> jitter(0.0, 0.3);
    for (auto v : big.vertices())
      big.set_point(v, gdm::to_point(gdm::to_eigen(big.point(v)) + gdm::Vec3(jitter(rng), jitter(rng), jitter(rng))));
    if (!write(big, dir + "/wrap_noisy.ply")) return 1;
  }
  // A block with a narrow slot across its top, 3 mm wide at the top, 2 mm at
  // the floor, 6 mm deep: the wrap's first convergence spans the slot with
  // faces longer than it is wide, its floor 2.5 mm from the wrap; the
  // coverage rounds must reach in (meshlab_shrink_wrap_slot).
  if (!write(slot_block(3.0, 6.0), dir + "/wrap_slot.ply")) return 1;
  std::printf("inputs written to %s\n", dir.c_str());
  return 0;
}


int check(int argc, char** argv) {
  const std::string path = argv[2];
  gdm::Mesh mesh;
  mesh.request_vertex_colors();
  OpenMesh::IO::Options opt;
  if (!OpenMesh::IO::read_mesh(mesh, path, opt)) {
    std::printf("FAIL cannot read %s\n", path.c_str());
    return 1;
  }
  const gdm::MeshReport r = gdm::measure(mesh);
  std::printf("%s: %s\n", path.c_str(), gdm::to_string(r).c_str());
  int failures = 0;
  const auto expect = [&](bool ok, const std::string& what) {
    std::printf("%s %s\n", ok ? "ok  " : "FAIL", what.c_str());
    if (!ok) ++failures;
  };
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--closed") expect(r.closed, "closed");
    else if (a == "--manifold") expect(r.two_manifold, "2-manifold");
    else if (a == "--genus") { const int g = std::atoi(argv[++i]); expect(r.genus == g && r.components == 1, "genus " + std::to_string(g) + ", one component (genus " + std::to_string(r.genus) + ", " + std::to_string(r.components) + " components)"); }
    else if (a == "--no-self-intersection") expect(r.self_intersections == 0, "no self-intersection (" + std::to_string(r.self_intersections) + " pairs)");
    else if (a == "--faces") {
      const double lo = std::atof(argv[i + 1]), hi = std::atof(argv[i + 2]);
      i += 2;
      expect(r.faces >= lo && r.faces <= hi, "faces " + std::to_string(r.faces) + " in [" + argv[i - 1] + ", " + argv[i] + "]");
    } else if (a == "--phantom") {
      const double limit = std::atof(argv[++i]);
      const auto grid = phantom_grid();
      const gdm::Vec3 c = grid.center();
      const double voxel = 1.0;  // report in mm
      const auto d = gdm::phantoms::vertex_distances(
          mesh, [&](const gdm::Vec3& p) { return gdm::phantoms::distance_to_ellipsoid(p, c, kRadii); }, voxel);
      char buf[200];
      std::snprintf(buf, sizeof buf, "distance to the analytic surface (mm): mean %.3f p95 %.3f max %.3f <= %.2f",
                    d.mean, d.p95, d.max, limit);
      expect(d.max <= limit, buf);
    } else if (a == "--covers") {
      const std::string input_path = argv[++i];
      const double tol = std::atof(argv[++i]);
      gdm::Mesh input;
      if (!OpenMesh::IO::read_mesh(input, input_path)) { expect(false, "read " + input_path); continue; }
      const gdm::TriangleLocator wrap(gdm::triangles_of(mesh));
      double worst = 0.0;
      for (auto v : input.vertices()) worst = std::max(worst, wrap.distance(gdm::to_eigen(input.point(v))));
      char buf[200];
      std::snprintf(buf, sizeof buf, "largest distance of the %zu input vertices from the wrap %.4f <= %.4f",
                    input.n_vertices(), worst, tol);
      expect(worst <= tol, buf);
    } else if (a == "--pyramids") {
      // At most `fraction` of the wrap's vertices farther than `beyond` from
      // the input stand out of their ring (wrap_pyramids.h).
      const std::string input_path = argv[++i];
      const double beyond = std::atof(argv[++i]), fraction = std::atof(argv[++i]);
      gdm::Mesh input;
      if (!OpenMesh::IO::read_mesh(input, input_path)) { expect(false, "read " + input_path); continue; }
      std::size_t free = 0;
      const std::size_t standing = gdm::test::pyramids(mesh, gdm::triangles_of(input), beyond, &free);
      char buf[200];
      std::snprintf(buf, sizeof buf, "%zu of the %zu vertices over holes (beyond %.3g mm) stand out of their ring <= %.3g",
                    standing, free, beyond, fraction);
      expect(static_cast<double>(standing) <= fraction * static_cast<double>(free), buf);
    } else if (a == "--no-contact") {
      // No face of the wrap touches the input (exact predicates), the input
      // taken at MeshLab's float precision as the plugin saw it.
      const std::string input_path = argv[++i];
      gdm::Mesh input;
      if (!OpenMesh::IO::read_mesh(input, input_path)) { expect(false, "read " + input_path); continue; }
      for (auto v : input.vertices())
        input.set_point(v, gdm::to_point(gdm::round_to_float(gdm::to_eigen(input.point(v)))));
      const gdm::Obstacle obstacle(gdm::triangles_of(input));
      std::size_t touching = 0;
      for (const auto& t : gdm::triangles_of(mesh)) touching += obstacle.blocks(t) ? 1 : 0;
      expect(touching == 0, "no face of the wrap touches the input (" + std::to_string(touching) + " do)");
    } else {
      std::printf("FAIL unknown check %s\n", a.c_str());
      ++failures;
    }
  }
  return failures == 0 ? 0 : 1;
}

// The input taken at float precision, as MeshLab hands it to the filter.
int wrap(int argc, char** argv) {
  gdm::Mesh input;
  if (!OpenMesh::IO::read_mesh(input, argv[2])) {
    std::fprintf(stderr, "cannot read %s\n", argv[2]);
    return 1;
  }
  for (auto v : input.vertices())
    input.set_point(v, gdm::to_point(gdm::round_to_float(gdm::to_eigen(input.point(v)))));
  gdm::WrapOptions w;
  w.cell_size = std::atof(argv[4]);
  w.tolerance = std::atof(argv[5]);
  if (argc > 6) w.coverage_rounds = std::atoi(argv[6]);
  std::vector<std::string> log;
  const auto start = std::chrono::steady_clock::now();
  gdm::Mesh mesh;
  try {
    gdm::WrapResult r = gdm::shrink_wrap(gdm::triangles_of(input), w);
    log = std::move(r.notes);
    mesh = std::move(r.mesh);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "Error: %s\n", e.what());
    return 1;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (const auto& l : log) std::printf("%s\n", l.c_str());
  std::printf("wrap time %.2f s\n", seconds);
  return write(mesh, argv[3], OpenMesh::IO::Options::Binary) ? 0 : 1;  // float coordinates, exact
}

}  // namespace

// Two mesh files hold the same mesh: the same vertices (compared as floats:
// MeshLab stores floats, and gdm's models end on float points) in the same
// order and the same triangles. Used to show that the gdm command and the
// MeshLab filter give one mesh for one volume and one set of options.
int same(const std::string& a, const std::string& b) {
  const gdm::MeshFileData x = gdm::read_mesh_file(a);
  const gdm::MeshFileData y = gdm::read_mesh_file(b);
  std::cout << a << ": " << x.points.size() << " vertices, " << x.triangles.size() << " faces; " << b << ": "
            << y.points.size() << " vertices, " << y.triangles.size() << " faces\n";
  if (x.points.size() != y.points.size() || x.triangles.size() != y.triangles.size()) {
    std::cerr << "different sizes\n";
    return 1;
  }
  std::size_t points = 0, faces = 0;
  for (std::size_t i = 0; i < x.points.size(); ++i)
    for (int d = 0; d < 3; ++d)
      if (static_cast<float>(x.points[i][d]) != static_cast<float>(y.points[i][d])) {
        ++points;
        break;
      }
  for (std::size_t f = 0; f < x.triangles.size(); ++f)
    if (x.triangles[f] != y.triangles[f]) ++faces;
  std::cout << points << " vertices and " << faces << " faces differ\n";
  return points == 0 && faces == 0 ? 0 : 1;
}

// `script FILTER OUT [name=value ...] [+cut=CONDITION]`: a meshlabserver
// script with every parameter at its default but those given
// (gdm_meshlab::script); +cut appends MeshLab's face selection by CONDITION and
// its deletion (an open mesh from a closed one).
int write_script(int argc, char** argv) {
  const std::string which = argv[2];
  const gdm_meshlab::Filter filter = which == "from_volume" ? gdm_meshlab::Filter::from_volume
                                     : which == "deform_mesh" ? gdm_meshlab::Filter::deform_mesh
                                                              : gdm_meshlab::Filter::shrink_wrap;
  std::vector<std::pair<std::string, std::string>> values;
  std::string cut;
  for (int i = 4; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto eq = arg.find('=');
    if (arg.rfind("+cut=", 0) == 0) cut = arg.substr(5);
    else if (eq != std::string::npos) values.emplace_back(arg.substr(0, eq), arg.substr(eq + 1));
  }
  std::string text = gdm_meshlab::script(filter, values);
  if (!cut.empty()) {
    const auto end = text.rfind("</FilterScript>");
    text = text.substr(0, end) + " <filter name=\"Conditional Face Selection\">\n  <Param type=\"RichString\" value=\"" +
           cut + "\" name=\"condSelect\"/>\n </filter>\n <filter name=\"Delete Selected Faces and Vertices\"/>\n</FilterScript>\n";
  }
  std::ofstream(argv[3]) << text;
  return 0;
}

// `dialogs`: every dialog's labels and helps fit MeshLab 2020.09's dialog (a
// help longer than kDialogHelpCharacters is cut off mid-sentence beside its
// field), and every catalogue parameter names an option of the catalogue.
int dialogs() {
  int bad = 0;
  for (const gdm_meshlab::Filter f :
       {gdm_meshlab::Filter::from_volume, gdm_meshlab::Filter::deform_mesh, gdm_meshlab::Filter::shrink_wrap})
    for (const gdm_meshlab::FilterParam& p : gdm_meshlab::filter_parameters(f)) {
      std::string help = p.help;
      if (p.kind == gdm_meshlab::ParamKind::catalogue) {
        const gdm::OptionInfo* o = gdm_meshlab::catalogue_option(p.name);
        if (o == nullptr) {
          std::printf("%s: %s is no option of the catalogue\n", gdm_meshlab::filter_name(f).c_str(), p.name.c_str());
          ++bad;
          continue;
        }
        help = gdm_meshlab::dialog_help(*o, p);
      }
      const std::string label = gdm_meshlab::dialog_label(p);
      if (label.empty() || label.size() > 32 || help.empty() || help.size() > gdm_meshlab::kDialogHelpCharacters) {
        std::printf("%s: %s: label '%s' (%zu characters, at most 32), help '%s' (%zu, at most %zu)\n",
                    gdm_meshlab::filter_name(f).c_str(), p.name.c_str(), label.c_str(), label.size(), help.c_str(),
                    help.size(), gdm_meshlab::kDialogHelpCharacters);
        ++bad;
      }
    }
  return bad == 0 ? 0 : 1;
}

int main(int argc, char** argv) {
  if (argc >= 4 && std::string(argv[1]) == "script") return write_script(argc, argv);
  if (argc >= 2 && std::string(argv[1]) == "parameters") {
    std::cout << gdm_meshlab::parameters_markdown();
    return 0;
  }
  if (argc >= 2 && std::string(argv[1]) == "dialogs") return dialogs();
  if (argc >= 4 && std::string(argv[1]) == "same") return same(argv[2], argv[3]);
  if (argc >= 3 && std::string(argv[1]) == "inputs") return inputs(argv[2]);
  if (argc >= 3 && std::string(argv[1]) == "check") return check(argc, argv);
  if (argc >= 6 && std::string(argv[1]) == "wrap") return wrap(argc, argv);
  std::fprintf(stderr,
               "usage: gdm_ml_testtool script <filter> <out.mlx> [name=value...] | parameters | dialogs | inputs <dir> | check <mesh> [checks...] | same <mesh> <mesh> | "
               "wrap <in> <out> <cell> <tol> [rounds]\n");
  return 2;
}
