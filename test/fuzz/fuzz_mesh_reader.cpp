// fuzz_mesh_reader: the input's first byte chooses the extension (.ply, .obj,
// .off, .stl, .vtk), the rest is the file; gdm::read_mesh_file reads it, and
// when it returns, the mesh it makes (gdm::read_mesh) goes through
// gdm::prepare_seed_mesh, the checks a user's seed mesh passes before the
// model. A gdm::Error is fine; anything else (a crash, a sanitizer report, a
// hang, a large allocation, another exception) is a finding.
#include <cstddef>
#include <cstdint>

#include "fuzz_util.h"
#include "gdm/errors.h"
#include "gdm/mesh_io.h"
#include "gdm/seeding.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const extensions[] = {".ply", ".obj", ".off", ".stl", ".vtk"};
  const std::string path = gdm_fuzz::write_temp(data + 1, size - 1, extensions[data[0] % 5]);
  try {
    const gdm::MeshFileData file = gdm::read_mesh_file(path);
    for (const auto& t : file.triangles)
      for (const auto i : t)
        if (i >= file.points.size()) __builtin_trap();  // the reader promised checked indices
    const gdm::Mesh mesh = gdm::read_mesh(path);
    bool reversed = false;
    const gdm::Mesh seed = gdm::prepare_seed_mesh(mesh, &reversed);
    if (seed.n_faces() == 0) __builtin_trap();
  } catch (const gdm::Error&) {
  }
  return 0;
}
