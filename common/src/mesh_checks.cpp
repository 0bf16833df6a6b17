// Topological and geometric checks and measurements on triangle meshes.
#include "gdm/mesh_checks.h"
#include "gdm/topology.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numeric>
#include <sstream>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "gdm/parallel.h"
#include "gdm/predicates.h"

namespace gdm {
namespace {

// Corner positions and vertex ids of a triangle face.
struct FaceData {
  std::array<Vec3, 3> points;
  std::array<int, 3> ids;
  Vec3 lo, hi;  // bounding box
};

// A vector whose new elements are default-initialised, not zeroed: the
// checks' lists are written in full before they are read, and zeroing
// them (136 bytes a face) took a fifth of the self-intersection check of an
// 841,136-face model, on one thread, page faults included (issue 17).
template <class T>
struct DefaultInitAllocator : std::allocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U>
  void construct(U* p) noexcept(std::is_nothrow_default_constructible_v<U>) {
    ::new (static_cast<void*>(p)) U;
  }
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};
template <class T>
using UninitVector = std::vector<T, DefaultInitAllocator<T>>;
using FaceList = UninitVector<FaceData>;

// The faces in index order. Filled in parallel, each slot by its own
// iteration, then compacted in order: the list does not depend on the
// thread count (the checks of an 832,038-face CT model gathered it four
// times, sequentially: 16 % of the checks' time, issue 17).
FaceList collect_faces(const Mesh& mesh, int threads = 1) {
  FaceList slots(mesh.n_faces());
  std::vector<char> valid(mesh.n_faces(), 0);
  parallel_for(slots.size(), resolve_thread_count(threads), [&](std::size_t i) {
    const Mesh::FaceHandle f(static_cast<int>(i));
    if (mesh.has_face_status() && mesh.status(f).deleted()) return;
    FaceData& data = slots[i];
    int k = 0;
    for (const auto v : mesh.fv_range(f)) {
      if (k == 3) break;  // TriMesh faces have three corners
      data.points[k] = to_eigen(mesh.point(v));
      data.ids[k] = v.idx();
      ++k;
    }
    if (k != 3) return;
    data.lo = data.points[0].cwiseMin(data.points[1]).cwiseMin(data.points[2]);
    data.hi = data.points[0].cwiseMax(data.points[1]).cwiseMax(data.points[2]);
    valid[i] = 1;
  });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < slots.size(); ++i)
    if (valid[i]) slots[kept++] = slots[i];
  slots.resize(kept);
  return slots;
}

inline bool boxes_overlap(const FaceData& a, const FaceData& b) {
  return (a.lo.array() <= b.hi.array()).all() &&
         (b.lo.array() <= a.hi.array()).all();
}

// Union-find with path halving.
int find_root(std::vector<int>& parent, int i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

int count_isolated_vertices(const Mesh& mesh) {
  int isolated = 0;
  for (const auto v : mesh.vertices())
    if (mesh.is_isolated(v)) ++isolated;
  return isolated;
}

}  // namespace

bool is_closed(const Mesh& mesh) {
  bool any_face = false;
  for (const auto f : mesh.faces()) {
    (void)f;
    any_face = true;
    break;
  }
  if (!any_face) return false;
  for (const auto h : mesh.halfedges())
    if (mesh.is_boundary(h)) return false;
  return true;
}

bool is_two_manifold(const Mesh& mesh) {
  if (!is_closed(mesh)) return false;  // every edge needs two faces
  // Outgoing halfedges per vertex, counted from the halfedge list, against
  // those reached by circulating the vertex's fan: a vertex with several
  // fans has halfedges its circulator never reaches.
  std::vector<int> outgoing(mesh.n_vertices(), 0);
  for (const auto h : mesh.halfedges())
    ++outgoing[mesh.from_vertex_handle(h).idx()];
  for (const auto v : mesh.vertices()) {
    if (outgoing[v.idx()] == 0) return false;  // isolated vertex
    int in_fan = 0;
    for (const auto h : mesh.voh_range(v)) {
      (void)h;
      ++in_fan;
      if (in_fan > outgoing[v.idx()]) return false;  // corrupt cycle
    }
    if (in_fan != outgoing[v.idx()]) return false;
  }
  return true;
}

int euler_characteristic(const Mesh& mesh) {
  int v = 0, e = 0, f = 0;
  for (const auto vh : mesh.vertices()) (void)vh, ++v;
  for (const auto eh : mesh.edges()) (void)eh, ++e;
  for (const auto fh : mesh.faces()) (void)fh, ++f;
  return v - e + f;
}

int connected_components(const Mesh& mesh) {
  std::vector<int> parent(mesh.n_faces());
  std::iota(parent.begin(), parent.end(), 0);
  for (const auto e : mesh.edges()) {
    const auto f0 = mesh.face_handle(mesh.halfedge_handle(e, 0));
    const auto f1 = mesh.face_handle(mesh.halfedge_handle(e, 1));
    if (!f0.is_valid() || !f1.is_valid()) continue;
    const int r0 = find_root(parent, f0.idx()), r1 = find_root(parent, f1.idx());
    if (r0 != r1) parent[std::max(r0, r1)] = std::min(r0, r1);
  }
  int components = 0;
  for (const auto f : mesh.faces())
    if (find_root(parent, f.idx()) == f.idx()) ++components;
  return components;
}

namespace {

// chi = 2 (components - genus) over closed components (isolated vertices
// left out of chi).
int genus_from(int chi, int components) { return (2 * components - chi) / 2; }

}  // namespace

int genus(const Mesh& mesh) {
  return genus_from(euler_characteristic(mesh) - count_isolated_vertices(mesh), connected_components(mesh));
}

namespace {

std::size_t intersecting_pairs_among(const FaceList& faces, int threads) {
  const int n = static_cast<int>(faces.size());
  if (n < 2) return 0;

  // Grid: cell size twice the mean face extent (so a face spans few cells),
  // but at least 1e-6 of the mesh's bounding-box diagonal so that cell
  // indices stay small.
  Vec3 lo = faces[0].lo, hi = faces[0].hi;
  double mean_extent = 0.0;
  for (const FaceData& f : faces) {
    lo = lo.cwiseMin(f.lo);
    hi = hi.cwiseMax(f.hi);
    mean_extent += (f.hi - f.lo).maxCoeff();
  }
  mean_extent /= n;
  double cell = std::max(2.0 * mean_extent, 1e-6 * (hi - lo).norm());
  if (!(cell > 0.0) || !std::isfinite(cell)) cell = 1.0;

  // Monotone in x, so a box [lo, hi] covers cells cell_of(lo)..cell_of(hi).
  auto cell_of = [&](double x, int k) {
    return static_cast<int>(std::floor((x - lo[k]) / cell));
  };

  auto test = [&](int i, int j) {
    return triangles_intersect_improperly(faces[i].points, faces[i].ids,
                                          faces[j].points, faces[j].ids);
  };

  // Faces spanning very many cells (a few huge triangles among many small
  // ones) are kept out of the grid and tested against all faces directly.
  constexpr long kMaxCellsPerFace = 512;
  UninitVector<std::array<int, 6>> span(static_cast<std::size_t>(n));  // each face's cells, low and high corner
  std::vector<int> oversize;
  std::vector<bool> is_oversize(n, false);
  std::array<int, 3> cells{1, 1, 1};  // the grid's extent in cells
  std::size_t entry_count = 0;
  for (int i = 0; i < n; ++i) {
    std::array<int, 6>& c = span[static_cast<std::size_t>(i)];
    long count = 1;
    for (int k = 0; k < 3; ++k) {
      c[k] = cell_of(faces[i].lo[k], k);
      c[k + 3] = cell_of(faces[i].hi[k], k);
      count *= static_cast<long>(c[k + 3] - c[k] + 1);
      cells[k] = std::max(cells[k], c[k + 3] + 1);
    }
    if (count > kMaxCellsPerFace) {
      oversize.push_back(i);
      is_oversize[i] = true;
      continue;
    }
    entry_count += static_cast<std::size_t>(count);
  }
  // The faces of each occupied cell, in face order, cells in (x, y, z)
  // order of their linear index x + X (y + Y z): by counting over the dense
  // grid when it has no more cells than a few per entry (a surface's grid),
  // else by sorting (cell, face) pairs. Either gives the same lists; the
  // cells' order does not change the count. (The lists as sorted triples of
  // cell coordinates compared by memcmp were most of the check's own time
  // on an 841,136-face CT model, issue 17.)
  const std::uint64_t X = static_cast<std::uint64_t>(cells[0]), Y = static_cast<std::uint64_t>(cells[1]),
                      Z = static_cast<std::uint64_t>(cells[2]);
  const auto for_each_cell_of = [&](int i, auto&& visit) {
    const std::array<int, 6>& c = span[static_cast<std::size_t>(i)];
    for (int z = c[2]; z <= c[5]; ++z)
      for (int y = c[1]; y <= c[4]; ++y)
        for (int x = c[0]; x <= c[3]; ++x)
          visit(static_cast<std::uint64_t>(x) + X * (static_cast<std::uint64_t>(y) + Y * static_cast<std::uint64_t>(z)));
  };
  std::vector<std::uint64_t> cell_key;  // per occupied cell, its linear index
  std::vector<std::size_t> cell_begin;  // per occupied cell, where its faces start in `members`
  UninitVector<int> members(entry_count);
  const bool dense = entry_count < (std::uint64_t{1} << 32) &&
                     X * Y * Z <= std::max<std::uint64_t>(std::uint64_t{1} << 20, 4 * static_cast<std::uint64_t>(entry_count));
  if (dense) {
    // Counts per cell, then (in place) where each cell's next face goes.
    std::vector<std::uint32_t> at(static_cast<std::size_t>(X * Y * Z), 0);
    for (int i = 0; i < n; ++i)
      if (!is_oversize[i]) for_each_cell_of(i, [&](std::uint64_t key) { ++at[key]; });
    std::uint32_t next = 0;
    for (std::size_t key = 0; key < at.size(); ++key) {
      if (at[key] == 0) continue;
      cell_key.push_back(key);
      cell_begin.push_back(next);
      next += std::exchange(at[key], next);
    }
    for (int i = 0; i < n; ++i)
      if (!is_oversize[i]) for_each_cell_of(i, [&](std::uint64_t key) { members[at[key]++] = i; });
  } else {
    std::vector<std::pair<std::uint64_t, int>> entries;
    entries.reserve(entry_count);
    for (int i = 0; i < n; ++i)
      if (!is_oversize[i]) for_each_cell_of(i, [&](std::uint64_t key) { entries.emplace_back(key, i); });
    std::sort(entries.begin(), entries.end());
    for (std::size_t e = 0; e < entries.size(); ++e) {
      if (e == 0 || entries[e].first != entries[e - 1].first) {
        cell_key.push_back(entries[e].first);
        cell_begin.push_back(e);
      }
      members[e] = entries[e].second;
    }
  }
  cell_begin.push_back(entry_count);

  // Each overlapping pair shares the cell containing the low corner of the
  // intersection of their boxes; it is tested only in that cell. Cells are
  // independent: counted in parallel, summed in cell order.
  std::vector<std::size_t> cell_pairs(cell_begin.size() - 1, 0);
  parallel_for(cell_pairs.size(), resolve_thread_count(threads), [&](std::size_t c) {
    const std::size_t begin = cell_begin[c], end = cell_begin[c + 1];
    const std::uint64_t linear = cell_key[c];
    const std::array<int, 3> key{static_cast<int>(linear % X), static_cast<int>((linear / X) % Y),
                                 static_cast<int>(linear / X / Y)};
    std::size_t found = 0;
    for (std::size_t a = begin; a < end; ++a) {
      const int i = members[a];
      for (std::size_t b = a + 1; b < end; ++b) {
        const int j = members[b];
        if (!boxes_overlap(faces[i], faces[j])) continue;
        bool home = true;
        for (int k = 0; k < 3 && home; ++k)
          home = cell_of(std::max(faces[i].lo[k], faces[j].lo[k]), k) == key[k];
        if (home && test(i, j)) ++found;
      }
    }
    cell_pairs[c] = found;
  });
  std::size_t pairs = 0;
  for (std::size_t found : cell_pairs) pairs += found;
  // Oversize faces against all faces (each oversize-oversize pair once).
  for (const int i : oversize) {
    for (int j = 0; j < n; ++j) {
      if (j == i || (is_oversize[j] && j < i)) continue;
      if (boxes_overlap(faces[i], faces[j]) && test(i, j)) ++pairs;
    }
  }
  return pairs;
}

double volume_of(const Mesh& mesh, const FaceList& faces) {
  // Sum of signed tetrahedra (reference, a, b, c); the reference point is the
  // bounding-box centre, which keeps the terms small for meshes far from the
  // origin (the sum does not depend on it for closed meshes).
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  for (const auto v : mesh.vertices()) {
    const Vec3 p = to_eigen(mesh.point(v));
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (!(lo.array() <= hi.array()).all()) return 0.0;
  const Vec3 reference = 0.5 * (lo + hi);
  double six_volume = 0.0;
  for (const FaceData& f : faces) {
    const Vec3 a = f.points[0] - reference, b = f.points[1] - reference,
               c = f.points[2] - reference;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

double area_of(const FaceList& faces) {
  double twice_area = 0.0;
  for (const FaceData& f : faces)
    twice_area +=
        (f.points[1] - f.points[0]).cross(f.points[2] - f.points[0]).norm();
  return 0.5 * twice_area;
}

// Each face's smallest angle in parallel, their minimum in order (a minimum
// is exact: the same for any thread count).
double smallest_angle_of(const FaceList& faces, int threads) {
  if (faces.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::vector<double> angle(faces.size());
  parallel_for(faces.size(), resolve_thread_count(threads), [&](std::size_t i) {
    const FaceData& f = faces[i];
    double smallest = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k) {
      const Vec3 u = f.points[(k + 1) % 3] - f.points[k];
      const Vec3 w = f.points[(k + 2) % 3] - f.points[k];
      // atan2 of |u x w| and u . w is accurate for small and large angles.
      smallest = std::min(smallest, std::atan2(u.cross(w).norm(), u.dot(w)));
    }
    angle[i] = smallest;
  });
  double smallest = std::numeric_limits<double>::infinity();
  for (double a : angle) smallest = std::min(smallest, a);
  return smallest * (180.0 / 3.14159265358979323846);
}

// Every edge's fold (mesh_checks.h), degrees, in parallel; -1 for an edge
// without two faces.
std::vector<double> edge_folds(const Mesh& mesh, int threads) {
  std::vector<double> fold(mesh.n_edges(), -1.0);
  parallel_for(fold.size(), resolve_thread_count(threads), [&](std::size_t i) {
    const Mesh::EdgeHandle e(static_cast<int>(i));
    if (mesh.has_edge_status() && mesh.status(e).deleted()) return;
    if (!mesh.is_boundary(e)) fold[i] = edge_fold_degrees(mesh, e);
  });
  return fold;
}

double sharpest_of(const std::vector<double>& folds) {
  double sharpest = 0.0;
  for (double f : folds) sharpest = std::max(sharpest, f);
  return sharpest;
}

std::size_t count_beyond(const std::vector<double>& folds, double degrees) {
  return static_cast<std::size_t>(std::count_if(folds.begin(), folds.end(), [&](double f) { return f > degrees; }));
}

}  // namespace

double fold_degrees(const std::array<Vec3, 3>& a, const std::array<Vec3, 3>& b) {
  const Vec3 na = (a[1] - a[0]).cross(a[2] - a[0]), nb = (b[1] - b[0]).cross(b[2] - b[0]);
  if (na.isZero() || nb.isZero()) return 0.0;
  // atan2 of |na x nb| and na . nb: accurate near 0 and 180 degrees.
  return std::atan2(na.cross(nb).norm(), na.dot(nb)) * (180.0 / 3.14159265358979323846);
}

double edge_fold_degrees(const Mesh& mesh, Mesh::EdgeHandle e) {
  const auto corners = [&](Mesh::FaceHandle f) {
    auto it = mesh.cfv_iter(f);
    return std::array<Vec3, 3>{to_eigen(mesh.point(*it)), to_eigen(mesh.point(*++it)), to_eigen(mesh.point(*++it))};
  };
  return fold_degrees(corners(mesh.face_handle(mesh.halfedge_handle(e, 0))),
                      corners(mesh.face_handle(mesh.halfedge_handle(e, 1))));
}

double sharpest_fold_degrees(const Mesh& mesh) { return sharpest_of(edge_folds(mesh, 1)); }

std::size_t folded_edges(const Mesh& mesh, double degrees) { return count_beyond(edge_folds(mesh, 1), degrees); }

std::size_t self_intersecting_pairs(const Mesh& mesh, int threads) {
  return intersecting_pairs_among(collect_faces(mesh, threads), threads);
}

double enclosed_volume(const Mesh& mesh) { return volume_of(mesh, collect_faces(mesh)); }

double surface_area(const Mesh& mesh) { return area_of(collect_faces(mesh)); }

double smallest_angle_degrees(const Mesh& mesh) { return smallest_angle_of(collect_faces(mesh), 1); }

double mean_edge_length(const Mesh& mesh) {
  double sum = 0.0;
  for (auto e : mesh.edges()) sum += mesh.calc_edge_length(e);
  return mesh.n_edges() > 0 ? sum / static_cast<double>(mesh.n_edges()) : 0.0;
}

bool faces_meet_mesh(const Mesh& mesh, const std::vector<Mesh::FaceHandle>& faces) {
  if (faces.empty()) return false;
  using Tri = std::array<Vec3, 3>;
  using Ids = std::array<int, 3>;
  const auto triangle = [&](Mesh::FaceHandle f, Tri& p, Ids& id) {
    int c = 0;
    for (auto v : mesh.fv_range(f)) {
      p[c] = to_eigen(mesh.point(v));
      id[c++] = v.idx();
    }
  };
  const auto box_of = [](const Tri& p, Vec3& lo, Vec3& hi) {
    lo = p[0].cwiseMin(p[1]).cwiseMin(p[2]);
    hi = p[0].cwiseMax(p[1]).cwiseMax(p[2]);
  };
  const auto apart = [](const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
    return (alo.array() > bhi.array()).any() || (ahi.array() < blo.array()).any();
  };
  std::vector<char> listed(mesh.n_faces(), 0);
  std::vector<Tri> p(faces.size());
  std::vector<Ids> id(faces.size());
  std::vector<Vec3> lo(faces.size()), hi(faces.size());
  Vec3 all_lo = Vec3::Constant(std::numeric_limits<double>::infinity()), all_hi = -all_lo;
  for (std::size_t i = 0; i < faces.size(); ++i) {
    listed[static_cast<std::size_t>(faces[i].idx())] = 1;
    triangle(faces[i], p[i], id[i]);
    box_of(p[i], lo[i], hi[i]);
    all_lo = all_lo.cwiseMin(lo[i]);
    all_hi = all_hi.cwiseMax(hi[i]);
  }
  Tri q;
  Ids qid;
  Vec3 qlo, qhi;
  for (auto f : mesh.faces()) {
    if (listed[static_cast<std::size_t>(f.idx())]) continue;
    triangle(f, q, qid);
    box_of(q, qlo, qhi);
    if (apart(qlo, qhi, all_lo, all_hi)) continue;
    for (std::size_t i = 0; i < faces.size(); ++i)
      if (!apart(qlo, qhi, lo[i], hi[i]) && triangles_intersect_improperly(p[i], id[i], q, qid)) return true;
  }
  for (std::size_t i = 0; i < faces.size(); ++i)
    for (std::size_t j = i + 1; j < faces.size(); ++j)
      if (!apart(lo[i], hi[i], lo[j], hi[j]) && triangles_intersect_improperly(p[i], id[i], p[j], id[j])) return true;
  return false;
}

MeshReport measure(const Mesh& mesh, int threads) {
  MeshReport r;
  for (const auto v : mesh.vertices()) (void)v, ++r.vertices;
  for (const auto f : mesh.faces()) (void)f, ++r.faces;
  for (const auto e : mesh.edges()) (void)e, ++r.edges;
  r.closed = is_closed(mesh);
  r.two_manifold = is_two_manifold(mesh);
  r.euler = euler_characteristic(mesh);
  // The components and chi counted once for the genus and its check.
  const int chi = r.euler - count_isolated_vertices(mesh);
  r.components = connected_components(mesh);
  r.genus = genus_from(chi, r.components);
  r.euler_consistent = euler_consistent(chi, r.components, r.genus, r.closed);
  // The face list gathered once for the four measures that read it.
  const FaceList faces = collect_faces(mesh, threads);
  r.self_intersections = intersecting_pairs_among(faces, threads);
  r.volume = volume_of(mesh, faces);
  r.area = area_of(faces);
  r.min_angle_deg = smallest_angle_of(faces, threads);
  const std::vector<double> folds = edge_folds(mesh, threads);
  r.max_fold_deg = sharpest_of(folds);
  r.folds = count_beyond(folds, kFoldDegrees);
  return r;
}

std::string to_string(const MeshReport& r) {
  std::ostringstream out;
  out.precision(6);
  out << "V=" << r.vertices << " F=" << r.faces << " E=" << r.edges
      << " closed=" << (r.closed ? "yes" : "no")
      << " two_manifold=" << (r.two_manifold ? "yes" : "no")
      << " chi=" << r.euler << " genus=" << r.genus
      << " components=" << r.components
      << " self_intersections=" << r.self_intersections
      << " volume=" << r.volume << " area=" << r.area
      << " min_angle_deg=" << r.min_angle_deg << " max_fold_deg=" << r.max_fold_deg << " folds=" << r.folds;
  return out.str();
}

}  // namespace gdm
