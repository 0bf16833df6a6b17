#include "gdm/face_budget.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <queue>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "gdm/error_lod.h"
#include "gdm/parallel.h"

namespace gdm {

namespace {

using Quadric = Eigen::Matrix4d;

// Candidates taken at once (Reducer::round), their checks on the threads: a
// larger batch spreads the threads' start over more checks, but looks
// deeper into the queue for regions apart, taking collapses further from
// least error first.
constexpr std::size_t kBatch = 64;
// How deep gather_batch looks for them, in batches.
constexpr std::size_t kBatchLook = 16;

Vec3 pos(const Mesh& mesh, Mesh::VertexHandle v) { return to_eigen(mesh.point(v)); }

// The plane of the triangle abc as a quadric weighted by its area: p^T Q p is
// the area times the squared distance of p from the plane (Garland and
// Heckbert's error, here of the fitted surface).
Quadric face_quadric(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = (b - a).cross(c - a);
  const double twice_area = n.norm();
  if (!(twice_area > 0.0)) return Quadric::Zero();
  const Vec3 u = n / twice_area;
  const Eigen::Vector4d plane(u.x(), u.y(), u.z(), -u.dot(a));
  return (0.5 * twice_area) * plane * plane.transpose();
}

double quadric_error(const Quadric& q, const Vec3& p) {
  const Eigen::Vector4d h(p.x(), p.y(), p.z(), 1.0);
  return h.dot(q * h);
}

// Where the merged vertex of edge ab goes: the point of least error, the one
// nearest the edge's midpoint when several are (a flat or cylindrical
// neighbourhood: the quadric's small eigenvalues are dropped), kept within
// half the edge's length of the midpoint.
Vec3 best_position(const Quadric& q, const Vec3& a, const Vec3& b) {
  const Vec3 m = 0.5 * (a + b);
  const Eigen::Matrix3d A = q.topLeftCorner<3, 3>();
  const Vec3 g = A * m + q.topRightCorner<3, 1>();  // half the gradient at m
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(A);
  const double largest = eig.eigenvalues().cwiseAbs().maxCoeff();
  if (!(largest > 0.0)) return m;
  Vec3 step = Vec3::Zero();
  for (int i = 0; i < 3; ++i) {
    const double l = eig.eigenvalues()[i];
    if (l > 1e-3 * largest) step -= (eig.eigenvectors().col(i).dot(g) / l) * eig.eigenvectors().col(i);
  }
  const double limit = 0.5 * (b - a).norm();
  if (step.norm() > limit) step *= limit / step.norm();
  return m + step;
}

// A candidate collapse: halfedge `h` (from -> to; the kept vertex moves to
// `target` when positions are chosen), with the stamps its vertices had when
// the error was computed (a later collapse into either makes the entry
// stale; a fresh one is queued then).
struct Candidate {
  double error;
  double length;
  int h;
  int from, to;
  unsigned from_stamp, to_stamp;
  Vec3 target;
};

// The queue's entry: a candidate's rank and its slot in the reducer's pool.
// The heap moves these 24 bytes instead of the candidate's 72 (its sift-downs
// were most of gather_batch on the T1 head's voxel seed, issue 17); the
// comparisons are the same, so are the pops.
struct Ranked {
  double error;
  double length;
  int h;
  std::uint32_t slot;
  // Least error first, ties by halfedge index: a fixed order.
  bool operator>(const Ranked& o) const {
    if (error != o.error) return error > o.error;
    return length != o.length ? length > o.length : h > o.h;
  }
};

class Reducer {
 public:
  Reducer(Mesh& mesh, const ReduceOptions& o) : mesh_(mesh), o_(o) {
    quadric_.assign(mesh.n_vertices(), Quadric::Zero());
    area_.assign(mesh.n_vertices(), 0.0);
    stamp_.assign(mesh.n_vertices(), 0u);
    for (auto f : mesh.faces()) {
      auto it = mesh.cfv_iter(f);
      const auto a = *it, b = *++it, c = *++it;
      const Quadric q = face_quadric(pos(mesh, a), pos(mesh, b), pos(mesh, c));
      const double area = 0.5 * (pos(mesh, b) - pos(mesh, a)).cross(pos(mesh, c) - pos(mesh, a)).norm();
      for (auto v : {a, b, c}) {
        quadric_[v.idx()] += q;
        area_[v.idx()] += area;
      }
    }
    faces_ = mesh.n_faces();
  }

  ReduceResult run() {
    ReduceResult r;
    // Rounds: a collapse refused once may become possible after its
    // neighbours changed; when a round ends short of the target, the quality
    // floor is halved, then dropped (the guarantees stay).
    const double floors[] = {o_.min_angle, o_.min_angle, 0.5 * o_.min_angle, 0.0};
    for (const double floor : floors) {
      if (faces_ <= o_.faces || (o_.keep_floor && floor < o_.min_angle)) break;
      const std::size_t made = round(floor);
      r.collapses += made;
      if (made == 0 && floor == 0.0) break;
    }
    r.faces = faces_;
    return r;
  }

 private:
  void queue_halfedge(Mesh::HalfedgeHandle h) {
    const auto from = mesh_.from_vertex_handle(h), to = mesh_.to_vertex_handle(h);
    const Quadric q = quadric_[from.idx()] + quadric_[to.idx()];
    const Vec3 target = o_.move_vertices ? best_position(q, pos(mesh_, from), pos(mesh_, to)) : pos(mesh_, to);
    // What the image noise explains is no error: there the shortest edges go
    // first (faces stay even where the surface is flat within the noise).
    const double allowance = (area_[from.idx()] + area_[to.idx()]) * o_.noise * o_.noise;
    const double error = std::max(0.0, quadric_error(q, target) - allowance);
    push({error, mesh_.calc_edge_length(h), h.idx(), from.idx(), to.idx(), stamp_[from.idx()], stamp_[to.idx()],
          target});
  }

  // Every edge at v: both halfedges, or (vertices moved to the best
  // position, where the direction only names the kept vertex) one.
  void queue_around(Mesh::VertexHandle v) {
    for (auto h : mesh_.voh_range(v)) {
      queue_halfedge(h);
      if (!o_.move_vertices) queue_halfedge(mesh_.opposite_halfedge_handle(h));
    }
  }

  bool stale(const Candidate& c) const {
    const Mesh::HalfedgeHandle h(c.h);
    if (mesh_.status(mesh_.edge_handle(h)).deleted()) return true;
    if (mesh_.from_vertex_handle(h).idx() != c.from || mesh_.to_vertex_handle(h).idx() != c.to) return true;
    return stamp_[c.from] != c.from_stamp || stamp_[c.to] != c.to_stamp;
  }

  double mean_edge_length() const {
    double length = 0.0;
    std::size_t edges = 0;
    for (auto e : mesh_.edges())
      if (!mesh_.status(e).deleted()) {
        length += mesh_.calc_edge_length(e);
        ++edges;
      }
    return length / static_cast<double>(std::max<std::size_t>(1, edges));
  }

  // What a collapse reads and changes lies in the box of both ends' rings
  // and the target: its moved faces, the faces the grid offers against
  // them, the faces it deletes and the new ones.
  struct Region {
    Vec3 lo, hi;
    bool meets(const Region& o) const { return !((lo.array() > o.hi.array()).any() || (hi.array() < o.lo.array()).any()); }
  };
  Region region_of(const Candidate& k) const {
    const Mesh::HalfedgeHandle h(k.h);
    Region r{k.target, k.target};
    for (const auto end : {mesh_.from_vertex_handle(h), mesh_.to_vertex_handle(h)})
      for (auto w : mesh_.vv_range(end)) {
        const Vec3 p = pos(mesh_, w);
        r.lo = r.lo.cwiseMin(p);
        r.hi = r.hi.cwiseMax(p);
      }
    return r;
  }

  // The next candidates in the queue's order whose regions meet none taken
  // before them, up to `size` (looking at most kBatchLook deep): none of
  // them changes what another's check reads, nor makes another stale. The
  // candidates passed over go back to the queue for the next batch.
  void gather_batch(std::size_t size, std::vector<Candidate>& batch, std::vector<Region>& region) {
    batch.clear();
    region.clear();
    passed_over_.clear();
    // (Only live candidates count as looked at: the batch does not depend
    // on how many stale entries the queue still holds.)
    for (std::size_t looked = 0; batch.size() < size && !queue_.empty() && looked < kBatchLook * size;) {
      const Candidate top = pop();
      if (stale(top)) continue;
      ++looked;
      const Region r = region_of(top);
      // (Newest first: a candidate passed over mostly meets one taken just before.)
      if (std::any_of(region.rbegin(), region.rend(), [&](const Region& q) { return q.meets(r); })) {
        passed_over_.push_back(top);
        continue;
      }
      batch.push_back(top);
      region.push_back(r);
    }
    for (const Candidate& k : passed_over_) push(k);
  }

  std::size_t round(double floor) {
    CollapseChecker checker(mesh_, 2.0 * mean_edge_length());
    // The grid's cells fit the faces: when half of them are gone (the rest
    // larger), it is built again with cells twice the new mean edge.
    std::size_t faces_at_build = faces_;
    CollapseOptions c;
    c.min_angle = floor;
    c.max_normal_change = o_.max_normal_change;
    queue_ = {};
    pool_.clear();
    free_slots_.clear();
    for (auto h : mesh_.halfedges())
      if (!mesh_.status(mesh_.edge_handle(h)).deleted() && (!o_.move_vertices || h.idx() % 2 == 0)) queue_halfedge(h);
    // The collapses are taken in batches: the queue's next candidates whose
    // regions are apart (gather_batch), each batch in the queue's order;
    // candidates queued by its collapses wait for the next batch (sending
    // the rest of a batch back whenever one came first made nearly every
    // batch one collapse long; taking neighbours together made half the
    // checks stale or out of date before their turn). With several threads
    // the batch's geometric checks (most of the time) run first, at once, on
    // the mesh as it stands: the regions lie apart, so no collapse before a
    // candidate's turn changes what its check read, and the answer is the
    // one its turn would give. The same collapses, in the same order, for
    // any thread count.
    const int threads = o_.move_vertices ? resolve_thread_count(o_.threads) : 1;
    const std::size_t batch_size = o_.move_vertices ? kBatch : 1;
    std::vector<CollapseChecker::Scratch> scratch(static_cast<std::size_t>(threads));
    std::vector<Candidate> batch;
    std::vector<char> answer;
    std::vector<Region> region;
    std::size_t made = 0;
    while (faces_ > o_.faces && !queue_.empty()) {
      if (2 * faces_ < faces_at_build) {
        checker.rebuild(2.0 * mean_edge_length());
        faces_at_build = faces_;
      }
      gather_batch(batch_size, batch, region);
      const bool ahead = threads > 1 && batch.size() > 1;
      if (ahead) {
        answer.assign(batch.size(), 0);
        const auto stride = static_cast<std::size_t>(threads);
        detail::run_tasks(stride, threads, [&](std::size_t w) {
          for (std::size_t i = w; i < batch.size(); i += stride)
            answer[i] = checker.geometry_ok(Mesh::HalfedgeHandle(batch[i].h), c, batch[i].target, scratch[w]);
        });
      }
      for (std::size_t i = 0; i < batch.size() && faces_ > o_.faces; ++i) {
        const Candidate& top = batch[i];
        if (stale(top)) continue;
        Mesh::HalfedgeHandle h(top.h);
        if (o_.move_vertices && !collapse_keeps_topology(mesh_, h)) h = mesh_.opposite_halfedge_handle(h);
        if (!collapse_keeps_topology(mesh_, h)) continue;
        // (With the vertices merged at the target, h and its opposite move
        // the same faces to the same places: the answer holds for either.)
        const bool ok = ahead ? answer[i] != 0
                              : (o_.move_vertices ? checker.geometry_ok(h, c, top.target) : checker.geometry_ok(h, c));
        if (!ok) continue;
        const auto from = mesh_.from_vertex_handle(h), to = mesh_.to_vertex_handle(h);
        quadric_[to.idx()] += quadric_[from.idx()];
        area_[to.idx()] += area_[from.idx()];
        ++stamp_[to.idx()];
        ++stamp_[from.idx()];
        mesh_.collapse(h);
        if (o_.move_vertices) mesh_.set_point(to, to_point(top.target));
        checker.note_vertex(to);
        faces_ -= 2;
        ++made;
        queue_around(to);
      }
    }
    return made;
  }

  Mesh& mesh_;
  const ReduceOptions& o_;
  std::vector<Quadric> quadric_;  // per vertex
  std::vector<double> area_;      // per vertex: the area its quadric stands for, mm^2
  std::vector<unsigned> stamp_;   // per vertex: collapses into (or of) it so far
  std::size_t faces_ = 0;         // faces not deleted
  void push(const Candidate& c) {
    std::uint32_t slot;
    if (free_slots_.empty()) {
      slot = static_cast<std::uint32_t>(pool_.size());
      pool_.push_back(c);
    } else {
      slot = free_slots_.back();
      free_slots_.pop_back();
      pool_[slot] = c;
    }
    queue_.push({c.error, c.length, c.h, slot});
  }
  Candidate pop() {
    const std::uint32_t slot = queue_.top().slot;
    queue_.pop();
    free_slots_.push_back(slot);
    return pool_[slot];
  }

  std::priority_queue<Ranked, std::vector<Ranked>, std::greater<Ranked>> queue_;
  std::vector<Candidate> pool_;            // the queued candidates, by slot
  std::vector<std::uint32_t> free_slots_;  // slots popped, taken again by the next pushes
  std::vector<Candidate> passed_over_;  // gather_batch's scratch
};

}  // namespace

std::vector<double> subdivision_fit_bounds(const Mesh& mesh, int rings, double floor_mm) {
  // Per vertex: the largest sagitta of the edges at it (the edges of the
  // subdivided mesh along a coarse edge turn by the coarse edge's angle; an
  // edge inside a coarse face does not turn).
  std::vector<double> sagitta(mesh.n_vertices(), 0.0);
  for (auto e : mesh.edges()) {
    if (mesh.is_boundary(e)) continue;
    const auto h = mesh.halfedge_handle(e, 0);
    const Vec3 n0 = to_eigen(mesh.calc_face_normal(mesh.face_handle(h)));
    const Vec3 n1 = to_eigen(mesh.calc_face_normal(mesh.face_handle(mesh.opposite_halfedge_handle(h))));
    const double theta = std::acos(std::clamp(n0.dot(n1), -1.0, 1.0));
    const double s = 2.0 * mesh.calc_edge_length(e) * theta / 8.0;
    for (auto v : {mesh.from_vertex_handle(h), mesh.to_vertex_handle(h)})
      sagitta[static_cast<std::size_t>(v.idx())] = std::max(sagitta[static_cast<std::size_t>(v.idx())], s);
  }
  // The largest within `rings` rings (a vertex inside a coarse face lies
  // between coarse edges).
  for (int r = 0; r < rings; ++r) {
    std::vector<double> next = sagitta;
    for (auto v : mesh.vertices())
      for (auto w : mesh.vv_range(v))
        next[static_cast<std::size_t>(v.idx())] = std::max(next[static_cast<std::size_t>(v.idx())], sagitta[static_cast<std::size_t>(w.idx())]);
    sagitta.swap(next);
  }
  for (double& s : sagitta) s += floor_mm;
  return sagitta;
}

ReduceResult reduce_to_faces(Mesh& mesh, const ReduceOptions& options) {
  mesh.request_vertex_status();
  mesh.request_edge_status();
  mesh.request_halfedge_status();
  mesh.request_face_status();
  ReduceResult r;
  if (mesh.n_faces() > options.faces) r = Reducer(mesh, options).run();
  else r.faces = mesh.n_faces();
  mesh.garbage_collection();
  mesh.release_vertex_status();
  mesh.release_edge_status();
  mesh.release_halfedge_status();
  mesh.release_face_status();
  return r;
}

}  // namespace gdm
