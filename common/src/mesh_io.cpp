#include "gdm/mesh_io.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "gdm/errors.h"

namespace gdm {
namespace {

// The mesh in plain arrays, vertices numbered in order (deleted ones skipped).
MeshFileData flatten(const Mesh& mesh) {
  MeshFileData m;
  const auto generation = find_generation_property(mesh);
  std::vector<std::uint32_t> index(mesh.n_vertices(), 0);
  for (auto v : mesh.vertices()) {
    index[v.idx()] = static_cast<std::uint32_t>(m.points.size());
    m.points.push_back(to_eigen(mesh.point(v)));
    if (generation.is_valid()) m.generation.push_back(mesh.property(generation, v));
  }
  for (auto f : mesh.faces()) {
    std::array<std::uint32_t, 3> face{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      if (k == 3) break;
      face[k++] = index[v.idx()];
    }
    m.triangles.push_back(face);
  }
  return m;
}

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

void write_ply(std::ostream& out, const MeshFileData& m) {
  out << "ply\nformat binary_little_endian 1.0\ncomment gdm: Geometrically Deformed Model, coordinates in mm\n"
      << (!m.generation.empty() ? "comment generation: the deformation cycle that created the vertex (Miller et al. "
                             "1991, section 6.4)\n"
                           : "")
      << "element vertex " << m.points.size() << "\nproperty float x\nproperty float y\nproperty float z\n"
      << (!m.generation.empty() ? "property int generation\n" : "")
      << "element face " << m.triangles.size() << "\nproperty list uchar int vertex_indices\nend_header\n";
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    for (int d = 0; d < 3; ++d) put_le(out, static_cast<float>(m.points[i][d]));
    if (!m.generation.empty()) put_le(out, static_cast<std::int32_t>(m.generation[i]));
  }
  for (const auto& f : m.triangles) {
    put_le(out, static_cast<std::uint8_t>(3));
    for (int k = 0; k < 3; ++k) put_le(out, static_cast<std::int32_t>(f[k]));
  }
}

void write_stl(std::ostream& out, const MeshFileData& m) {
  char header[80] = {};
  std::snprintf(header, sizeof header, "gdm: Geometrically Deformed Model, mm");
  out.write(header, 80);
  put_le(out, static_cast<std::uint32_t>(m.triangles.size()));
  for (const auto& f : m.triangles) {
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

void write_obj(std::ostream& out, const MeshFileData& m) {
  out << "# gdm: Geometrically Deformed Model, coordinates in mm\n";
  for (const auto& p : m.points) out << "v " << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : m.triangles) out << "f " << f[0] + 1 << ' ' << f[1] + 1 << ' ' << f[2] + 1 << '\n';
}

void write_off(std::ostream& out, const MeshFileData& m) {
  out << "OFF\n" << m.points.size() << ' ' << m.triangles.size() << " 0\n";
  for (const auto& p : m.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  for (const auto& f : m.triangles) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
}

void write_vtk(std::ostream& out, const MeshFileData& m) {
  out << "# vtk DataFile Version 3.0\ngdm: Geometrically Deformed Model, coordinates in mm\nASCII\n"
      << "DATASET POLYDATA\nPOINTS " << m.points.size() << " double\n";
  for (const auto& p : m.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  out << "POLYGONS " << m.triangles.size() << ' ' << 4 * m.triangles.size() << '\n';
  for (const auto& f : m.triangles) out << "3 " << f[0] << ' ' << f[1] << ' ' << f[2] << '\n';
  if (!!m.generation.empty()) return;
  out << "POINT_DATA " << m.points.size() << "\nSCALARS generation int 1\nLOOKUP_TABLE default\n";
  for (std::size_t i = 0; i < m.points.size(); ++i) out << m.generation[i] << '\n';
}

// ------------------------------------------------- interrupted writes --
// The files to remove when SIGINT, SIGTERM or SIGHUP ends the process: a fixed
// table (no allocation, no lock), read by an async-signal-safe handler.
constexpr int kInterruptSlots = 32;
constexpr std::size_t kInterruptPathMax = 4096;
char g_interrupt_paths[kInterruptSlots][kInterruptPathMax];
std::atomic<int> g_interrupt_state[kInterruptSlots];  // 0 free, 1 being filled, 2 listed
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free atomics");
constexpr int kInterruptSignals[] = {SIGINT, SIGTERM, SIGHUP};

void remove_listed_files(int sig) {
  const int saved_errno = errno;
  for (int i = 0; i < kInterruptSlots; ++i)
    if (g_interrupt_state[i].load() == 2) ::unlink(g_interrupt_paths[i]);
  errno = saved_errno;
  // SA_RESETHAND restored the default action; the signal is blocked in here,
  // so it ends the process (as that signal) when the handler returns.
  ::raise(sig);
}

bool install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = remove_listed_files;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  for (const int sig : kInterruptSignals) sigaddset(&action.sa_mask, sig);
  for (const int sig : kInterruptSignals) {
    struct sigaction current {};
    if (::sigaction(sig, nullptr, &current) != 0) continue;
    // A program's own handler, or an ignored signal (nohup), is left alone;
    // so is ours when it is already there.
    if (current.sa_handler != SIG_DFL || (current.sa_flags & SA_SIGINFO) != 0) continue;
    ::sigaction(sig, &action, nullptr);
  }
  return true;
}

void ensure_interrupt_handlers() {
  static const bool installed = install_interrupt_handlers();  // once, thread-safe
  (void)installed;
}

}  // namespace

void remove_on_interrupt_install() { install_interrupt_handlers(); }

RemoveOnInterrupt::RemoveOnInterrupt(const std::string& path) {
  ensure_interrupt_handlers();
  if (path.empty() || path.size() >= kInterruptPathMax) return;  // cannot be listed: left unguarded
  for (int i = 0; i < kInterruptSlots; ++i) {
    int expected = 0;
    if (!g_interrupt_state[i].compare_exchange_strong(expected, 1)) continue;
    std::memcpy(g_interrupt_paths[i], path.c_str(), path.size() + 1);
    g_interrupt_state[i].store(2);
    slot_ = i;
    return;
  }
}

void RemoveOnInterrupt::release() {
  if (slot_ >= 0) g_interrupt_state[slot_].store(0);
  slot_ = -1;
}

RemoveOnInterrupt::~RemoveOnInterrupt() { release(); }

void write_file_atomically(const std::string& path, bool binary, const std::function<void(std::ostream&)>& body) {
  const std::string temporary = path + ".tmp-" + std::to_string(::getpid());
  // Listed before it exists, unlisted once renamed: an interrupt never leaves it.
  RemoveOnInterrupt guard(temporary);
  {
    std::ofstream out(temporary, binary ? std::ios::binary : std::ios::out);
    if (!out) throw Error("cannot write " + path + ": " + std::strerror(errno));
    out.precision(17);
    body(out);
    out.flush();
    if (!out) {
      std::remove(temporary.c_str());
      throw Error("writing " + path + " failed (disk full?)");
    }
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    const std::string reason = std::strerror(errno);
    std::remove(temporary.c_str());
    throw Error("cannot rename the temporary file to " + path + ": " + reason);
  }
}

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

void write_mesh(const Mesh& mesh, const std::string& path) {
  if (!is_supported_mesh_extension(path))
    throw InvalidOption("cannot write '" + path + "': unknown mesh extension (use .ply, .obj, .stl, .off or .vtk)");
  write_mesh(flatten(mesh), path);
}

void write_mesh(const MeshFileData& m, const std::string& path) {
  const std::string e = file_extension(path);
  if (!is_supported_mesh_extension(path))
    throw InvalidOption("cannot write '" + path + "': unknown mesh extension (use .ply, .obj, .stl, .off or .vtk)");
  if (!m.generation.empty() && m.generation.size() != m.points.size())
    throw InvalidOption("cannot write '" + path + "': " + std::to_string(m.generation.size()) +
                        " generations for " + std::to_string(m.points.size()) + " points");
  for (const auto& t : m.triangles)
    for (auto i : t)
      if (i >= m.points.size())
        throw InvalidOption("cannot write '" + path + "': a triangle refers to point " + std::to_string(i) + " of " +
                            std::to_string(m.points.size()));
  if (e == ".ply") write_file_atomically(path, true, [&](std::ostream& o) { write_ply(o, m); });
  else if (e == ".stl") write_file_atomically(path, true, [&](std::ostream& o) { write_stl(o, m); });
  else if (e == ".obj") write_file_atomically(path, false, [&](std::ostream& o) { write_obj(o, m); });
  else if (e == ".off") write_file_atomically(path, false, [&](std::ostream& o) { write_off(o, m); });
  else write_file_atomically(path, false, [&](std::ostream& o) { write_vtk(o, m); });
}

namespace {

[[noreturn]] void bad(const std::string& path, const std::string& problem) {
  throw InvalidInput("cannot read the mesh " + path + ": " + problem);
}

// A cursor over the file's bytes: text tokens and binary values, every read
// checked against the end.
class Cursor {
 public:
  Cursor(const std::string& data, const std::string& path) : d_(data), path_(path) {}

  std::size_t pos() const { return pos_; }
  std::size_t remaining() const { return d_.size() - pos_; }
  bool at_end() const { return pos_ >= d_.size(); }
  [[noreturn]] void fail(const std::string& problem) const { bad(path_, problem); }

  void skip_space() {
    while (pos_ < d_.size() && std::isspace(static_cast<unsigned char>(d_[pos_]))) ++pos_;
  }
  // The next whitespace-separated word ("" at the end); NUL bytes are refused.
  std::string word() {
    skip_space();
    const std::size_t start = pos_;
    while (pos_ < d_.size() && !std::isspace(static_cast<unsigned char>(d_[pos_]))) {
      if (d_[pos_] == '\0') fail("a NUL byte in text at byte " + std::to_string(pos_) + " (not a text file?)");
      ++pos_;
    }
    return d_.substr(start, pos_ - start);
  }
  // The rest of the current line, without its end of line; false at the end.
  bool line(std::string* out) {
    if (pos_ >= d_.size()) return false;
    const std::size_t end = d_.find('\n', pos_);
    const std::size_t stop = end == std::string::npos ? d_.size() : end;
    *out = d_.substr(pos_, stop - pos_);
    if (out->find('\0') != std::string::npos)
      fail("a NUL byte in text near byte " + std::to_string(pos_) + " (not a text file?)");
    if (!out->empty() && out->back() == '\r') out->pop_back();
    pos_ = end == std::string::npos ? d_.size() : end + 1;
    return true;
  }
  // Skips the single end of line that follows a header line of a binary block.
  void skip_line_end() {
    while (pos_ < d_.size() && (d_[pos_] == ' ' || d_[pos_] == '\t' || d_[pos_] == '\r')) ++pos_;
    if (pos_ < d_.size() && d_[pos_] == '\n') ++pos_;
  }
  template <typename T>
  T binary(bool big_endian, const char* what) {
    if (remaining() < sizeof(T)) fail("the file ends inside " + std::string(what));
    unsigned char bytes[sizeof(T)];
    std::memcpy(bytes, d_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    if (big_endian) std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    return value;
  }

 private:
  const std::string& d_;
  const std::string& path_;
  std::size_t pos_ = 0;
};

bool parse_double(const std::string& s, double* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  *out = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size();
}

bool parse_integer(const std::string& s, long long* out) {
  if (s.empty()) return false;
  char* end = nullptr;
  errno = 0;
  *out = std::strtoll(s.c_str(), &end, 10);
  return end == s.c_str() + s.size() && errno == 0;
}

// A count from the file: not negative, and `count` items of at least
// `min_bytes` each fit in what is left of the file.
std::size_t checked_count(const Cursor& c, long long count, double min_bytes, const std::string& what) {
  if (count < 0) c.fail("negative " + what + " count " + std::to_string(count));
  if (static_cast<double>(count) * min_bytes > static_cast<double>(c.remaining()))
    c.fail(what + " count " + std::to_string(count) + " is larger than the file can hold (" +
           std::to_string(c.remaining()) + " bytes left)");
  return static_cast<std::size_t>(count);
}

long long integer_word(Cursor& c, const std::string& what) {
  const std::string w = c.word();
  long long v = 0;
  if (!parse_integer(w, &v)) c.fail("expected an integer " + what + ", got '" + w.substr(0, 40) + "'");
  return v;
}

double number_word(Cursor& c, const std::string& what) {
  const std::string w = c.word();
  double v = 0;
  if (!parse_double(w, &v)) c.fail("expected a number (" + what + "), got '" + w.substr(0, 40) + "'");
  return v;
}

// An integral value from the file (an index, a count, a generation), refused
// when it is not an integer of a sane size (NaN casts are undefined).
long long integral(const Cursor& c, double v, const std::string& what) {
  if (!(v == std::floor(v) && std::fabs(v) < 2.0e9)) c.fail("bad " + what + " (not an integer in range)");
  return static_cast<long long>(v);
}

void add_polygon(const Cursor& c, MeshFileData& m, const std::vector<long long>& corners, std::size_t face) {
  if (corners.size() < 3)
    c.fail("face " + std::to_string(face) + " has " + std::to_string(corners.size()) + " corners (at least 3)");
  for (long long i : corners)
    if (i < 0 || i >= static_cast<long long>(m.points.size()))
      c.fail("face " + std::to_string(face) + " refers to vertex " + std::to_string(i) + " of " +
             std::to_string(m.points.size()));
  for (std::size_t k = 1; k + 1 < corners.size(); ++k)
    m.triangles.push_back({static_cast<std::uint32_t>(corners[0]), static_cast<std::uint32_t>(corners[k]),
                           static_cast<std::uint32_t>(corners[k + 1])});
}

// ---- PLY ------------------------------------------------------------------

struct PlyProperty {
  std::string name;
  std::string type;        // scalar type, or the item type of a list
  std::string count_type;  // empty for a scalar
};
struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

int ply_size(const Cursor& c, const std::string& t) {
  if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
  if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
  if (t == "int" || t == "uint" || t == "int32" || t == "uint32" || t == "float" || t == "float32") return 4;
  if (t == "double" || t == "float64") return 8;
  c.fail("unknown PLY property type '" + t.substr(0, 40) + "'");
}

double ply_binary(Cursor& c, const std::string& t) {
  const char* what = "a PLY element";
  if (t == "char" || t == "int8") return c.binary<std::int8_t>(false, what);
  if (t == "uchar" || t == "uint8") return c.binary<std::uint8_t>(false, what);
  if (t == "short" || t == "int16") return c.binary<std::int16_t>(false, what);
  if (t == "ushort" || t == "uint16") return c.binary<std::uint16_t>(false, what);
  if (t == "int" || t == "int32") return c.binary<std::int32_t>(false, what);
  if (t == "uint" || t == "uint32") return c.binary<std::uint32_t>(false, what);
  if (t == "float" || t == "float32") return c.binary<float>(false, what);
  return c.binary<double>(false, what);
}

MeshFileData read_ply(Cursor& c) {
  std::string line;
  if (!c.line(&line) || line != "ply") c.fail("not a PLY file (no 'ply' first line)");
  bool binary = false, have_format = false;
  std::vector<PlyElement> elements;
  for (;;) {
    if (!c.line(&line)) c.fail("the PLY header has no end_header");
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (key == "end_header") break;
    if (key == "format") {
      std::string f;
      in >> f;
      if (f == "ascii") binary = false;
      else if (f == "binary_little_endian") binary = true;
      else c.fail("unsupported PLY format '" + f.substr(0, 40) + "' (ascii or binary_little_endian)");
      have_format = true;
    } else if (key == "element") {
      PlyElement e;
      std::string count;
      in >> e.name >> count;
      if (!parse_integer(count, &e.count)) c.fail("bad count '" + count.substr(0, 40) + "' of element " + e.name);
      if (e.count < 0) c.fail("negative count " + count + " of element " + e.name);
      elements.push_back(e);
    } else if (key == "property") {
      if (elements.empty()) c.fail("a PLY property before any element");
      PlyProperty p;
      std::string t;
      in >> t;
      if (t == "list") {
        in >> p.count_type >> p.type >> p.name;
        ply_size(c, p.count_type);
      } else {
        p.type = t;
        in >> p.name;
      }
      ply_size(c, p.type);
      elements.back().properties.push_back(p);
    } else if (key != "comment" && key != "obj_info" && !key.empty()) {
      c.fail("unknown PLY header line '" + line.substr(0, 40) + "'");
    }
  }
  if (!have_format) c.fail("the PLY header has no format line");
  // Every element must fit in the rest of the file before anything is allocated.
  double needed = 0.0;
  for (const auto& e : elements) {
    double bytes = 0.0;
    for (const auto& p : e.properties) bytes += binary ? ply_size(c, p.count_type.empty() ? p.type : p.count_type) : 2.0;
    needed += bytes * static_cast<double>(e.count);
  }
  if (needed > static_cast<double>(c.remaining()))
    c.fail("the PLY header's element counts need at least " + std::to_string(static_cast<long long>(needed)) +
           " bytes, the file has " + std::to_string(c.remaining()) + " left");
  MeshFileData m;
  bool have_vertices = false;
  std::size_t face_number = 0;
  std::vector<double> values;
  std::vector<long long> corners;
  for (const auto& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    int x = -1, y = -1, z = -1, g = -1, list = -1;
    for (int i = 0; i < static_cast<int>(e.properties.size()); ++i) {
      const auto& p = e.properties[i];
      if (!p.count_type.empty()) {
        if (is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) list = i;
        continue;
      }
      if (p.name == "x") x = i;
      if (p.name == "y") y = i;
      if (p.name == "z") z = i;
      if (p.name == "generation") g = i;
    }
    if (is_vertex) {
      if (x < 0 || y < 0 || z < 0) c.fail("the PLY vertex element lacks x, y or z");
      m.points.reserve(static_cast<std::size_t>(e.count));
      if (g >= 0) m.generation.reserve(static_cast<std::size_t>(e.count));
      have_vertices = true;
    }
    if (is_face && list < 0) c.fail("the PLY face element has no vertex_indices list");
    if (is_face && !have_vertices) c.fail("the PLY face element comes before the vertices");
    if (e.properties.empty()) continue;
    for (long long n = 0; n < e.count; ++n) {
      values.assign(e.properties.size(), 0.0);
      for (int i = 0; i < static_cast<int>(e.properties.size()); ++i) {
        const auto& p = e.properties[i];
        if (p.count_type.empty()) {
          values[i] = binary ? ply_binary(c, p.type) : number_word(c, e.name + " " + p.name);
          continue;
        }
        const double k = binary ? ply_binary(c, p.count_type) : number_word(c, "list length");
        const std::size_t items = checked_count(c, integral(c, k, "list length in element " + e.name),
                                                binary ? ply_size(c, p.type) : 2.0,
                                                "list item");
        if (i == list) corners.clear();
        for (std::size_t j = 0; j < items; ++j) {
          const double v = binary ? ply_binary(c, p.type) : number_word(c, "list item");
          if (i == list) corners.push_back(integral(c, v, "vertex index in face " + std::to_string(face_number)));
        }
      }
      if (is_vertex) {
        m.points.emplace_back(values[x], values[y], values[z]);
        if (g >= 0) m.generation.push_back(static_cast<int>(integral(c, values[g], "vertex generation")));
      } else if (is_face) {
        add_polygon(c, m, corners, face_number++);
      }
    }
  }
  return m;
}

// ---- OBJ ------------------------------------------------------------------

MeshFileData read_obj(Cursor& c) {
  MeshFileData m;
  std::vector<std::vector<long long>> faces;
  std::string line;
  std::size_t line_number = 0;
  while (c.line(&line)) {
    ++line_number;
    std::istringstream in(line);
    std::string key;
    in >> key;
    if (key == "v") {
      std::string a, b, d;
      in >> a >> b >> d;
      double x, y, z;
      if (!parse_double(a, &x) || !parse_double(b, &y) || !parse_double(d, &z))
        c.fail("line " + std::to_string(line_number) + ": a vertex needs three numbers");
      m.points.emplace_back(x, y, z);
    } else if (key == "f") {
      std::vector<long long> corners;
      std::string w;
      while (in >> w) {
        long long i = 0;
        if (!parse_integer(w.substr(0, w.find('/')), &i) || i == 0)
          c.fail("line " + std::to_string(line_number) + ": bad face corner '" + w.substr(0, 40) + "'");
        // 1-based; negative counts back from the last vertex read so far.
        corners.push_back(i > 0 ? i - 1 : static_cast<long long>(m.points.size()) + i);
      }
      faces.push_back(std::move(corners));
    }
  }
  for (std::size_t f = 0; f < faces.size(); ++f) add_polygon(c, m, faces[f], f);
  return m;
}

// ---- OFF ------------------------------------------------------------------

// The next line with content, comments (#) removed; false at the end.
bool content_line(Cursor& c, std::string* line) {
  while (c.line(line)) {
    const auto hash = line->find('#');
    if (hash != std::string::npos) line->erase(hash);
    if (line->find_first_not_of(" \t\r") != std::string::npos) return true;
  }
  return false;
}

MeshFileData read_off(Cursor& c) {
  std::string line;
  if (!content_line(c, &line)) c.fail("the file is empty");
  std::istringstream head(line);
  std::string key;
  head >> key;
  if (key != "OFF") c.fail("not an OFF file (no 'OFF' first line)");
  std::string counts_text;
  std::getline(head, counts_text);
  if (counts_text.find_first_not_of(" \t") == std::string::npos && !content_line(c, &counts_text))
    c.fail("the OFF file has no vertex and face counts");
  std::istringstream counts(counts_text);
  std::string a, b;
  counts >> a >> b;
  long long nv = 0, nf = 0;
  if (!parse_integer(a, &nv) || !parse_integer(b, &nf)) c.fail("bad OFF counts '" + counts_text.substr(0, 40) + "'");
  // Each vertex and face takes a line of at least 6 bytes ("0 0 0\n", "3 0 1 2\n").
  checked_count(c, nv, 6.0, "vertex");
  checked_count(c, nf, 8.0, "face");
  checked_count(c, nv + nf, 6.0, "vertex and face");
  MeshFileData m;
  m.points.reserve(static_cast<std::size_t>(nv));
  for (long long i = 0; i < nv; ++i) {
    if (!content_line(c, &line)) c.fail("the file ends after " + std::to_string(i) + " of " + std::to_string(nv) + " vertices");
    std::istringstream in(line);
    std::string x, y, z;
    in >> x >> y >> z;
    double p[3];
    if (!parse_double(x, &p[0]) || !parse_double(y, &p[1]) || !parse_double(z, &p[2]))
      c.fail("vertex " + std::to_string(i) + " needs three numbers");
    m.points.emplace_back(p[0], p[1], p[2]);
  }
  std::vector<long long> corners;
  for (long long f = 0; f < nf; ++f) {
    if (!content_line(c, &line)) c.fail("the file ends after " + std::to_string(f) + " of " + std::to_string(nf) + " faces");
    std::istringstream in(line);
    std::string w;
    in >> w;
    long long k = 0;
    if (!parse_integer(w, &k) || k < 0 || k > static_cast<long long>(line.size()))
      c.fail("face " + std::to_string(f) + " has a bad corner count '" + w.substr(0, 40) + "'");
    corners.clear();
    for (long long j = 0; j < k; ++j) {
      long long i = 0;
      if (!(in >> w) || !parse_integer(w, &i)) c.fail("face " + std::to_string(f) + " has too few corners");
      corners.push_back(i);
    }
    add_polygon(c, m, corners, static_cast<std::size_t>(f));
  }
  return m;
}

// ---- STL ------------------------------------------------------------------

struct Welder {
  std::map<std::array<double, 3>, std::uint32_t> index;
  std::uint32_t operator()(MeshFileData& m, const Vec3& p) {
    const auto r = index.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, static_cast<std::uint32_t>(m.points.size()));
    if (r.second) m.points.push_back(p);
    return r.first->second;
  }
};

MeshFileData read_stl(Cursor& c, const std::string& data) {
  MeshFileData m;
  Welder weld;
  if (data.size() >= 84) {
    std::uint32_t n = 0;
    std::memcpy(&n, data.data() + 80, 4);  // little-endian hosts (x86, arm64)
    if (84.0 + 50.0 * n == static_cast<double>(data.size())) {
      for (std::size_t pos = 0; pos < 84; ++pos) c.binary<std::uint8_t>(false, "the STL header");
      for (std::uint32_t t = 0; t < n; ++t) {
        for (int k = 0; k < 3; ++k) c.binary<float>(false, "an STL triangle");  // normal
        std::array<std::uint32_t, 3> tri{};
        for (int k = 0; k < 3; ++k) {
          Vec3 p;
          for (int d = 0; d < 3; ++d) p[d] = c.binary<float>(false, "an STL triangle");
          if (!p.allFinite()) c.fail("triangle " + std::to_string(t) + " has a non-finite coordinate");
          tri[k] = weld(m, p);
        }
        c.binary<std::uint16_t>(false, "an STL triangle");
        m.triangles.push_back(tri);
      }
      return m;
    }
  }
  const std::size_t start = data.find_first_not_of(" \t\r\n");
  if (start == std::string::npos || data.compare(start, 5, "solid") != 0) {
    if (data.size() >= 84) {
      std::uint32_t n = 0;
      std::memcpy(&n, data.data() + 80, 4);
      c.fail("a binary STL whose header counts " + std::to_string(n) + " triangles must have " +
             std::to_string(84ull + 50ull * n) + " bytes, the file has " + std::to_string(data.size()));
    }
    c.fail("not an STL file (too short for binary, no 'solid' for ASCII)");
  }
  c.word();  // solid
  std::vector<std::uint32_t> corners;
  for (std::string w = c.word(); !w.empty(); w = c.word()) {
    if (w == "vertex") {
      Vec3 p;
      for (int d = 0; d < 3; ++d) p[d] = number_word(c, "an STL vertex coordinate");
      if (!p.allFinite()) c.fail("a vertex has a non-finite coordinate");
      corners.push_back(weld(m, p));
    } else if (w == "endloop") {
      if (corners.size() != 3) c.fail("a facet with " + std::to_string(corners.size()) + " vertices (3 expected)");
      m.triangles.push_back({corners[0], corners[1], corners[2]});
      corners.clear();
    }
  }
  return m;
}

// ---- VTK (legacy) -----------------------------------------------------------

int vtk_size(const Cursor& c, const std::string& t) {
  if (t == "unsigned_char" || t == "char" || t == "bit") return 1;
  if (t == "unsigned_short" || t == "short") return 2;
  if (t == "unsigned_int" || t == "int" || t == "float") return 4;
  if (t == "unsigned_long" || t == "long" || t == "double" || t == "vtktypeint64" || t == "vtktypeuint64") return 8;
  c.fail("unknown VTK data type '" + t.substr(0, 40) + "'");
}

double vtk_value(Cursor& c, bool binary, const std::string& t, const char* what) {
  if (!binary) return number_word(c, what);
  if (t == "unsigned_char" || t == "bit") return c.binary<std::uint8_t>(true, what);
  if (t == "char") return c.binary<std::int8_t>(true, what);
  if (t == "unsigned_short") return c.binary<std::uint16_t>(true, what);
  if (t == "short") return c.binary<std::int16_t>(true, what);
  if (t == "unsigned_int") return c.binary<std::uint32_t>(true, what);
  if (t == "int") return c.binary<std::int32_t>(true, what);
  if (t == "float") return c.binary<float>(true, what);
  if (t == "double") return c.binary<double>(true, what);
  if (t == "unsigned_long" || t == "vtktypeuint64") return static_cast<double>(c.binary<std::uint64_t>(true, what));
  return static_cast<double>(c.binary<std::int64_t>(true, what));
}

MeshFileData read_vtk(Cursor& c) {
  std::string line;
  if (!c.line(&line) || line.rfind("# vtk DataFile", 0) != 0) c.fail("not a legacy VTK file (no '# vtk DataFile' line)");
  if (!c.line(&line)) c.fail("the VTK file ends in its header");
  const std::string format = c.word();
  if (format != "ASCII" && format != "BINARY") c.fail("the VTK file is neither ASCII nor BINARY");
  const bool binary = format == "BINARY";
  if (c.word() != "DATASET" || c.word() != "POLYDATA") c.fail("only DATASET POLYDATA is read");
  MeshFileData m;
  bool have_points = false;
  std::size_t face_number = 0;
  std::size_t attribute_count = 0;  // values per component in the current POINT_DATA / CELL_DATA
  bool in_point_data = false;
  std::vector<long long> corners;
  for (std::string key = c.word(); !key.empty(); key = c.word()) {
    if (key == "POINTS") {
      const long long n = integer_word(c, "point count");
      const std::string type = c.word();
      const int size = binary ? vtk_size(c, type) : 2;
      const std::size_t count = checked_count(c, n, 3.0 * size, "point");
      if (binary) c.skip_line_end();
      m.points.reserve(count);
      for (std::size_t i = 0; i < count; ++i) {
        Vec3 p;
        for (int d = 0; d < 3; ++d) p[d] = vtk_value(c, binary, type, "the VTK points");
        m.points.push_back(p);
      }
      have_points = true;
    } else if (key == "POLYGONS" || key == "TRIANGLE_STRIPS" || key == "VERTICES" || key == "LINES") {
      const long long n = integer_word(c, key + " cell count");
      const long long total = integer_word(c, key + " size");
      checked_count(c, n, binary ? 4.0 : 2.0, key + " cell");
      checked_count(c, total, binary ? 4.0 : 2.0, key + " size");
      if (total < n) c.fail(key + " size " + std::to_string(total) + " is smaller than its cell count");
      if (binary) c.skip_line_end();
      const bool faces = key == "POLYGONS" || key == "TRIANGLE_STRIPS";
      if (faces && !have_points) c.fail(key + " before POINTS");
      long long read = 0;
      for (long long cell = 0; cell < n; ++cell) {
        const long long k = integral(c, vtk_value(c, binary, "int", "a VTK cell"), key + " point count");
        ++read;
        if (k < 0 || read + k > total)
          c.fail(key + " cell " + std::to_string(cell) + " has a bad point count");
        corners.clear();
        for (long long j = 0; j < k; ++j)
          corners.push_back(integral(c, vtk_value(c, binary, "int", "a VTK cell"), key + " point index"));
        read += k;
        if (key == "POLYGONS") {
          add_polygon(c, m, corners, face_number++);
        } else if (key == "TRIANGLE_STRIPS") {
          if (corners.size() < 3) c.fail("a triangle strip with fewer than 3 points");
          for (std::size_t j = 0; j + 2 < corners.size(); ++j) {
            std::vector<long long> t = {corners[j], corners[j + 1], corners[j + 2]};
            if (j % 2 == 1) std::swap(t[0], t[1]);
            add_polygon(c, m, t, face_number++);
          }
        }
      }
      if (read != total) c.fail(key + " size " + std::to_string(total) + " disagrees with its cells (" +
                                std::to_string(read) + ")");
    } else if (key == "POINT_DATA" || key == "CELL_DATA") {
      const long long n = integer_word(c, key + " count");
      in_point_data = key == "POINT_DATA";
      if (in_point_data && n != static_cast<long long>(m.points.size()))
        c.fail("POINT_DATA " + std::to_string(n) + " for " + std::to_string(m.points.size()) + " points");
      attribute_count = checked_count(c, n, 1.0, key);
    } else if (key == "SCALARS") {
      const std::string name = c.word(), type = c.word();
      std::string rest;
      c.line(&rest);
      long long components = 1;
      if (rest.find_first_not_of(" \t") != std::string::npos && !parse_integer(rest.substr(rest.find_first_not_of(" \t")), &components))
        c.fail("bad SCALARS component count '" + rest.substr(0, 40) + "'");
      if (components < 1 || components > 4) c.fail("SCALARS " + name + " with " + std::to_string(components) + " components");
      // An optional LOOKUP_TABLE line.
      std::string table = c.word();
      if (table == "LOOKUP_TABLE") {
        c.word();
        if (binary) c.skip_line_end();
      } else {
        c.fail("SCALARS " + name + " without its LOOKUP_TABLE line");
      }
      const int size = binary ? vtk_size(c, type) : 2;
      checked_count(c, static_cast<long long>(attribute_count) * components, size, "SCALARS value");
      const bool keep = in_point_data && name == "generation" && components == 1;
      if (keep) m.generation.reserve(attribute_count);
      for (std::size_t i = 0; i < attribute_count * static_cast<std::size_t>(components); ++i) {
        const double v = vtk_value(c, binary, type, "the VTK scalars");
        if (keep) m.generation.push_back(static_cast<int>(integral(c, v, "generation")));
      }
    } else {
      break;  // attributes this reader does not need (normals, fields, metadata)
    }
  }
  if (!have_points) c.fail("the VTK file has no POINTS");
  return m;
}

}  // namespace

MeshFileData read_mesh_file(const std::string& path) {
  const std::string e = file_extension(path);
  if (!is_supported_mesh_extension(path))
    throw InvalidOption("cannot read '" + path + "': unknown mesh extension (use .ply, .obj, .stl, .off or .vtk)");
  // Only a regular file is opened: a FIFO would block the open, a folder or a
  // device has no size to read.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) bad(path, std::string("cannot open the file: ") + std::strerror(errno));
  if (!S_ISREG(st.st_mode))
    bad(path, std::string("not a regular file: it is ") +
                  (S_ISDIR(st.st_mode)    ? "a folder"
                   : S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                   : S_ISSOCK(st.st_mode) ? "a socket"
                                          : "a device"));
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) bad(path, std::string("cannot open the file: ") + std::strerror(errno));
  const std::streamoff size = in.tellg();
  if (size < 0) bad(path, "cannot tell the file's size (a folder?)");
  if (size == 0) bad(path, "the file is empty");
  std::string data(static_cast<std::size_t>(size), '\0');
  in.seekg(0);
  if (!in.read(&data[0], size)) bad(path, "cannot read the file");
  Cursor c(data, path);
  MeshFileData m;
  if (e == ".ply") m = read_ply(c);
  else if (e == ".obj") m = read_obj(c);
  else if (e == ".off") m = read_off(c);
  else if (e == ".stl") m = read_stl(c, data);
  else m = read_vtk(c);
  for (std::size_t i = 0; i < m.points.size(); ++i)
    if (!m.points[i].allFinite()) bad(path, "vertex " + std::to_string(i) + " has a non-finite coordinate");
  if (!m.generation.empty() && m.generation.size() != m.points.size()) m.generation.clear();
  if (m.points.empty()) bad(path, "the file has no vertices");
  if (m.triangles.empty()) bad(path, "the file has " + std::to_string(m.points.size()) + " vertices but no faces");
  return m;
}

Mesh read_mesh(const std::string& path) {
  const MeshFileData data = read_mesh_file(path);
  Mesh mesh;
  std::vector<Mesh::VertexHandle> handles;
  handles.reserve(data.points.size());
  for (const auto& p : data.points) handles.push_back(mesh.add_vertex(to_point(p)));
  for (std::size_t f = 0; f < data.triangles.size(); ++f) {
    const auto& t = data.triangles[f];
    if (t[0] == t[1] || t[1] == t[2] || t[0] == t[2])
      bad(path, "face " + std::to_string(f) + " repeats a corner");
    const auto face = mesh.add_face(handles[t[0]], handles[t[1]], handles[t[2]]);
    if (!face.is_valid()) bad(path, "face " + std::to_string(f) + " cannot join the mesh (a non-manifold edge or vertex)");
  }
  if (!data.generation.empty()) {
    const auto g = generation_property(mesh);
    for (std::size_t i = 0; i < data.generation.size(); ++i) mesh.property(g, handles[i]) = data.generation[i];
  }
  return mesh;
}

std::vector<Triangle> read_triangles(const std::string& path) {
  const MeshFileData data = read_mesh_file(path);
  std::vector<Triangle> out;
  out.reserve(data.triangles.size());
  for (const auto& t : data.triangles) out.push_back({data.points[t[0]], data.points[t[1]], data.points[t[2]]});
  return out;
}

}  // namespace gdm
