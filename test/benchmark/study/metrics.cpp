// See metrics.h.
#include "metrics.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <unordered_map>
#include <unordered_set>

#include <OpenMesh/Core/System/omstream.hh>

#include "gdm/mesh_checks.h"
#include "gdm/predicates.h"
#include "gdm/self_contact.h"

namespace study {
namespace {

std::uint64_t edge_key(int a, int b) {
  if (a > b) std::swap(a, b);
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int a, int b) { parent[find(a)] = find(b); }
};

gdm::Vec3 vec(const Point& p) { return {p[0], p[1], p[2]}; }

// Improperly intersecting face pairs of a soup, by gdm's exact predicate, with a uniform grid.
long soup_self_intersections(const Surface& s) {
  if (s.faces.empty()) return 0;
  gdm::Vec3 lo = vec(s.points[s.faces[0][0]]), hi = lo;
  double edge_sum = 0.0;
  for (const auto& f : s.faces)
    for (int k = 0; k < 3; ++k) {
      lo = lo.cwiseMin(vec(s.points[f[k]]));
      hi = hi.cwiseMax(vec(s.points[f[k]]));
      edge_sum += (vec(s.points[f[k]]) - vec(s.points[f[(k + 1) % 3]])).norm();
    }
  const double cell = std::max(1e-9, 2.0 * edge_sum / (3.0 * s.faces.size()));
  auto key = [&](const gdm::Vec3& p) {
    return std::array<long, 3>{static_cast<long>((p.x() - lo.x()) / cell), static_cast<long>((p.y() - lo.y()) / cell),
                               static_cast<long>((p.z() - lo.z()) / cell)};
  };
  const long nx = key(hi)[0] + 1, ny = key(hi)[1] + 1;
  std::unordered_map<long, std::vector<int>> grid;
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    gdm::Vec3 a = vec(s.points[s.faces[t][0]]), b = a;
    for (int k = 1; k < 3; ++k) {
      a = a.cwiseMin(vec(s.points[s.faces[t][k]]));
      b = b.cwiseMax(vec(s.points[s.faces[t][k]]));
    }
    const auto ka = key(a), kb = key(b);
    for (long i = ka[0]; i <= kb[0]; ++i)
      for (long j = ka[1]; j <= kb[1]; ++j)
        for (long k = ka[2]; k <= kb[2]; ++k) grid[i + nx * (j + ny * k)].push_back(static_cast<int>(t));
  }
  // Each pair is tested once: in the cell holding the lower corner of the overlap of their boxes.
  std::vector<std::array<long, 3>> lower(s.faces.size());
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    gdm::Vec3 a = vec(s.points[s.faces[t][0]]);
    for (int k = 1; k < 3; ++k) a = a.cwiseMin(vec(s.points[s.faces[t][k]]));
    lower[t] = key(a);
  }
  long count = 0;
  for (const auto& [cell_id, faces] : grid) {
    for (std::size_t x = 0; x < faces.size(); ++x)
      for (std::size_t y = x + 1; y < faces.size(); ++y) {
        const int f = faces[x], g = faces[y];
        const long rx = std::max(lower[f][0], lower[g][0]), ry = std::max(lower[f][1], lower[g][1]),
                   rz = std::max(lower[f][2], lower[g][2]);
        if (rx + nx * (ry + ny * rz) != cell_id) continue;
        const auto& F = s.faces[f];
        const auto& G = s.faces[g];
        const std::array<gdm::Vec3, 3> t1{vec(s.points[F[0]]), vec(s.points[F[1]]), vec(s.points[F[2]])};
        const std::array<gdm::Vec3, 3> t2{vec(s.points[G[0]]), vec(s.points[G[1]]), vec(s.points[G[2]])};
        if (gdm::triangles_intersect_improperly(t1, F, t2, G)) ++count;
      }
  }
  return count;
}

}  // namespace

Surface from_gdm(const gdm::Mesh& mesh) {
  Surface s;
  std::vector<int> index(mesh.n_vertices(), -1);
  const auto generation = gdm::find_generation_property(mesh);
  for (auto v : mesh.vertices()) {
    index[v.idx()] = static_cast<int>(s.points.size());
    const auto& p = mesh.point(v);
    s.points.push_back({p[0], p[1], p[2]});
    if (generation.is_valid()) s.generation.push_back(mesh.property(generation, v));
  }
  for (auto f : mesh.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (auto v : mesh.fv_range(f)) t[k++] = index[v.idx()];
    s.faces.push_back(t);
  }
  return s;
}

// Every face's three edges as (edge key, face) pairs, sorted: the uses of an
// edge are neighbours.
static std::vector<std::pair<std::uint64_t, int>> sorted_edge_uses(const Surface& s) {
  std::vector<std::pair<std::uint64_t, int>> edges;
  edges.reserve(s.faces.size() * 3);
  for (std::size_t t = 0; t < s.faces.size(); ++t)
    for (int k = 0; k < 3; ++k) edges.emplace_back(edge_key(s.faces[t][k], s.faces[t][(k + 1) % 3]), static_cast<int>(t));
  std::sort(edges.begin(), edges.end());
  return edges;
}

Checks check_surface(const Surface& s, std::size_t max_faces_for_intersections) {
  Checks c;
  // Edge use counts (sorted (edge, face) pairs) and face components through edges.
  const std::vector<std::pair<std::uint64_t, int>> edges = sorted_edge_uses(s);
  UnionFind uf(s.faces.size());
  bool boundary = false, edges_two = true;
  std::size_t edge_count = 0;
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    ++edge_count;
    if (j - i == 1) boundary = true;
    if (j - i != 2) edges_two = false;
    for (std::size_t k = i + 1; k < j; ++k) uf.unite(edges[i].second, edges[k].second);
    i = j;
  }
  std::unordered_set<int> roots;
  for (std::size_t t = 0; t < s.faces.size(); ++t) roots.insert(uf.find(static_cast<int>(t)));
  c.components = static_cast<int>(roots.size());
  c.closed = !s.faces.empty() && !boundary;

  // Vertex fans: the faces around each vertex must form one fan (connected
  // through the edges at the vertex). Faces per vertex in compressed rows.
  bool fans_ok = edges_two && !s.faces.empty();
  if (fans_ok) {
    std::vector<int> start(s.points.size() + 1, 0);
    for (const auto& f : s.faces)
      for (int v : f) ++start[v + 1];
    for (std::size_t v = 0; v < s.points.size(); ++v) start[v + 1] += start[v];
    std::vector<int> fill(start.begin(), start.end() - 1), fan_of(start.back());
    for (std::size_t t = 0; t < s.faces.size(); ++t)
      for (int v : s.faces[t]) fan_of[fill[v]++] = static_cast<int>(t);
    std::vector<int> stack;
    std::vector<char> seen;
    for (std::size_t v = 0; v < s.points.size() && fans_ok; ++v) {
      const int b = start[v], e = start[v + 1], n = e - b;
      if (n == 0) continue;  // unreferenced points are not part of the surface
      seen.assign(n, 0);
      seen[0] = 1;
      stack.assign(1, 0);
      int reached = 1;
      while (!stack.empty()) {
        const int x = stack.back();
        stack.pop_back();
        const auto& F = s.faces[fan_of[b + x]];
        for (int y = 0; y < n; ++y) {
          if (seen[y]) continue;
          const auto& G = s.faces[fan_of[b + y]];
          int shared = 0;  // vertices other than v that F and G share
          for (int p : F)
            if (p != static_cast<int>(v) && (p == G[0] || p == G[1] || p == G[2])) ++shared;
          if (shared > 0) {
            seen[y] = 1;
            ++reached;
            stack.push_back(y);
          }
        }
      }
      if (reached != n) fans_ok = false;
    }
  }
  c.two_manifold = fans_ok;

  // A closed 2-manifold soup is measured as a gdm::Mesh with gdm's own checks.
  gdm::Mesh mesh;
  if (c.two_manifold && to_gdm_mesh(s, mesh)) {
    c.via_gdm_mesh = true;
    c.closed = gdm::is_closed(mesh);
    c.two_manifold = gdm::is_two_manifold(mesh);
    c.components = gdm::connected_components(mesh);
    c.genus = c.closed && c.two_manifold ? gdm::genus(mesh) : -1;
    if (s.faces.size() <= max_faces_for_intersections)
      c.self_intersections = static_cast<long>(gdm::self_intersecting_pairs(mesh));
    return c;
  }
  if (c.closed && c.two_manifold) {
    std::unordered_set<int> used;
    for (const auto& f : s.faces) used.insert(f.begin(), f.end());
    const long chi = static_cast<long>(used.size()) - static_cast<long>(edge_count) + static_cast<long>(s.faces.size());
    c.genus = static_cast<int>((2 * c.components - chi) / 2);
  }
  if (s.faces.size() <= max_faces_for_intersections) c.self_intersections = soup_self_intersections(s);
  return c;
}

bool to_gdm_mesh(const Surface& s, gdm::Mesh& mesh) {
  mesh.clear();
  std::vector<gdm::Mesh::VertexHandle> handles;
  handles.reserve(s.points.size());
  for (const auto& p : s.points) handles.push_back(mesh.add_vertex({p[0], p[1], p[2]}));
  bool ok = true;
  omerr().disable();
  for (const auto& f : s.faces)
    if (!mesh.add_face(handles[f[0]], handles[f[1]], handles[f[2]]).is_valid()) {
      ok = false;  // non-manifold or inconsistent orientation
      break;
    }
  omerr().enable();
  if (!ok) return false;
  // Drop the unreferenced points so that gdm counts them as it counts the surface.
  for (auto v : mesh.vertices())
    if (mesh.is_isolated(v)) {
      mesh.request_vertex_status();
      mesh.delete_vertex(v, false);
    }
  if (mesh.has_vertex_status()) mesh.garbage_collection();
  return true;
}

namespace {

// Face labels of the edge-connected components; returns their count.
int label_components(const Surface& s, std::vector<int>& label) {
  const std::vector<std::pair<std::uint64_t, int>> edges = sorted_edge_uses(s);
  UnionFind uf(s.faces.size());
  for (std::size_t i = 0; i < edges.size();) {
    std::size_t j = i + 1;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    for (std::size_t k = i + 1; k < j; ++k) uf.unite(edges[i].second, edges[k].second);
    i = j;
  }
  std::unordered_map<int, int> id;
  label.assign(s.faces.size(), -1);
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    const int root = uf.find(static_cast<int>(t));
    auto it = id.emplace(root, static_cast<int>(id.size())).first;
    label[t] = it->second;
  }
  return static_cast<int>(id.size());
}

}  // namespace

std::vector<ComponentTopology> component_topology(const Surface& s) {
  std::vector<int> label;
  const int n = label_components(s, label);
  std::vector<ComponentTopology> out(n);
  std::vector<gdm::Vec3> lo(n, gdm::Vec3::Constant(1e300)), hi(n, gdm::Vec3::Constant(-1e300));
  std::vector<std::unordered_set<int>> vertices(n);
  std::vector<std::unordered_map<std::uint64_t, int>> edge_uses(n);
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    const int c = label[t];
    ++out[c].faces;
    for (int k = 0; k < 3; ++k) {
      const int v = s.faces[t][k];
      vertices[c].insert(v);
      ++edge_uses[c][edge_key(v, s.faces[t][(k + 1) % 3])];
      lo[c] = lo[c].cwiseMin(vec(s.points[v]));
      hi[c] = hi[c].cwiseMax(vec(s.points[v]));
    }
  }
  for (int c = 0; c < n; ++c) {
    out[c].extent = (hi[c] - lo[c]).norm();
    bool closed = true;
    for (const auto& [edge, uses] : edge_uses[c]) closed = closed && uses == 2;
    if (!closed) continue;
    const long chi = static_cast<long>(vertices[c].size()) - static_cast<long>(edge_uses[c].size()) +
                     static_cast<long>(out[c].faces);
    out[c].genus = static_cast<int>((2 - chi) / 2);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const ComponentTopology& a, const ComponentTopology& b) { return a.extent > b.extent; });
  return out;
}

Surface largest_component(const Surface& s) {
  std::vector<int> label;
  const int n = label_components(s, label);
  if (n <= 1) return s;
  std::vector<gdm::Vec3> lo(n, gdm::Vec3::Constant(1e300)), hi(n, gdm::Vec3::Constant(-1e300));
  for (std::size_t t = 0; t < s.faces.size(); ++t)
    for (int v : s.faces[t]) {
      lo[label[t]] = lo[label[t]].cwiseMin(vec(s.points[v]));
      hi[label[t]] = hi[label[t]].cwiseMax(vec(s.points[v]));
    }
  int best = 0;
  for (int c = 1; c < n; ++c)
    if ((hi[c] - lo[c]).norm() > (hi[best] - lo[best]).norm()) best = c;
  Surface out;
  std::vector<int> index(s.points.size(), -1);
  for (std::size_t t = 0; t < s.faces.size(); ++t) {
    if (label[t] != best) continue;
    std::array<int, 3> f{};
    for (int k = 0; k < 3; ++k) {
      int& i = index[s.faces[t][k]];
      if (i < 0) {
        i = static_cast<int>(out.points.size());
        out.points.push_back(s.points[s.faces[t][k]]);
      }
      f[k] = i;
    }
    out.faces.push_back(f);
  }
  return out;
}

std::vector<Point> sample_points(const Surface& s) {
  std::vector<Point> points;
  std::vector<char> used(s.points.size(), 0);
  for (const auto& f : s.faces) {
    Point c{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      used[f[k]] = 1;
      for (int a = 0; a < 3; ++a) c[a] += s.points[f[k]][a] / 3.0;
    }
    points.push_back(c);
  }
  for (std::size_t i = 0; i < s.points.size(); ++i)
    if (used[i]) points.push_back(s.points[i]);
  return points;
}

ErrorStats error_stats(const std::vector<Point>& points, const std::function<double(const Point&)>& distance,
                       double voxel_size) {
  ErrorStats e;
  if (points.empty()) return e;
  std::vector<double> d(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) d[i] = std::abs(distance(points[i])) / voxel_size;
  e.mean = std::accumulate(d.begin(), d.end(), 0.0) / static_cast<double>(d.size());
  double within = 0.0;
  std::size_t beyond = 0;
  for (double x : d) {
    if (x > 1.0) ++beyond;
    else within += x;
  }
  e.share_beyond_one = static_cast<double>(beyond) / static_cast<double>(d.size());
  e.mean_within_one = beyond < d.size() ? within / static_cast<double>(d.size() - beyond) : 0.0;
  e.max = *std::max_element(d.begin(), d.end());
  const std::size_t k = std::min(d.size() - 1, static_cast<std::size_t>(std::ceil(0.95 * d.size())) - 1);
  std::nth_element(d.begin(), d.begin() + static_cast<long>(k), d.end());
  e.p95 = d[k];
  e.valid = true;
  return e;
}

SeamSplit seam_split(const Surface& s, const std::function<double(const Point&)>& distance, double voxel_size,
                     const std::function<bool(const gdm::Vec3&)>& object_side, int threads) {
  SeamSplit r;
  if (s.faces.empty()) return r;
  // The faces OpenMesh accepts (a decimated surface may have a few
  // non-manifold edges or vertices; the faces it refuses count as off the
  // seams), in the surface's order.
  gdm::Mesh mesh;
  std::vector<gdm::Mesh::VertexHandle> handles;
  handles.reserve(s.points.size());
  for (const auto& p : s.points) handles.push_back(mesh.add_vertex({p[0], p[1], p[2]}));
  std::vector<int> refused;
  omerr().disable();
  for (std::size_t i = 0; i < s.faces.size(); ++i) {
    const auto& f = s.faces[i];
    if (!mesh.add_face(handles[f[0]], handles[f[1]], handles[f[2]]).is_valid()) refused.push_back(static_cast<int>(i));
  }
  omerr().enable();
  std::vector<gdm::Vec3> gaps;
  std::vector<char> seam = gdm::contact_faces(mesh, voxel_size, &gaps, threads);
  std::size_t seams = 0;
  for (std::size_t f = 0; f < seam.size(); ++f) {
    seam[f] = seam[f] && object_side(gaps[f]);
    seams += seam[f] ? 1 : 0;
  }
  double sum = 0.0;
  std::size_t count = 0;
  const auto add = [&](const gdm::Vec3& p) {
    sum += std::abs(distance({p.x(), p.y(), p.z()})) / voxel_size;
    ++count;
  };
  for (auto f : mesh.faces()) {
    if (seam[static_cast<std::size_t>(f.idx())]) continue;
    gdm::Vec3 c = gdm::Vec3::Zero();
    for (auto v : mesh.fv_range(f)) c += gdm::to_eigen(mesh.point(v));
    add(c / 3.0);
  }
  std::vector<char> elsewhere(s.points.size(), 0);
  for (auto v : mesh.vertices())
    for (auto f : mesh.vf_range(v)) elsewhere[static_cast<std::size_t>(v.idx())] |= !seam[static_cast<std::size_t>(f.idx())];
  for (int i : refused) {
    Point c{0, 0, 0};
    for (int k = 0; k < 3; ++k) {
      const auto& q = s.points[static_cast<std::size_t>(s.faces[static_cast<std::size_t>(i)][k])];
      elsewhere[static_cast<std::size_t>(s.faces[static_cast<std::size_t>(i)][k])] = 1;
      for (int a = 0; a < 3; ++a) c[a] += q[a] / 3.0;
    }
    add({c[0], c[1], c[2]});
  }
  for (std::size_t i = 0; i < elsewhere.size(); ++i)
    if (elsewhere[i]) add({s.points[i][0], s.points[i][1], s.points[i][2]});
  r.share = static_cast<double>(seams) / static_cast<double>(s.faces.size());
  r.mean_elsewhere = count ? sum / static_cast<double>(count) : 0.0;
  r.valid = true;
  return r;
}

}  // namespace study
