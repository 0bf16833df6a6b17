#include "mesh_writers.h"

#include <ostream>

#include "cli_errors.h"
#include "gdm/errors.h"
#include "gdm/mesh_io.h"

namespace gdm_cli {

std::string file_extension(const std::string& path) { return gdm::file_extension(path); }

bool is_supported_mesh_extension(const std::string& path) { return gdm::is_supported_mesh_extension(path); }

void write_mesh(const SurfaceMesh& mesh, const std::string& path) {
  gdm::MeshFileData data;
  data.points.reserve(mesh.points.size());
  for (const auto& p : mesh.points) data.points.emplace_back(p[0], p[1], p[2]);
  data.triangles = mesh.faces;
  // The CLI's files always carry the generation (0 where unknown).
  data.generation.assign(mesh.points.size(), 0);
  for (std::size_t i = 0; i < mesh.points.size() && i < mesh.generation.size(); ++i)
    data.generation[i] = mesh.generation[i];
  try {
    gdm::write_mesh(data, path);
  } catch (const gdm::Error& e) {
    throw OutputError(e.what());
  }
}

void write_text_file(const std::string& text, const std::string& path) {
  try {
    gdm::write_file_atomically(path, false, [&](std::ostream& o) { o << text; });
  } catch (const gdm::Error& e) {
    throw OutputError(e.what());
  }
}

SurfaceMesh read_surface_mesh(const std::string& path) {
  gdm::MeshFileData data;
  try {
    data = gdm::read_mesh_file(path);
  } catch (const gdm::Error& e) {  // InvalidInput, or InvalidOption for an unknown extension
    throw InputError(e.what());
  }
  SurfaceMesh mesh;
  mesh.points.reserve(data.points.size());
  for (const auto& p : data.points) mesh.points.push_back({p.x(), p.y(), p.z()});
  mesh.faces = std::move(data.triangles);
  mesh.generation = std::move(data.generation);
  if (mesh.generation.empty()) mesh.generation.assign(mesh.points.size(), 0);
  return mesh;
}

}  // namespace gdm_cli
