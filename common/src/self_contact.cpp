#include "gdm/self_contact.h"

#include <algorithm>
#include <numeric>
#include <unordered_set>

#include "gdm/face_grid.h"
#include "gdm/parallel.h"
#include "gdm/text.h"
#include "gdm/triangle_locator.h"

namespace gdm {
namespace {

struct FaceData {
  Triangle corners;
  Vec3 centroid;
  Vec3 normal;  // unit
  double area;
};

bool face_is_deleted(const Mesh& mesh, Mesh::FaceHandle f) { return mesh.has_face_status() && mesh.status(f).deleted(); }

// Each face's data written by its own iteration (deleted faces: zero area,
// skipped by every test).
std::vector<FaceData> face_data(const Mesh& mesh, int threads) {
  std::vector<FaceData> faces(mesh.n_faces());  // value-initialized: zeros
  parallel_for(faces.size(), threads, [&](std::size_t i) {
    const Mesh::FaceHandle f(static_cast<int>(i));
    if (face_is_deleted(mesh, f)) return;
    FaceData& d = faces[i];
    int k = 0;
    for (auto v : mesh.fv_range(f)) d.corners[static_cast<std::size_t>(k++)] = to_eigen(mesh.point(v));
    d.centroid = (d.corners[0] + d.corners[1] + d.corners[2]) / 3.0;
    const Vec3 n = (d.corners[1] - d.corners[0]).cross(d.corners[2] - d.corners[0]);
    d.area = 0.5 * n.norm();
    d.normal = d.area > 0.0 ? Vec3(n.normalized()) : Vec3::Zero();
  });
  return faces;
}

// The vertices of f and of its neighbours: faces touching them are f's own
// neighbourhood, never a contact.
std::unordered_set<int> neighbourhood_of(const Mesh& mesh, Mesh::FaceHandle f) {
  std::unordered_set<int> near;
  for (auto v : mesh.fv_range(f)) {
    near.insert(v.idx());
    for (auto w : mesh.vv_range(v)) near.insert(w.idx());
  }
  return near;
}

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    parent[static_cast<std::size_t>(i)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
    i = parent[static_cast<std::size_t>(i)];
  }
  return i;
}

// Is face f in contact (contact_faces' definition)? Writes its gap's midpoint
// when so. With `behind`, the other face lies behind f (the model is thin
// there, thin_faces) instead of in front of it.
bool face_in_contact(const Mesh& mesh, const std::vector<FaceData>& faces, const FaceGrid& grid, int f,
                     double distance, Vec3* gap, bool behind) {
  const FaceData& a = faces[static_cast<std::size_t>(f)];
  if (a.area == 0.0) return false;
  const Vec3 reach = Vec3::Constant(distance);
  std::unordered_set<int> near;
  return grid.any_near(a.centroid - reach, a.centroid + reach, [&](int g) {
    const FaceData& b = faces[static_cast<std::size_t>(g)];
    if (g == f || b.area == 0.0 || a.normal.dot(b.normal) > -0.5) return false;
    if (((b.centroid - a.centroid).dot(a.normal) <= 0.0) != behind) return false;  // on the wrong side of f
    const double d = point_triangle_distance(a.centroid, b.corners);
    if (d >= distance) return false;
    if (near.empty()) near = neighbourhood_of(mesh, Mesh::FaceHandle(f));
    for (auto v : mesh.fv_range(Mesh::FaceHandle(g)))
      if (near.count(v.idx())) return false;
    if (gap) *gap = a.centroid + (behind ? -0.5 : 0.5) * d * a.normal;
    return true;
  });
}

// contact_faces over face data already computed. Faces are flagged in
// parallel: the grid, the face data and the mesh are only read, and each
// face's flag and gap are written by its own iteration alone (the first
// contact any_near finds depends on the grid, never on the thread count).
std::vector<char> faces_in_contact(const Mesh& mesh, const std::vector<FaceData>& faces, double distance,
                                   std::vector<Vec3>* gaps, int threads, bool behind = false,
                                   const std::vector<char>* only = nullptr) {
  std::vector<char> contact(mesh.n_faces(), 0);
  if (gaps) gaps->assign(mesh.n_faces(), Vec3::Zero());
  if (mesh.n_faces() == 0 || !(distance > 0.0)) return contact;
  double longest = 0.0;
  for (const FaceData& d : faces)
    for (int k = 0; k < 3; ++k) longest = std::max(longest, (d.corners[static_cast<std::size_t>(k)] - d.centroid).norm());
  FaceGrid grid;
  grid.rebuild(mesh, std::max(distance, longest), 0.0);
  parallel_for(faces.size(), threads, [&](std::size_t i) {
    if (only && !(*only)[i]) return;
    contact[i] = face_in_contact(mesh, faces, grid, static_cast<int>(i), distance, gaps ? &(*gaps)[i] : nullptr, behind);
  });
  return contact;
}

}  // namespace

std::vector<char> contact_faces(const Mesh& mesh, double distance, std::vector<Vec3>* gaps, int threads,
                                const std::vector<char>* only) {
  return faces_in_contact(mesh, face_data(mesh, threads), distance, gaps, threads, false, only);
}

std::vector<char> thin_faces(const Mesh& mesh, double distance, std::vector<Vec3>* middles, int threads) {
  return faces_in_contact(mesh, face_data(mesh, threads), distance, middles, threads, true);
}

ContactReport find_self_contacts(const Mesh& mesh, double distance, const std::function<bool(const Vec3&)>& object_side,
                                 int threads) {
  ContactReport report;
  if (mesh.n_faces() == 0 || !(distance > 0.0)) return report;
  const std::vector<FaceData> faces = face_data(mesh, threads);
  std::vector<Vec3> gap;
  const std::vector<char> contact = faces_in_contact(mesh, faces, distance, &gap, threads);

  // Edge-connected regions, in face order (deterministic).
  std::vector<int> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  for (auto e : mesh.edges()) {
    if (mesh.is_boundary(e)) continue;
    const int f = mesh.face_handle(mesh.halfedge_handle(e, 0)).idx();
    const int g = mesh.face_handle(mesh.halfedge_handle(e, 1)).idx();
    if (contact[static_cast<std::size_t>(f)] && contact[static_cast<std::size_t>(g)])
      parent[static_cast<std::size_t>(find_root(parent, f))] = find_root(parent, g);
  }
  std::vector<int> region_of(faces.size(), -1);
  std::vector<int> votes;  // per region: object side minus background side
  for (std::size_t i = 0; i < faces.size(); ++i) {
    if (!contact[i]) continue;
    const int root = find_root(parent, static_cast<int>(i));
    if (region_of[static_cast<std::size_t>(root)] < 0) {
      region_of[static_cast<std::size_t>(root)] = static_cast<int>(report.regions.size());
      report.regions.emplace_back();
      votes.push_back(0);
    }
    const int r = region_of[static_cast<std::size_t>(root)];
    ContactRegion& region = report.regions[static_cast<std::size_t>(r)];
    ++region.faces;
    region.area += faces[i].area;
    region.centre += faces[i].area * faces[i].centroid;
    if (object_side) votes[static_cast<std::size_t>(r)] += object_side(gap[i]) ? 1 : -1;
  }
  for (std::size_t r = 0; r < report.regions.size(); ++r) {
    ContactRegion& region = report.regions[r];
    if (region.area > 0.0) region.centre /= region.area;
    region.across_object = votes[r] >= 0;
    report.faces += region.faces;
    report.area += region.area;
  }
  std::stable_sort(report.regions.begin(), report.regions.end(),
                   [](const ContactRegion& a, const ContactRegion& b) { return a.area > b.area; });
  return report;
}

std::vector<std::string> describe_contacts(const ContactReport& report, std::size_t limit) {
  std::vector<std::string> lines;
  if (report.regions.empty()) return lines;
  lines.push_back("the model meets itself in " + std::to_string(report.regions.size()) + " region(s), " +
                  format_number(report.area, 4) + " mm^2 of faces closer than a voxel to another part of the surface:");
  for (std::size_t i = 0; i < report.regions.size() && i < limit; ++i) {
    const ContactRegion& r = report.regions[i];
    const Vec3& c = r.centre;
    lines.push_back("  at (" + format_number(c.x(), 4) + ", " + format_number(c.y(), 4) + ", " + format_number(c.z(), 4) +
                    ") mm, " + format_number(r.area, 4) + " mm^2: " +
                    (r.across_object ? "two sheets a hair apart across the object: the model grew around a cavity or "
                                       "a handle of the object from two sides, so the surface there is not the object's"
                                     : "a slit of background thinner than a voxel between two parts of the object"));
  }
  if (report.regions.size() > limit)
    lines.push_back("  ... and " + std::to_string(report.regions.size() - limit) + " smaller region(s)");
  return lines;
}

}  // namespace gdm
