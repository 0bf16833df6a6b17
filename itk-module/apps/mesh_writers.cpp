#include "mesh_writers.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cctype>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>

#include "cli_errors.h"

namespace gdm_cli {
namespace {

bool little_endian() {
  const std::uint16_t one = 1;
  unsigned char byte;
  std::memcpy(&byte, &one, 1);
  return byte == 1;
}

template <typename T>
void put_le(std::ostream& out, T value) {
  unsigned char bytes[sizeof(T)];
  std::memcpy(bytes, &value, sizeof(T));
  if (!little_endian()) std::reverse(bytes, bytes + sizeof(T));
  out.write(reinterpret_cast<const char*>(bytes), sizeof(T));
}

void write_ply(std::ostream& out, const SurfaceMesh& m) {
  out << "ply\nformat binary_little_endian 1.0\ncomment gdm: Geometrically Deformed Model, coordinates in mm\n"
      << "comment generation: the deformation cycle that created the vertex (Miller et al. 1991, section 6.4)\n"
      << "element vertex " << m.points.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "property int generation\n"
      << "element face " << m.faces.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    for (int d = 0; d < 3; ++d) put_le(out, static_cast<float>(m.points[i][d]));
    put_le(out, static_cast<std::int32_t>(i < m.generation.size() ? m.generation[i] : 0));
  }
  for (const auto& f : m.faces) {
    put_le(out, static_cast<std::uint8_t>(3));
    for (int k = 0; k < 3; ++k) put_le(out, static_cast<std::int32_t>(f[k]));
  }
}

void write_stl(std::ostream& out, const SurfaceMesh& m) {
  char header[80] = {};
  std::snprintf(header, sizeof header, "gdm: Geometrically Deformed Model, mm");
  out.write(header, 80);
  put_le(out, static_cast<std::uint32_t>(m.faces.size()));
  for (const auto& f : m.faces) {
    const auto& a = m.points[f[0]];
    const auto& b = m.points[f[1]];
    const auto& c = m.points[f[2]];
    double n[3] = {(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                   (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                   (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& x : n) x = len > 0 ? x / len : 0.0;
    for (double x : n) put_le(out, static_cast<float>(x));
    for (int k = 0; k < 3; ++k)
      for (int d = 0; d < 3; ++d) put_le(out, static_cast<float>(m.points[f[k]][d]));
    put_le(out, static_cast<std::uint16_t>(0));
  }
}

void write_obj(std::ostream& out, const SurfaceMesh& m) {
  out << "# gdm: Geometrically Deformed Model, coordinates in mm\n";
  for (const auto& p : m.points) out << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : m.faces) out << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
}

void write_off(std::ostream& out, const SurfaceMesh& m) {
  out << "OFF\n" << m.points.size() << ' ' << m.faces.size() << " 0\n";
  for (const auto& p : m.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : m.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

void write_vtk(std::ostream& out, const SurfaceMesh& m) {
  out << "# vtk DataFile Version 3.0\ngdm: Geometrically Deformed Model, coordinates in mm\nASCII\n"
      << "DATASET POLYDATA\nPOINTS " << m.points.size() << " double\n";
  for (const auto& p : m.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  out << "POLYGONS " << m.faces.size() << ' ' << 4 * m.faces.size() << '\n';
  for (const auto& f : m.faces) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  out << "POINT_DATA " << m.points.size() << "\nSCALARS generation int 1\nLOOKUP_TABLE default\n";
  for (std::size_t i = 0; i < m.points.size(); ++i) out << (i < m.generation.size() ? m.generation[i] : 0) << '\n';
}

// Writes through `path.tmp-<pid>` and renames; removes the temporary on failure.
void write_atomically(const std::string& path, bool binary, const std::function<void(std::ostream&)>& body) {
  const std::string temporary = path + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, binary ? std::ios::binary : std::ios::out);
    if (!out) throw OutputError("cannot write " + path + ": " + std::strerror(errno));
    out.precision(17);
    body(out);
    out.flush();
    if (!out) {
      std::remove(temporary.c_str());
      throw OutputError("writing " + path + " failed (disk full?)");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw OutputError("cannot rename the temporary file to " + path + ": " + reason);
  }
}

}  // namespace

std::string file_extension(const std::string& path) {
  const auto slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
  for (const char* two : {".nii.gz", ".tar.gz"}) {
    const std::string t = two;
    if (name.size() > t.size() && name.compare(name.size() - t.size(), t.size(), t) == 0) return t;
  }
  const auto dot = name.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? std::string() : name.substr(dot);
}

bool is_supported_mesh_extension(const std::string& path) {
  const std::string e = file_extension(path);
  return e == ".ply" || e == ".obj" || e == ".stl" || e == ".off" || e == ".vtk";
}

void write_mesh(const SurfaceMesh& mesh, const std::string& path) {
  const std::string e = file_extension(path);
  if (e == ".ply") write_atomically(path, true, [&](std::ostream& o) { write_ply(o, mesh); });
  else if (e == ".stl") write_atomically(path, true, [&](std::ostream& o) { write_stl(o, mesh); });
  else if (e == ".obj") write_atomically(path, false, [&](std::ostream& o) { write_obj(o, mesh); });
  else if (e == ".off") write_atomically(path, false, [&](std::ostream& o) { write_off(o, mesh); });
  else if (e == ".vtk") write_atomically(path, false, [&](std::ostream& o) { write_vtk(o, mesh); });
  else throw OutputError("cannot write '" + path + "': unknown mesh extension (use .ply, .obj, .stl, .off or .vtk)");
}

void write_text_file(const std::string& text, const std::string& path) {
  write_atomically(path, false, [&](std::ostream& o) { o << text; });
}

}  // namespace gdm_cli
