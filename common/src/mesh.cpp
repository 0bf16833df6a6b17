#include "gdm/mesh.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace gdm {

namespace {

// Per-thread marks, one per vertex or face index: an element is taken once
// when its mark equals the call's stamp. The neighbourhoods were collected
// with their repeats and sorted, then made unique: each face of a 1-ring's
// faces came three times, and the sort of the repeats was a twelfth of a
// phantom's run (issue 17, perf on gdm_core_benchmark's cube). The lists
// are the same, sorted and unique.
struct Marks {
  std::vector<std::uint32_t> mark;
  std::uint32_t stamp = 0;

  // A new stamp for indices below n.
  std::uint32_t next(std::size_t n) {
    if (mark.size() < n) mark.resize(n, 0);
    if (++stamp == 0) {
      std::fill(mark.begin(), mark.end(), 0);
      stamp = 1;
    }
    return stamp;
  }
};

// Whether i is new for the stamp s in the marks at `mark` (then marked). The
// callers hold the marks' storage in a local pointer: reached through the
// thread_local each time, GCC looked its address up again (a call to
// __tls_get_addr) for every element of a neighbourhood.
bool take(std::uint32_t* mark, int i, std::uint32_t s) {
  std::uint32_t& m = mark[static_cast<std::size_t>(i)];
  if (m == s) return false;
  m = s;
  return true;
}

Marks& vertex_marks() {
  thread_local Marks m;
  return m;
}

Marks& face_marks() {
  thread_local Marks m;
  return m;
}

}  // namespace

void vertices_within(const Mesh& mesh, Mesh::VertexHandle v, int rings, std::vector<int>& found) {
  found.assign(1, v.idx());
  if (rings <= 0) return;
  Marks& marks = vertex_marks();
  const std::uint32_t stamp = marks.next(mesh.n_vertices());
  std::uint32_t* const mark = marks.mark.data();
  take(mark, v.idx(), stamp);
  std::size_t begin = 0;
  for (int r = 0; r < rings; ++r) {
    const std::size_t end = found.size();
    for (std::size_t i = begin; i < end; ++i)
      for (auto w : mesh.vv_range(Mesh::VertexHandle(found[i])))
        if (take(mark, w.idx(), stamp)) found.push_back(w.idx());
    begin = end;
  }
  std::sort(found.begin(), found.end());
}

void faces_around(const Mesh& mesh, const std::vector<int>& vertices, std::vector<int>& faces) {
  faces.clear();
  Marks& marks = face_marks();
  const std::uint32_t stamp = marks.next(mesh.n_faces());
  std::uint32_t* const mark = marks.mark.data();
  for (int u : vertices)
    for (auto f : mesh.vf_range(Mesh::VertexHandle(u)))
      if (take(mark, f.idx(), stamp)) faces.push_back(f.idx());
  std::sort(faces.begin(), faces.end());
}

void sort_listed(std::vector<int>& listed, std::vector<char>& flags) {
  if (16 * listed.size() > flags.size()) {
    listed.clear();
    for (std::size_t i = 0; i < flags.size(); ++i)
      if (flags[i]) listed.push_back(static_cast<int>(i));
  } else {
    std::sort(listed.begin(), listed.end());
  }
  for (int i : listed) flags[static_cast<std::size_t>(i)] = 0;
}

}  // namespace gdm
