// Mesh and text files for the CLI: the core's writers (gdm/mesh_io.h: .ply
// binary little-endian with the per-vertex generation, .obj, .stl binary,
// .off, .vtk legacy ASCII with the generation as point data), each written to
// a temporary name in the same folder and renamed, so a failed run leaves no
// partial file; errors mapped onto the CLI's exit codes.
#pragma once

#include <string>

#include "gdm/mesh.h"

namespace gdm_cli {

// True for the extensions above (case-insensitive).
bool is_supported_mesh_extension(const std::string& path);

// Throws OutputError (unsupported extension, cannot write, cannot rename).
void write_mesh(const gdm::Mesh& mesh, const std::string& path);

// Writes `text` to `path` through a temporary name; throws OutputError.
void write_text_file(const std::string& text, const std::string& path);

// Lower-case extension with its dot (".nii.gz" counts as one), "" when none.
std::string file_extension(const std::string& path);

}  // namespace gdm_cli
