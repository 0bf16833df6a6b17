#include "gdm/creases.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>

#include "gdm/intersection_guard.h"
#include "gdm/parallel.h"
#include "gdm/surface_fit.h"

namespace gdm {

namespace {

// The sine of the smallest angle between a corner's third plane's normal and
// the plane of the other two normals.
constexpr double kCornerOutOfPlane = 0.5;

// An edge of the object: a bend of the surface whose radius (the partial
// volume's rounding) is below this many voxels. The crossing that measures
// it must lie within kNoiseMargin standard deviations of the crossings'
// noise less than a smooth bend's would: else no edge is taken.
constexpr double kMaxEdgeRadius = 1.5;
constexpr double kNoiseMargin = 3.0;

// Rounds of finding planes and placing vertices, at most.
constexpr int kRounds = 3;

// A corner is one point: the vertex nearest it may travel twice max_move
// to it (its faces are then checked by the guard like any move's).
constexpr double kCornerReach = 2.0;

// A face as the planes see it: unit normal, area, and where the data crosses
// the threshold along the normal from the centroid.
struct FaceSample {
  Vec3 normal = Vec3::Zero();
  Vec3 crossing = Vec3::Zero();
  double area = 0.0;
  bool valid = false;
};

// n . x = offset, n of unit length.
struct Plane {
  Vec3 normal = Vec3::Zero();
  double offset = 0.0;
  double distance(const Vec3& p) const { return normal.dot(p) - offset; }
};

// The planes around a vertex: none, two (an edge) or three (a corner).
struct LocalPlanes {
  std::vector<Plane> planes;
};

// The point of the line where planes a and b meet nearest p (empty when
// they are nearly parallel).
std::optional<Vec3> nearest_on_line(const Plane& a, const Plane& b, const Vec3& p) {
  const double c = a.normal.dot(b.normal);
  const double det = 1.0 - c * c;
  if (det < 1e-6) return std::nullopt;
  const double ra = -a.distance(p), rb = -b.distance(p);
  const double la = (ra - c * rb) / det, lb = (rb - c * ra) / det;
  return Vec3(p + la * a.normal + lb * b.normal);
}

std::optional<Vec3> common_point(const std::vector<Plane>& planes) {
  Eigen::Matrix3d m;
  Vec3 rhs;
  for (int k = 0; k < 3; ++k) {
    m.row(k) = planes[static_cast<std::size_t>(k)].normal.transpose();
    rhs[k] = planes[static_cast<std::size_t>(k)].offset;
  }
  if (std::abs(m.determinant()) < 0.1) return std::nullopt;  // two of them nearly parallel
  return Vec3(m.inverse() * rhs);
}

class CreaseMaker {
 public:
  CreaseMaker(Mesh& mesh, const Volume& volume, double threshold, const CreaseOptions& o)
      : mesh_(mesh), volume_(volume), threshold_(threshold), o_(o), voxel_(volume.voxel_size()),
        cos_spread_(std::cos(o.plane_spread * M_PI / 180.0)), cos_edge_(std::cos(o.min_angle * M_PI / 180.0)),
        cos_lean_(std::cos(0.5 * o.plane_spread * M_PI / 180.0)),
        cos_half_edge_(std::cos(0.5 * o.min_angle * M_PI / 180.0)) {}

  CreaseResult run() {
    // Each face's sample and each vertex's planes depend on the mesh as
    // given only: computed on the run's threads, the same for any count.
    samples_.resize(mesh_.n_faces());
    parallel_for(mesh_.n_faces(), o_.threads, [&](std::size_t f) { sample_face(Mesh::FaceHandle(static_cast<int>(f))); });
    // Rounds: a vertex placed on an edge or a corner changes the faces
    // around it, and the next round sees the edge's segments next to it
    // (beside a corner, most of all) that the first could not.
    // After the first, a round looks again only at the vertices whose
    // planes can have changed: within the planes' rings (and one more, for
    // an edge's other end) of a vertex the last round moved or added.
    std::vector<char> look(mesh_.n_vertices(), 1);
    for (int round = 0; round < kRounds; ++round) {
      local_.assign(mesh_.n_vertices(), LocalPlanes{});
      parallel_for(mesh_.n_vertices(), o_.threads, [&](std::size_t v) {
        if (look[v]) local_[v] = planes_at(Mesh::VertexHandle(static_cast<int>(v)));
      });
      std::size_t found = 0;
      for (const LocalPlanes& l : local_) found += l.planes.size() >= 2;
      if (round == 0)
        for (const LocalPlanes& l : local_) {
          result_.edge_vertices += l.planes.size() == 2;
          result_.corner_vertices += l.planes.size() == 3;
        }
      if (found == 0) break;
      if (o_.prevent_self_intersection && !guard_)
        guard_ = std::make_unique<IntersectionGuard>(mesh_, 0.05 * voxel_, 1e-6 * voxel_ * voxel_);
      const std::size_t before = result_.corners + result_.edge_moves + result_.splits;
      changed_.clear();
      move_to_corners();
      split_across_edges();
      if (result_.corners + result_.edge_moves + result_.splits == before) break;
      look = near_changes();
    }
    return result_;
  }

  // The vertices within o_.rings + 1 rings of those changed this round.
  std::vector<char> near_changes() const {
    std::vector<char> changed(mesh_.n_vertices(), 0);
    for (int v : changed_) changed[static_cast<std::size_t>(v)] = 1;
    return grow_by_rings(mesh_, std::move(changed), o_.rings + 1);
  }

 private:
  Vec3 point(Mesh::VertexHandle v) const { return to_eigen(mesh_.point(v)); }
  const FaceSample& sample(int f) const { return samples_[static_cast<std::size_t>(f)]; }

  void sample_face(Mesh::FaceHandle f) {
    if (samples_.size() <= static_cast<std::size_t>(f.idx())) samples_.resize(static_cast<std::size_t>(f.idx()) + 1);
    FaceSample& s = samples_[static_cast<std::size_t>(f.idx())];
    auto it = mesh_.cfv_iter(f);
    const Vec3 a = point(*it), b = point(*++it), c = point(*++it);
    const Vec3 n = (b - a).cross(c - a);
    const double len = n.norm();
    s.valid = false;
    if (!(len > 0.0)) return;
    s.normal = n / len;
    s.area = 0.5 * len;
    const Vec3 centroid = (a + b + c) / 3.0;
    const auto d = find_crossing(volume_, threshold_, centroid, s.normal, o_.search * voxel_, 0.25 * voxel_);
    if (!d) return;
    s.crossing = centroid + *d * s.normal;
    s.valid = true;
  }

  // Whether every face's normal lies within half the edge angle of their
  // mean: then no two are the edge angle apart (most vertices; a test in
  // one pass over the faces before the seeds' pairs).
  bool all_within_half_an_edge_angle(const std::vector<FaceSample>& faces) const {
    Vec3 mean = Vec3::Zero();
    for (const FaceSample& f : faces) mean += f.normal;
    if (!(mean.norm() > 0.0)) return false;
    mean.normalize();
    for (const FaceSample& f : faces)
      if (f.normal.dot(mean) < cos_half_edge_) return false;
    return true;
  }

  // Each face's support: the sum of the areas of the faces whose normals
  // lie within the spread of its own (itself included), in face order.
  // Branch-free (issue 17): near an edge about half the pairs agree, and
  // a branch per pair mispredicted that often. The pairs' agreement first
  // (1.0 or 0.0, each dot product summed as Eigen's Vec3::dot sums it),
  // then every sum in face order, a disagreeing face adding 0.0: the same
  // sums, bit for bit, as adding only the agreeing faces' areas. More
  // instructions (the cube of gdm_core_benchmark: 2.21 -> 2.26 G), less
  // time (its fit stage, runs interleaved: 202-209 -> 192-198 ms).
  void face_supports(const std::vector<FaceSample>& faces, std::vector<double>& support) const {
    const std::size_t count = faces.size();
    thread_local std::vector<double> nx, ny, nz, area;
    thread_local std::vector<double> agree;  // count x count: 1.0 where the pair agrees, 0.0 where not
    nx.resize(count);
    ny.resize(count);
    nz.resize(count);
    area.resize(count);
    for (std::size_t i = 0; i < count; ++i) {
      nx[i] = faces[i].normal[0];
      ny[i] = faces[i].normal[1];
      nz[i] = faces[i].normal[2];
      area[i] = faces[i].area;
    }
    agree.resize(count * count);
    for (std::size_t i = 0; i < count; ++i) {
      double* row = agree.data() + i * count;
      const double x = nx[i], y = ny[i], z = nz[i];
      row[i] = 1.0;
      for (std::size_t j = i + 1; j < count; ++j) row[j] = (x * nx[j] + y * ny[j]) + z * nz[j] >= cos_spread_ ? 1.0 : 0.0;
      for (std::size_t j = i + 1; j < count; ++j) agree[j * count + i] = row[j];
    }
    // Face j's area added to every support at once: each sum still in face order.
    support.assign(count, 0.0);
    for (std::size_t j = 0; j < count; ++j) {
      const double a = area[j];
      const double* row = agree.data() + j * count;
      for (std::size_t k = 0; k < count; ++k) support[k] += row[k] * a;
    }
  }

  // Seeds: the normal most of the faces' area agrees with (within the
  // spread), then the one most agree with among the faces at least the edge
  // angle from it, then one at least that far from both (a corner).
  std::vector<Vec3> seed_normals(const std::vector<FaceSample>& faces) const {
    // Each face's support (the area of the faces within the spread of its
    // normal) once; a seed is the best supported face apart from the seeds.
    thread_local std::vector<double> support;
    face_supports(faces, support);
    std::vector<Vec3> seeds;
    for (int k = 0; k < 3; ++k) {
      double best = 0.0;
      int seed = -1;  // index into faces
      Vec3 out_of_plane = Vec3::Zero();
      if (seeds.size() == 2) out_of_plane = seeds[0].cross(seeds[1]).normalized();
      for (std::size_t i = 0; i < faces.size(); ++i) {
        if (support[i] <= best) continue;
        const Vec3& n = faces[i].normal;
        bool apart = true;
        for (const Vec3& s : seeds) apart = apart && n.dot(s) < cos_edge_;
        // A corner's third normal stands out of the other two's plane; a
        // face across the edge between two planes has its normal in it.
        if (seeds.size() == 2) apart = apart && std::abs(n.dot(out_of_plane)) >= kCornerOutOfPlane;
        if (!apart) continue;
        best = support[i];
        seed = static_cast<int>(i);
      }
      if (seed < 0) break;
      seeds.push_back(faces[static_cast<std::size_t>(seed)].normal);
    }
    return seeds;
  }

  LocalPlanes planes_at(Mesh::VertexHandle v) const {
    // The valid samples of the faces around, copied side by side (in face
    // order) for the loops below, which visit each many times.
    thread_local std::vector<int> near, around;
    thread_local std::vector<FaceSample> faces;
    vertices_within(mesh_, v, o_.rings, near);
    faces_around(mesh_, near, around);
    faces.clear();
    for (int f : around)
      if (sample(f).valid) faces.push_back(sample(f));
    if (faces.size() < 4 || all_within_half_an_edge_angle(faces)) return {};
    std::vector<Vec3> normals = seed_normals(faces);
    if (normals.size() < 2) return {};
    // Members by angle to each normal; each normal then the area-weighted
    // mean of its members', twice. A third group needs two faces of its
    // own, else its seed was a face across the edge.
    thread_local std::vector<int> member;
    member.assign(faces.size(), -1);
    for (int round = 0; round < 2; ++round) {
      for (std::size_t i = 0; i < faces.size(); ++i) {
        member[i] = -1;
        double best = cos_spread_;
        for (std::size_t k = 0; k < normals.size(); ++k) {
          const double c = faces[i].normal.dot(normals[k]);
          if (c >= best) {
            best = c;
            member[i] = static_cast<int>(k);
          }
        }
      }
      if (normals.size() == 3 && std::count(member.begin(), member.end(), 2) < 2) {
        normals.pop_back();
        --round;
        continue;
      }
      for (std::size_t k = 0; k < normals.size(); ++k) {
        Vec3 sum = Vec3::Zero();
        for (std::size_t i = 0; i < faces.size(); ++i)
          if (member[i] == static_cast<int>(k)) sum += faces[i].area * faces[i].normal;
        if (!(sum.norm() > 0.0)) return {};
        normals[k] = sum.normalized();
      }
    }
    // Each plane: two faces at least, through the area-weighted mean of its
    // faces' crossings, every crossing within the flatness.
    LocalPlanes out;
    for (std::size_t k = 0; k < normals.size(); ++k) {
      double sum = 0.0, w = 0.0;
      int count = 0;
      for (std::size_t i = 0; i < faces.size(); ++i)
        if (member[i] == static_cast<int>(k)) {
          sum += faces[i].area * normals[k].dot(faces[i].crossing);
          w += faces[i].area;
          ++count;
        }
      if (count < 2) return {};
      const Plane plane = fit_plane(faces, member, static_cast<int>(k), Plane{normals[k], sum / w});
      for (std::size_t i = 0; i < faces.size(); ++i)
        if (member[i] == static_cast<int>(k) && std::abs(plane.distance(faces[i].crossing)) > o_.flatness * voxel_)
          return {};
      out.planes.push_back(plane);
    }
    if (!bends_sharply(out.planes, point(v))) return {};
    return out;
  }

  // Whether the surface turns from one plane to the other (or the others)
  // within kMaxEdgeRadius of where they meet: the data crosses the threshold
  // along the planes' mean normal from their common line (or point) within
  // r (1 / cos(a) - 1), a the angle from that normal to each plane's, as a
  // ball of radius r rolled into the edge leaves it. A bend of a smooth
  // surface (a tube a few voxels across, whose faces on either side also
  // fall into flat-looking groups at a fine level of detail) lies farther
  // from where its tangent planes meet, and is no edge.
  bool bends_sharply(const std::vector<Plane>& planes, const Vec3& p) const {
    std::optional<Vec3> apex;
    Vec3 mean = Vec3::Zero();
    for (const Plane& q : planes) mean += q.normal;
    if (!(mean.norm() > 0.0)) return false;
    mean.normalize();
    if (planes.size() == 3)
      apex = common_point(planes);
    else
      apex = nearest_on_line(planes[0], planes[1], p);
    if (!apex) return false;
    const double cos_a = mean.dot(planes[0].normal);
    if (!(cos_a > 0.0)) return false;
    const double allowed = kMaxEdgeRadius * (1.0 / cos_a - 1.0) * voxel_;
    // A test noise could pass by chance tells nothing.
    if (allowed < kNoiseMargin * o_.noise) return false;
    const auto within = [&](const Vec3& at, const Vec3& normal, double reach) {
      return find_crossing(volume_, threshold_, at, normal, reach, 0.25 * voxel_).has_value();
    };
    if (planes.size() == 2) {
      // At the point nearest p and a voxel either side of it along the edge.
      const Vec3 along = planes[0].normal.cross(planes[1].normal).normalized() * voxel_;
      return within(*apex, mean, allowed) && within(*apex - along, mean, allowed) && within(*apex + along, mean, allowed);
    }
    if (!within(*apex, mean, allowed)) return false;
    // A corner: and a voxel along each of its three edges (each leaves the
    // corner on one side only: convex, concave or a saddle).
    for (std::size_t k = 0; k < 3; ++k) {
      const Plane &a = planes[(k + 1) % 3], &b = planes[(k + 2) % 3];
      const Vec3 along = a.normal.cross(b.normal).normalized() * voxel_;
      const Vec3 bisector = (a.normal + b.normal).normalized();
      const double reach = kMaxEdgeRadius * (1.0 / bisector.dot(a.normal) - 1.0) * voxel_;
      if (reach < kNoiseMargin * o_.noise ||
          !(within(*apex + along, bisector, reach) || within(*apex - along, bisector, reach)))
        return false;
    }
    return true;
  }

  // The plane through the crossings of the faces of group k, by least
  // squares (area-weighted): the faces' own normals lean a few degrees
  // where the fit's faces cross the rounded surface, and a lean of 3
  // degrees over the two rings puts the edge 0.15 voxel off. The faces'
  // mean plane (`guess`) when the crossings lie on a line.
  Plane fit_plane(const std::vector<FaceSample>& faces, const std::vector<int>& member, int k, const Plane& guess) const {
    Vec3 centre = Vec3::Zero();
    double w = 0.0;
    for (std::size_t i = 0; i < faces.size(); ++i)
      if (member[i] == k) {
        centre += faces[i].area * faces[i].crossing;
        w += faces[i].area;
      }
    centre /= w;
    Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < faces.size(); ++i)
      if (member[i] == k) {
        const Vec3 d = faces[i].crossing - centre;
        scatter += faces[i].area * d * d.transpose();
      }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(scatter);
    // Spread in two directions (not a line of crossings): the smallest
    // eigenvector is the normal.
    if (eig.info() != Eigen::Success || eig.eigenvalues()[1] < 0.05 * eig.eigenvalues()[2]) return guess;
    Vec3 n = eig.eigenvectors().col(0);
    if (n.dot(guess.normal) < 0.0) n = -n;
    if (n.dot(guess.normal) < cos_lean_) return guess;
    return Plane{n, n.dot(centre)};
  }

  // Moves v to p when it is within `reach` and the guard allows it (no face
  // turned over or flattened, no intersection).
  bool try_move(Mesh::VertexHandle v, const Vec3& p, double reach) {
    const double travel = (p - point(v)).norm();
    if (travel > reach || !volume_.contains(p)) return false;
    if (guard_ && !guard_->move_is_safe(v, p)) {
      ++result_.refused;
      return false;
    }
    mesh_.set_point(v, to_point(p));
    changed_.push_back(v.idx());
    for (auto f : mesh_.vf_range(v)) {
      sample_face(f);
      if (guard_) guard_->note_face(f);
    }
    return true;
  }

  // Each corner once: of the vertices whose three planes meet at the same
  // point (within half a voxel), the nearest moves there.
  void move_to_corners() {
    struct Candidate {
      double travel;
      int vertex;
      Vec3 corner;
    };
    std::vector<Candidate> candidates;
    for (auto v : mesh_.vertices()) {
      const LocalPlanes& l = local_[static_cast<std::size_t>(v.idx())];
      if (l.planes.size() != 3) continue;
      if (const auto c = common_point(l.planes)) candidates.push_back({(*c - point(v)).norm(), v.idx(), *c});
    }
    std::sort(candidates.begin(), candidates.end(),
              [](const Candidate& a, const Candidate& b) { return a.travel != b.travel ? a.travel < b.travel : a.vertex < b.vertex; });
    for (const Candidate& c : candidates) {
      const bool known = std::any_of(taken_.begin(), taken_.end(), [&](const Vec3& t) { return (t - c.corner).norm() < 0.5 * voxel_; });
      if (known) continue;
      if (try_move(Mesh::VertexHandle(c.vertex), c.corner, kCornerReach * o_.max_move * voxel_)) {
        taken_.push_back(c.corner);
        on_edge_.resize(mesh_.n_vertices(), 0);
        on_edge_[static_cast<std::size_t>(c.vertex)] = 1;
        ++result_.corners;
      }
    }
  }

  // The plane of `planes` nearest p.
  static int nearest_plane(const std::vector<Plane>& planes, const Vec3& p) {
    int best = 0;
    for (std::size_t k = 1; k < planes.size(); ++k)
      if (std::abs(planes[k].distance(p)) < std::abs(planes[static_cast<std::size_t>(best)].distance(p))) best = static_cast<int>(k);
    return best;
  }

  // Every edge (of the mesh as it was) whose ends lie nearest different
  // planes of an end's planes crosses the line where those planes meet: the
  // nearer end moves onto the line when the crossing is within a fifth of
  // the edge from it, else the edge is split there and the new vertex moves
  // onto the line.
  void split_across_edges() {
    const std::size_t edges = mesh_.n_edges();
    on_edge_.resize(mesh_.n_vertices(), 0);
    const auto gen = generation_property(mesh_);
    for (std::size_t e = 0; e < edges; ++e) {
      const auto h = mesh_.halfedge_handle(Mesh::EdgeHandle(static_cast<int>(e)), 0);
      const Mesh::VertexHandle a = mesh_.from_vertex_handle(h), b = mesh_.to_vertex_handle(h);
      if (on_edge_[static_cast<std::size_t>(a.idx())] || on_edge_[static_cast<std::size_t>(b.idx())]) continue;
      const LocalPlanes& la = local_[static_cast<std::size_t>(a.idx())];
      const LocalPlanes& lb = local_[static_cast<std::size_t>(b.idx())];
      const std::vector<Plane>& planes = la.planes.size() >= lb.planes.size() ? la.planes : lb.planes;
      if (planes.size() < 2) continue;
      const Vec3 pa = point(a), pb = point(b);
      const int ia = nearest_plane(planes, pa), ib = nearest_plane(planes, pb);
      if (ia == ib) continue;
      const Plane &A = planes[static_cast<std::size_t>(ia)], &B = planes[static_cast<std::size_t>(ib)];
      // Where the edge is as near one plane as the other.
      const double ha = std::abs(A.distance(pa)) - std::abs(B.distance(pa));
      const double hb = std::abs(A.distance(pb)) - std::abs(B.distance(pb));
      if (!(ha < 0.0 && hb > 0.0)) continue;
      const double t = ha / (ha - hb);
      const Vec3 m = pa + t * (pb - pa);
      if (t < 0.2 || t > 0.8) {
        const Mesh::VertexHandle end = t < 0.5 ? a : b;
        const auto on = nearest_on_line(A, B, point(end));
        if (on && try_move(end, *on, o_.max_move * voxel_)) {
          on_edge_[static_cast<std::size_t>(end.idx())] = 1;
          ++result_.edge_moves;
        }
        continue;
      }
      const auto on = nearest_on_line(A, B, m);
      if (!on || (*on - m).norm() > o_.max_move * voxel_) continue;
      const Mesh::VertexHandle mid = mesh_.add_vertex(to_point(m));
      mesh_.split(Mesh::EdgeHandle(static_cast<int>(e)), mid);
      mesh_.property(gen, mid) = o_.generation;
      on_edge_.resize(mesh_.n_vertices(), 0);
      local_.resize(mesh_.n_vertices());
      for (auto f : mesh_.vf_range(mid)) sample_face(f);
      changed_.push_back(mid.idx());
      if (guard_) guard_->note_new_faces();
      ++result_.splits;
      if (try_move(mid, *on, o_.max_move * voxel_)) {
        on_edge_[static_cast<std::size_t>(mid.idx())] = 1;
        ++result_.edge_moves;
      }
    }
  }

  Mesh& mesh_;
  const Volume& volume_;
  double threshold_;
  const CreaseOptions& o_;
  double voxel_;
  double cos_spread_, cos_edge_;
  double cos_lean_;       // the crossings' plane leans at most half the spread from its faces' mean normal
  double cos_half_edge_;  // half the edge angle: faces all this close to their mean normal make no edge
  std::vector<FaceSample> samples_;
  std::vector<LocalPlanes> local_;
  std::vector<char> on_edge_;  // vertices placed on an edge or a corner
  std::vector<Vec3> taken_;     // corners a vertex was placed on
  std::vector<int> changed_;    // vertices moved or added this round
  std::unique_ptr<IntersectionGuard> guard_;
  CreaseResult result_;
};

}  // namespace

CreaseResult sharpen_creases(Mesh& mesh, const Volume& volume, double threshold, const CreaseOptions& options) {
  return CreaseMaker(mesh, volume, threshold, options).run();
}

}  // namespace gdm
