#include "gdm/self_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>
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

// One face's data (a deleted face: zero area, skipped by every test).
FaceData data_of(const Mesh& mesh, Mesh::FaceHandle f) {
  FaceData d{};
  if (face_is_deleted(mesh, f)) return d;
  int k = 0;
  for (auto v : mesh.fv_range(f)) d.corners[static_cast<std::size_t>(k++)] = to_eigen(mesh.point(v));
  d.centroid = (d.corners[0] + d.corners[1] + d.corners[2]) / 3.0;
  const Vec3 n = (d.corners[1] - d.corners[0]).cross(d.corners[2] - d.corners[0]);
  d.area = 0.5 * n.norm();
  d.normal = d.area > 0.0 ? Vec3(n.normalized()) : Vec3::Zero();
  return d;
}

// Each face's data written by its own iteration.
std::vector<FaceData> face_data(const Mesh& mesh, int threads) {
  std::vector<FaceData> faces(mesh.n_faces());
  parallel_for(faces.size(), threads, [&](std::size_t i) { faces[i] = data_of(mesh, Mesh::FaceHandle(static_cast<int>(i))); });
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

// Is face f, with data `a`, in contact (contact_faces' definition)? Writes
// its gap's midpoint when so. With `behind`, the other face lies behind f
// (the model is thin there, thin_faces) instead of in front of it.
// `partner(id)`: the face index and data of a grid entry.
template <class Partner>
bool face_in_contact(const Mesh& mesh, const FaceData& a, const FaceGrid& grid, int f, double distance, Vec3* gap,
                     bool behind, Partner&& partner) {
  if (a.area == 0.0) return false;
  const Vec3 reach = Vec3::Constant(distance);
  std::unordered_set<int> near;
  return grid.any_near(a.centroid - reach, a.centroid + reach, [&](int id) {
    const auto [g, b] = partner(id);
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
    contact[i] = face_in_contact(mesh, faces[i], grid, static_cast<int>(i), distance, gaps ? &(*gaps)[i] : nullptr,
                                 behind, [&](int g) { return std::pair<int, const FaceData&>(g, faces[static_cast<std::size_t>(g)]); });
  });
  return contact;
}

// Flagged faces at most one in this many: contact_faces looks only at the
// faces near them.
constexpr std::size_t kFewFlagged = 16;

// contact_faces for a few flagged faces: a face can be in contact only with
// faces whose box meets the box `distance` around its centroid (the distance
// to a triangle is at least the distance to its box), so only those faces
// are registered and have their data computed; each flagged face's yes or
// no is the same as over every face. (Local refinement asks this for a few
// hundred faces of the CT series' 837,000 each round; the face data and grid
// of every face took half a second a round.)
std::vector<char> few_faces_in_contact(const Mesh& mesh, const std::vector<int>& flagged, double distance,
                                       int threads) {
  const std::size_t n = mesh.n_faces();
  std::vector<char> contact(n, 0);
  const Vec3 reach = Vec3::Constant(distance);
  std::vector<FaceData> mine(flagged.size());
  FaceGrid queries;  // the boxes around the flagged faces' centroids, by their place in `flagged`
  queries.reset(2.0 * distance, 0.0);
  for (std::size_t k = 0; k < flagged.size(); ++k) {
    mine[k] = data_of(mesh, Mesh::FaceHandle(flagged[k]));
    if (mine[k].area > 0.0) queries.insert_box(static_cast<int>(k), mine[k].centroid - reach, mine[k].centroid + reach);
  }
  std::vector<char> near(n, 0);
  parallel_for(n, threads, [&](std::size_t i) {
    const Mesh::FaceHandle f(static_cast<int>(i));
    if (face_is_deleted(mesh, f)) return;
    Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (auto v : mesh.fv_range(f)) {
      lo = lo.cwiseMin(to_eigen(mesh.point(v)));
      hi = hi.cwiseMax(to_eigen(mesh.point(v)));
    }
    near[i] = queries.any_near(lo, hi, [](int) { return true; });
  });
  // The faces near them, registered by their place in `partners`.
  std::vector<int> partners;
  std::vector<FaceData> data;
  double longest = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!near[i]) continue;
    partners.push_back(static_cast<int>(i));
    data.push_back(data_of(mesh, Mesh::FaceHandle(static_cast<int>(i))));
    for (const Vec3& c : data.back().corners) longest = std::max(longest, (c - data.back().centroid).norm());
  }
  FaceGrid grid;
  grid.reset(std::max(distance, longest), 0.0);
  for (std::size_t k = 0; k < data.size(); ++k) {
    const Triangle& t = data[k].corners;
    grid.insert_box(static_cast<int>(k), t[0].cwiseMin(t[1]).cwiseMin(t[2]), t[0].cwiseMax(t[1]).cwiseMax(t[2]));
  }
  parallel_for(flagged.size(), threads, [&](std::size_t k) {
    const int f = flagged[k];
    contact[static_cast<std::size_t>(f)] = face_in_contact(mesh, mine[k], grid, f, distance, nullptr, false, [&](int id) {
      return std::pair<int, const FaceData&>(partners[static_cast<std::size_t>(id)], data[static_cast<std::size_t>(id)]);
    });
  });
  return contact;
}

}  // namespace

std::vector<char> contact_faces(const Mesh& mesh, double distance, std::vector<Vec3>* gaps, int threads,
                                const std::vector<char>* only) {
  if (only && !gaps && mesh.n_faces() > 0 && distance > 0.0) {
    std::vector<int> flagged;
    for (std::size_t i = 0; i < only->size() && i < mesh.n_faces(); ++i)
      if ((*only)[i]) flagged.push_back(static_cast<int>(i));
    if (flagged.size() * kFewFlagged <= mesh.n_faces()) return few_faces_in_contact(mesh, flagged, distance, threads);
  }
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
    if (region.across_object) {
      report.seam_faces += region.faces;
      report.seam_area += region.area;
    }
  }
  std::stable_sort(report.regions.begin(), report.regions.end(),
                   [](const ContactRegion& a, const ContactRegion& b) { return a.area > b.area; });
  return report;
}

bool seams_worth_a_voxel_seed(const ContactReport& report, double model_area) {
  return model_area > 0.0 && report.seam_area > kSeamShareWorthAVoxelSeed * model_area;
}

std::vector<std::string> describe_contacts(const ContactReport& report, std::size_t limit, double model_area) {
  std::vector<std::string> lines;
  if (report.regions.empty()) return lines;
  // The seams' share of the model, in whole percent (or "under 1 %").
  std::string share;
  if (model_area > 0.0) {
    const double percent = 100.0 * report.seam_area / model_area;
    share = percent < 1.0 && report.seam_area > 0.0 ? ", under 1 % of the model's area"
                                                     : ", " + format_number(std::round(percent), 3) + " % of the model's area";
  }
  lines.push_back("the model meets itself in " + std::to_string(report.regions.size()) + " region(s), " +
                  format_number(report.area, 4) + " mm^2 of faces closer than a voxel to another part of the surface; " +
                  format_number(report.seam_area, 4) + " mm^2 of them (" + std::to_string(report.seam_faces) +
                  " faces" + share + ") are seams across the object, where the surface is not the object's:");
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
