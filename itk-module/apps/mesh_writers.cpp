#include "mesh_writers.h"

#include <ostream>

#include "cli_errors.h"
#include "gdm/errors.h"
#include "gdm/mesh_io.h"

namespace gdm_cli {

std::string file_extension(const std::string& path) { return gdm::file_extension(path); }

bool is_supported_mesh_extension(const std::string& path) { return gdm::is_supported_mesh_extension(path); }

void write_mesh(const gdm::Mesh& mesh, const std::string& path) {
  try {
    gdm::write_mesh(mesh, path);
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

}  // namespace gdm_cli
