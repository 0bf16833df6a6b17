// gdm/mesh_io.h: every format round-trips, and hostile files are refused
// with gdm::InvalidInput (never a crash, never a huge allocation).
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/mesh_io.h"
#include "gdm/seed.h"

namespace fs = std::filesystem;

namespace {

fs::path scratch() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const fs::path dir = fs::temp_directory_path() /
                       ("gdm_mesh_io_" + std::to_string(::getpid()) + "_" + info->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void put(const fs::path& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

// A closed sphere away from the origin, generation = index % 7.
gdm::Mesh sample_mesh() {
  gdm::Mesh mesh = gdm::make_geodesic_sphere(gdm::Vec3(12.25, -40.5, 101.125), 7.3, 2);
  const auto g = gdm::generation_property(mesh);
  for (auto v : mesh.vertices()) mesh.property(g, v) = v.idx() % 7;
  return mesh;
}

TEST(MeshIo, every_format_round_trips) {
  const fs::path dir = scratch();
  const gdm::Mesh mesh = sample_mesh();
  for (const std::string ext : {".ply", ".obj", ".stl", ".off", ".vtk"}) {
    SCOPED_TRACE(ext);
    const std::string path = (dir / ("m" + ext)).string();
    gdm::write_mesh(mesh, path);
    EXPECT_FALSE(fs::exists(path + ".tmp-" + std::to_string(::getpid())));
    const gdm::MeshFileData data = gdm::read_mesh_file(path);
    ASSERT_EQ(data.points.size(), mesh.n_vertices());
    ASSERT_EQ(data.triangles.size(), mesh.n_faces());
    const bool as_float = ext == ".ply" || ext == ".stl";
    const auto stored = [&](const gdm::Vec3& p) -> gdm::Vec3 {
      if (!as_float) return p;
      return gdm::Vec3(static_cast<float>(p.x()), static_cast<float>(p.y()), static_cast<float>(p.z()));
    };
    if (ext == ".stl") {
      // Corners are welded in the order they appear: each read point is a
      // written vertex at float precision.
      for (const auto& p : data.points) {
        double nearest = 1e300;
        for (auto v : mesh.vertices()) nearest = std::min(nearest, (gdm::to_eigen(mesh.point(v)) - p).norm());
        EXPECT_LT(nearest, 1e-5) << p.transpose();
      }
    } else {
      for (auto v : mesh.vertices()) EXPECT_EQ(data.points[v.idx()], stored(gdm::to_eigen(mesh.point(v))));
      std::size_t f = 0;
      for (auto face : mesh.faces()) {
        int k = 0;
        for (auto v : mesh.fv_range(face)) EXPECT_EQ(data.triangles[f][k++], static_cast<std::uint32_t>(v.idx()));
        ++f;
      }
    }
    if (ext == ".ply" || ext == ".vtk") {
      ASSERT_EQ(data.generation.size(), mesh.n_vertices());
      for (auto v : mesh.vertices()) EXPECT_EQ(data.generation[v.idx()], v.idx() % 7);
    }
    const gdm::Mesh back = gdm::read_mesh(path);
    const gdm::MeshReport m = gdm::measure(back);
    EXPECT_TRUE(m.closed);
    EXPECT_TRUE(m.two_manifold);
    EXPECT_EQ(gdm::read_triangles(path).size(), mesh.n_faces());
    if (ext == ".ply" || ext == ".vtk") {
      EXPECT_TRUE(gdm::find_generation_property(back).is_valid());
    }
  }
}

TEST(MeshIo, ply_without_generation_has_no_generation_property) {
  const fs::path dir = scratch();
  gdm::Mesh mesh = gdm::make_geodesic_sphere(gdm::Vec3(0, 0, 0), 1.0, 1);
  auto g = gdm::find_generation_property(mesh);
  if (g.is_valid()) mesh.remove_property(g);
  gdm::write_mesh(mesh, (dir / "m.ply").string());
  std::ifstream in(dir / "m.ply", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(bytes.find("generation"), std::string::npos);
  EXPECT_TRUE(gdm::read_mesh_file((dir / "m.ply").string()).generation.empty());
}

const char* const kTetraPoints[] = {"0 0 0", "1 0 0", "0 1 0", "0 0 1"};

TEST(MeshIo, other_variants_read) {
  const fs::path dir = scratch();
  // ASCII PLY with a quad (fanned) and an extra element.
  put(dir / "a.ply",
      "ply\nformat ascii 1.0\ncomment x\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
      "element face 2\nproperty list uchar int vertex_indices\nelement extra 1\nproperty int q\nend_header\n"
      "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n4 0 1 2 3\n3 0 1 4\n7\n");
  const auto a = gdm::read_mesh_file((dir / "a.ply").string());
  EXPECT_EQ(a.points.size(), 5u);
  EXPECT_EQ(a.triangles.size(), 3u);
  // ASCII STL.
  put(dir / "a.stl",
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n"
      "facet normal 0 0 1\nouter loop\nvertex 1 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n");
  const auto s = gdm::read_mesh_file((dir / "a.stl").string());
  EXPECT_EQ(s.points.size(), 4u);
  EXPECT_EQ(s.triangles.size(), 2u);
  // Binary VTK (big-endian) with an int generation.
  std::string vtk = "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 4 float\n";
  const auto be32 = [&](std::uint32_t v) {
    for (int i = 3; i >= 0; --i) vtk += static_cast<char>((v >> (8 * i)) & 0xff);
  };
  const float coords[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
  for (float c : coords) {
    std::uint32_t u;
    std::memcpy(&u, &c, 4);
    be32(u);
  }
  vtk += "\nPOLYGONS 4 16\n";
  for (std::uint32_t v : {3u, 0u, 2u, 1u, 3u, 0u, 1u, 3u, 3u, 0u, 3u, 2u, 3u, 1u, 2u, 3u}) be32(v);
  vtk += "\nPOINT_DATA 4\nSCALARS generation int 1\nLOOKUP_TABLE default\n";
  for (std::uint32_t v : {0u, 1u, 2u, 3u}) be32(v);
  vtk += "\n";
  put(dir / "b.vtk", vtk);
  const gdm::Mesh b = gdm::read_mesh((dir / "b.vtk").string());
  EXPECT_EQ(b.n_faces(), 4u);
  EXPECT_TRUE(gdm::measure(b).closed);
  EXPECT_EQ(gdm::read_mesh_file((dir / "b.vtk").string()).generation, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(b.point(gdm::Mesh::VertexHandle(3))[2], 1.0);
  // OBJ with slashes, negative indices and comments.
  std::string obj = "# c\n";
  for (const char* p : kTetraPoints) obj += std::string("v ") + p + "\n";
  obj += "vn 0 0 1\nf 1//1 3//1 2//1\nf -4/1/1 -3 -1\n";
  put(dir / "c.obj", obj);
  EXPECT_EQ(gdm::read_triangles((dir / "c.obj").string()).size(), 2u);
}

void expect_invalid(const fs::path& path, const std::string& problem) {
  SCOPED_TRACE(path.filename().string());
  try {
    gdm::read_mesh_file(path.string());
    ADD_FAILURE() << "accepted " << path;
  } catch (const gdm::InvalidInput& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(path.string()), std::string::npos) << m;
    EXPECT_NE(m.find(problem), std::string::npos) << m;
  }
  EXPECT_THROW(gdm::read_mesh(path.string()), gdm::InvalidInput);
  EXPECT_THROW(gdm::read_triangles(path.string()), gdm::InvalidInput);
}

TEST(MeshIo, hostile_files_are_invalid_input) {
  const fs::path d = scratch();
  const std::string ply_head = "ply\nformat ascii 1.0\nelement vertex ";
  const std::string ply_props = "property float x\nproperty float y\nproperty float z\n";
  const std::string ply_face = "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  // Empty files.
  for (const std::string ext : {".ply", ".obj", ".off", ".stl", ".vtk"}) {
    put(d / ("empty" + ext), "");
    expect_invalid(d / ("empty" + ext), "empty");
  }
  expect_invalid(d / "missing.obj", "cannot open");
  // Vertices without faces.
  put(d / "points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n");
  expect_invalid(d / "points.obj", "no faces");
  put(d / "points.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n");
  expect_invalid(d / "points.off", "no faces");
  put(d / "points.ply", ply_head + "3\n" + ply_props + "end_header\n0 0 0\n1 0 0\n0 1 0\n");
  expect_invalid(d / "points.ply", "no faces");
  put(d / "points.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n");
  expect_invalid(d / "points.vtk", "no faces");
  // Face index out of range.
  put(d / "range.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n");
  expect_invalid(d / "range.obj", "refers to vertex 3");
  put(d / "range.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  expect_invalid(d / "range.off", "refers to vertex 7");
  put(d / "range.ply", ply_head + "3\n" + ply_props + ply_face + "0 0 0\n1 0 0\n0 1 0\n3 0 1 -1\n");
  expect_invalid(d / "range.ply", "refers to vertex -1");
  put(d / "range.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 3 float\n0 0 0 1 0 0 0 1 0\n"
                       "POLYGONS 1 4\n3 0 1 3\n");
  expect_invalid(d / "range.vtk", "refers to vertex 3");
  // Negative counts.
  put(d / "negative.off", "OFF\n-3 1 0\n0 0 0\n");
  expect_invalid(d / "negative.off", "negative");
  put(d / "negative.ply", ply_head + "-3\n" + ply_props + ply_face + "0 0 0\n");
  expect_invalid(d / "negative.ply", "negative");
  put(d / "negative.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS -3 float\n0 0 0\n");
  expect_invalid(d / "negative.vtk", "negative");
  // Counts larger than the file can hold (refused before any allocation).
  put(d / "huge.off", "OFF\n4000000000000 1 0\n0 0 0\n");
  expect_invalid(d / "huge.off", "larger than the file can hold");
  put(d / "huge.ply", ply_head + "4000000000000\n" + ply_props + ply_face + "0 0 0\n");
  expect_invalid(d / "huge.ply", "bytes");
  std::string huge_binary_ply = "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + ply_props +
                                "element face 1\nproperty list uchar int vertex_indices\nend_header\n" +
                                std::string(36, '\0') + std::string(1, '\xff') + std::string(8, '\0');
  put(d / "huge_list.ply", huge_binary_ply);
  expect_invalid(d / "huge_list.ply", "larger than the file can hold");
  put(d / "huge.vtk", "# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 999999999999 float\n0 0 0\n");
  expect_invalid(d / "huge.vtk", "larger than the file can hold");
  std::string stl(84, '\0');
  const std::uint32_t many = 0x7fffffff;
  std::memcpy(&stl[80], &many, 4);
  put(d / "huge.stl", stl + std::string(50, '\0'));
  expect_invalid(d / "huge.stl", "bytes");
  // Truncated binary PLY.
  put(d / "truncated.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 3\n" + ply_props + ply_face +
                               std::string(20, '\0'));
  expect_invalid(d / "truncated.ply", "bytes");
  // NaN coordinates.
  put(d / "nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
  expect_invalid(d / "nan.obj", "non-finite");
  put(d / "nan.off", "OFF\n3 1 0\n0 0 0\n1 inf 0\n0 1 0\n3 0 1 2\n");
  expect_invalid(d / "nan.off", "non-finite");
  put(d / "nan.ply", ply_head + "3\n" + ply_props + ply_face + "0 0 0\n1 0 nan\n0 1 0\n3 0 1 2\n");
  expect_invalid(d / "nan.ply", "non-finite");
  put(d / "nan.stl", "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex nan 0 0\nvertex 0 1 0\n"
                     "endloop\nendfacet\nendsolid t\n");
  expect_invalid(d / "nan.stl", "non-finite");
  // Random bytes, every extension, several seeds and sizes.
  std::mt19937 random(12345);
  for (int n : {1, 7, 83, 84, 134, 1000, 5000})
    for (const std::string ext : {".ply", ".obj", ".off", ".stl", ".vtk"}) {
      std::string bytes(static_cast<std::size_t>(n), '\0');
      for (char& c : bytes) c = static_cast<char>(random() & 0xff);
      const fs::path p = d / ("random" + std::to_string(n) + ext);
      put(p, bytes);
      EXPECT_THROW(gdm::read_mesh_file(p.string()), gdm::InvalidInput) << p;
    }
  // Random bytes after a valid header.
  for (int seed = 0; seed < 20; ++seed) {
    std::mt19937 r(static_cast<unsigned>(seed));
    std::string tail(300, '\0');
    for (char& c : tail) c = static_cast<char>(r() & 0xff);
    const fs::path ply = d / ("tail" + std::to_string(seed) + ".ply");
    put(ply, "ply\nformat binary_little_endian 1.0\nelement vertex 5\n" + ply_props + "element face 4\n"
             "property list uchar int vertex_indices\nend_header\n" + tail);
    EXPECT_THROW(gdm::read_mesh_file(ply.string()), gdm::InvalidInput) << ply;
    const fs::path vtk = d / ("tail" + std::to_string(seed) + ".vtk");
    put(vtk, "# vtk DataFile Version 3.0\nt\nBINARY\nDATASET POLYDATA\nPOINTS 5 float\n" + tail);
    EXPECT_THROW(gdm::read_mesh_file(vtk.string()), gdm::InvalidInput) << vtk;
  }
  fs::remove_all(d);
}

TEST(MeshIo, non_manifold_file_is_invalid_for_read_mesh_only) {
  const fs::path d = scratch();
  // Three triangles on one edge.
  put(d / "fin.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 -1 0\nv 0 0 1\nf 1 2 3\nf 2 1 4\nf 1 2 5\n");
  EXPECT_EQ(gdm::read_triangles((d / "fin.obj").string()).size(), 3u);
  EXPECT_THROW(gdm::read_mesh((d / "fin.obj").string()), gdm::InvalidInput);
}

TEST(MeshIo, unknown_extension_and_unwritable_folder) {
  EXPECT_THROW(gdm::read_mesh_file("mesh.xyz"), gdm::InvalidOption);
  const gdm::Mesh mesh = gdm::make_geodesic_sphere(gdm::Vec3(0, 0, 0), 1.0, 0);
  EXPECT_THROW(gdm::write_mesh(mesh, "mesh.xyz"), gdm::InvalidOption);
  EXPECT_THROW(gdm::write_mesh(mesh, "/nonexistent-folder/mesh.ply"), gdm::Error);
  EXPECT_TRUE(gdm::is_supported_mesh_extension("A.PLY"));
  EXPECT_EQ(gdm::file_extension("/a.b/scan.nii.gz"), ".nii.gz");
}

// Issue 13, item 9: a FIFO would block the open forever, a folder has nothing
// to read: both refused at once, saying what they are.
TEST(MeshIo, fifo_or_folder_is_refused_at_once) {
  const fs::path d = scratch();
  fs::create_directory(d / "folder.obj");
  expect_invalid(d / "folder.obj", "not a regular file: it is a folder");
  ASSERT_EQ(::mkfifo((d / "pipe.off").c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  expect_invalid(d / "pipe.off", "not a regular file: it is a FIFO (named pipe)");
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 5.0);
  fs::remove_all(d);
}

// Issue 13, item 10: SIGTERM, SIGINT or SIGHUP while write_file_atomically is
// inside its body removes the temporary file; the target is not created and
// the process still ends by that signal. A child process blocks in the body.
TEST(MeshIo, interrupted_write_leaves_no_temporary_file) {
  const fs::path d = scratch();
  for (const int sig : {SIGTERM, SIGINT, SIGHUP}) {
    SCOPED_TRACE(sig);
    const fs::path target = d / ("out" + std::to_string(sig) + ".ply");
    int ready[2];
    ASSERT_EQ(::pipe(ready), 0);
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      ::close(ready[0]);
      // As on a terminal (a background job of a script ignores SIGINT).
      ::signal(sig, SIG_DFL);
      gdm::remove_on_interrupt_install();
      gdm::write_file_atomically(target.string(), true, [&](std::ostream& o) {
        o << std::string(1 << 20, 'x') << std::flush;
        const char byte = 1;
        if (::write(ready[1], &byte, 1) != 1) ::_exit(3);
        for (;;) ::pause();
      });
      ::_exit(2);  // not reached: the body never returns
    }
    ::close(ready[1]);
    char byte = 0;
    ASSERT_EQ(::read(ready[0], &byte, 1), 1) << "the child did not start writing";
    ::close(ready[0]);
    const fs::path temporary = target.string() + ".tmp-" + std::to_string(child);
    EXPECT_TRUE(fs::exists(temporary)) << "the write is in flight";
    ASSERT_EQ(::kill(child, sig), 0);
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "status " << status;
    EXPECT_FALSE(fs::exists(temporary));
    EXPECT_FALSE(fs::exists(target));
  }
  for (const auto& entry : fs::directory_iterator(d)) ADD_FAILURE() << "left behind: " << entry.path();
  fs::remove_all(d);
}

// A signal the program ignores (nohup's SIGHUP) stays ignored; a guard lists
// any path (the gdm command's report while its mesh is written).
TEST(MeshIo, ignored_signals_stay_ignored_and_guards_remove_listed_files) {
  const fs::path d = scratch();
  const fs::path report = d / "report.json";
  const fs::path target = d / "out.ply";
  int ready[2];
  ASSERT_EQ(::pipe(ready), 0);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    ::close(ready[0]);
    ::signal(SIGTERM, SIG_DFL);
    ::signal(SIGHUP, SIG_IGN);
    gdm::remove_on_interrupt_install();
    gdm::write_file_atomically(report.string(), false, [](std::ostream& o) { o << "{}\n"; });
    gdm::RemoveOnInterrupt keep_report_only_with_the_mesh(report.string());
    gdm::write_file_atomically(target.string(), true, [&](std::ostream& o) {
      o << "partial" << std::flush;
      const char byte = 1;
      if (::write(ready[1], &byte, 1) != 1) ::_exit(3);
      for (;;) ::pause();
    });
    ::_exit(2);
  }
  ::close(ready[1]);
  char byte = 0;
  ASSERT_EQ(::read(ready[0], &byte, 1), 1);
  ::close(ready[0]);
  EXPECT_TRUE(fs::exists(report));
  ASSERT_EQ(::kill(child, SIGHUP), 0);
  ::usleep(200 * 1000);
  int status = 0;
  EXPECT_EQ(::waitpid(child, &status, WNOHANG), 0) << "an ignored SIGHUP ended the process";
  EXPECT_TRUE(fs::exists(target.string() + ".tmp-" + std::to_string(child)));
  ASSERT_EQ(::kill(child, SIGTERM), 0);
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM) << "status " << status;
  for (const auto& entry : fs::directory_iterator(d)) ADD_FAILURE() << "left behind: " << entry.path();
  fs::remove_all(d);
}

}  // namespace
