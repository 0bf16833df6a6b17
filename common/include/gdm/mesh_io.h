// Mesh files without ITK: writing (.ply, .obj, .stl, .off, .vtk) and reading
// (.ply, .obj, .off, .stl, .vtk) by extension. Readers take hostile files:
// every problem (empty file, vertices without faces, an index out of range, a
// negative count, a count larger than the file can hold, a non-finite
// coordinate, random bytes) is a gdm::InvalidInput naming the file and the
// problem, never a crash or an allocation the file does not justify.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "gdm/mesh.h"
#include "gdm/triangle_locator.h"

namespace gdm {

// Lower-case extension with its dot (".nii.gz" and ".tar.gz" count as one),
// "" when none.
std::string file_extension(const std::string& path);

// True for the extensions write_mesh and read_mesh know (case-insensitive):
// .ply, .obj, .stl, .off, .vtk.
bool is_supported_mesh_extension(const std::string& path);

// A mesh in plain arrays; as read: polygons fanned into triangles, every
// index checked against the points, every coordinate finite.
struct MeshFileData {
  std::vector<Vec3> points;                        // mm
  std::vector<std::array<std::uint32_t, 3>> triangles;
  std::vector<int> generation;                     // per point, when the file has it (ply, vtk); else empty
};

// Writes `mesh` by the extension of `path`:
//   .ply  binary little-endian, float x y z, with a per-vertex int
//         `generation` property when the mesh has "v:generation"
//   .obj  ASCII, 17 significant digits
//   .stl  binary, float, per-face unit normals
//   .off  ASCII, 17 significant digits
//   .vtk  legacy ASCII polydata, double points, generation as point data when
//         the mesh has "v:generation"
// through a temporary name in the same folder (`path`.tmp-<pid>) renamed to
// `path`: a failed write leaves no partial file. Throws InvalidOption (unknown
// extension) or Error (cannot write, cannot rename).
void write_mesh(const Mesh& mesh, const std::string& path);

// The same for plain arrays (generation written when not empty; it must then
// have one value per point). Also throws InvalidOption for an index out of range.
void write_mesh(const MeshFileData& mesh, const std::string& path);

// Writes through `path`.tmp-<pid> and renames (see write_mesh); `body` writes
// the content (a stream with precision 17). Throws Error naming the file.
// An interrupt (SIGINT, SIGTERM, SIGHUP) during the write removes the
// temporary file (see RemoveOnInterrupt) and the process still ends by that
// signal.
void write_file_atomically(const std::string& path, bool binary, const std::function<void(std::ostream&)>& body);

// Lists `path` for removal if SIGINT, SIGTERM or SIGHUP ends the process while
// the guard lives (write_file_atomically guards its temporary file with it; the
// gdm command guards its report until the mesh is written). The listing is a
// fixed table (32 paths of under 4096 bytes; a path that does not fit is left
// unguarded) read by an async-signal-safe handler that unlinks the listed
// paths, then lets the signal end the process with its default action (exit
// status: killed by that signal). The handler is installed by the first guard,
// or earlier by remove_on_interrupt_install(), and only for a signal whose
// action is still the default: a program's own handler, or an ignored SIGHUP
// (nohup), is left as it is.
class RemoveOnInterrupt {
 public:
  explicit RemoveOnInterrupt(const std::string& path);
  ~RemoveOnInterrupt();
  RemoveOnInterrupt(const RemoveOnInterrupt&) = delete;
  RemoveOnInterrupt& operator=(const RemoveOnInterrupt&) = delete;
  void release();  // no longer removed on an interrupt (also done by the destructor)

 private:
  int slot_ = -1;
};

// Installs the handler of RemoveOnInterrupt now, for each of the signals whose
// action is the default at this call (a program calls it at start, before it
// starts threads; calling it again installs it where the action has been set
// back to the default since).
void remove_on_interrupt_install();

// Reads .ply (ASCII, binary little-endian), .obj, .off, .stl (ASCII, binary),
// .vtk (legacy polydata, ASCII or binary). STL corners are welded by exact
// coordinates. Throws InvalidInput (missing or unreadable file, any of the
// problems above, no triangles) or InvalidOption (unknown extension).
MeshFileData read_mesh_file(const std::string& path);

// read_mesh_file as a gdm::Mesh ("v:generation" set when the file has it).
// Also throws InvalidInput when a triangle cannot join the mesh (a
// non-manifold edge or vertex, a repeated corner).
Mesh read_mesh(const std::string& path);

// read_mesh_file as a triangle soup (no topology needed: anything with
// triangles can be wrapped).
std::vector<Triangle> read_triangles(const std::string& path);

}  // namespace gdm
