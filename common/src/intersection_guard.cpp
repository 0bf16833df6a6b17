#include "gdm/intersection_guard.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "gdm/mesh_checks.h"
#include "gdm/parallel.h"
#include "gdm/predicates.h"

namespace gdm {

// ---- IntersectionGuard ----------------------------------------------------

IntersectionGuard::IntersectionGuard(const Mesh& mesh, double margin, double min_face_area)
    : mesh_(&mesh), margin_(margin), min_face_area_(min_face_area) {
  rebuild();
}

void IntersectionGuard::rebuild() {
  const double cell = std::max(2.0 * (mesh_->n_edges() ? mean_edge_length(*mesh_) : 1.0), 4.0 * margin_);
  grid_.rebuild(*mesh_, cell > 0.0 ? cell : 1.0, margin_);
  moved_vertices_.clear();
  flipped_faces_.clear();
}

void IntersectionGuard::renumber_faces(const std::vector<int>& to) {
  grid_.renumber(to, mesh_->n_faces());
  moved_vertices_.clear();
  flipped_faces_.clear();
}

void IntersectionGuard::prepare_moves() {
  // Only faces whose box grew are registered again, with the same margin as
  // a rebuild: the grid offers the exact tests every face a rebuild would
  // (and a face that shrank in place, with its larger box, perhaps more),
  // and each decision is a yes/no over all of them. Every other face kept
  // its box since it was last registered or looked at.
  std::vector<int>& faces = changed_faces_;
  faces.clear();
  if (moved_vertices_.size() + flipped_faces_.size() < mesh_->n_faces()) {
    // Each face once (a face flag instead of sorting every face of every
    // move with its repeats: most of this function's time on the T1 head),
    // in ascending order: by a pass over the flags when many are listed.
    face_listed_.resize(mesh_->n_faces(), 0);
    for (int v : moved_vertices_)
      for (auto f : mesh_->vf_range(Mesh::VertexHandle(v))) list_once(f.idx(), faces, face_listed_);
    for (int f : flipped_faces_) list_once(f, faces, face_listed_);
    sort_listed(faces, face_listed_);
    moved_vertices_.clear();
    flipped_faces_.clear();
    if (!grid_.refresh(*mesh_, margin_, faces)) rebuild();
    return;
  }
  moved_vertices_.clear();
  flipped_faces_.clear();
  if (!grid_.refresh(*mesh_, margin_)) rebuild();
}

IntersectionGuard::Triangle IntersectionGuard::face_triangle(int face, int moved_vertex,
                                                             const Vec3& moved_to) const {
  Triangle t;
  auto h = mesh_->halfedge_handle(Mesh::FaceHandle(face));
  for (int i = 0; i < 3; ++i, h = mesh_->next_halfedge_handle(h)) {
    const auto v = mesh_->to_vertex_handle(h);
    t.id[i] = v.idx();
    t.p[i] = v.idx() == moved_vertex ? moved_to : to_eigen(mesh_->point(v));
  }
  return t;
}

bool IntersectionGuard::triangle_is_clear(const Triangle& t, const std::vector<int>& ignore_faces,
                                          int moved_vertex, const Vec3& moved_to, int& blocking) {
  const Vec3 lo = t.p[0].cwiseMin(t.p[1]).cwiseMin(t.p[2]);
  const Vec3 hi = t.p[0].cwiseMax(t.p[1]).cwiseMax(t.p[2]);
  bool clear = true;
  grid_.for_each_near(lo, hi, [&](int g) {
    if (!clear || std::find(ignore_faces.begin(), ignore_faces.end(), g) != ignore_faces.end()) return;
    const Triangle other = face_triangle(g, moved_vertex, moved_to);
    const Vec3 olo = other.p[0].cwiseMin(other.p[1]).cwiseMin(other.p[2]);
    const Vec3 ohi = other.p[0].cwiseMax(other.p[1]).cwiseMax(other.p[2]);
    if ((olo.array() > hi.array()).any() || (ohi.array() < lo.array()).any()) return;
    if (triangles_intersect_improperly(t.p, t.id, other.p, other.id)) {
      clear = false;
      blocking = g;
    }
  });
  return clear;
}

bool IntersectionGuard::move_is_safe(Mesh::VertexHandle v, const Vec3& p, int hint) {
  const bool safe = move_is_safe(v, p, hint, own_);
  last_blocking_face_ = own_.last_blocking_face;
  absorb(own_);
  return safe;
}

void IntersectionGuard::absorb(Checker& checker) {
  stats_.rejected_moves += checker.rejected;
  checker.rejected = 0;
  for (int v : checker.moved)
    if (moved_vertices_.size() <= mesh_->n_faces()) moved_vertices_.push_back(v);  // beyond: prepare_moves() looks at every face
  checker.moved.clear();
}

bool IntersectionGuard::move_is_safe(Mesh::VertexHandle v, const Vec3& p, int hint, Checker& checker) const {
  std::vector<int>& ring_faces = checker.ring_faces;
  ring_faces.clear();
  for (auto f : mesh_->vf_range(v)) ring_faces.push_back(f.idx());
  // One grid query for the whole moved fan: every candidate face is built
  // once and tested against each fan face whose box it meets. Pairs within
  // the fan are checked too (their shared vertex is known to the predicate),
  // so a fan cannot fold over itself.
  // Each triangle with its normal, computed once for all the pairs it is in.
  std::vector<FilteredTriangle>& fan = checker.fan;
  fan.clear();
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  std::vector<std::pair<Vec3, Vec3>>& boxes = checker.boxes;
  boxes.clear();
  for (int f : ring_faces) {
    const Triangle before = face_triangle(f, -1, p);
    Triangle after = before;
    for (int k = 0; k < 3; ++k)
      if (after.id[k] == v.idx()) after.p[k] = p;
    const Vec3 n_before = before.normal();
    const Vec3 n_after = after.normal();
    if (0.5 * n_after.norm() < min_face_area_ || n_after.dot(n_before) <= 0.0) {
      ++checker.rejected;
      checker.last_blocking_face = -1;
      return false;
    }
    fan.emplace_back(after.p, after.id);
    boxes.emplace_back(after.p[0].cwiseMin(after.p[1]).cwiseMin(after.p[2]),
                       after.p[0].cwiseMax(after.p[1]).cwiseMax(after.p[2]));
    lo = lo.cwiseMin(boxes.back().first);
    hi = hi.cwiseMax(boxes.back().second);
  }
  // Whether face g cuts the moved fan. A fan face is tested against the fan
  // faces before it only: each pair within the fan once (the predicate's
  // answer does not depend on the order). The predicate's scale: the extent
  // of the box around both triangles.
  // A face outside the fan lies in the box it is registered with (the
  // moves keep it so): when that box meets no fan face's box, neither does
  // g, and g is not built (nor are its vertices read: a check reads only
  // what lies within reach()).
  // `registered`: g is in the grid (every face is, but for faces split off
  // since the last registration).
  const auto cuts_fan = [&](int g, bool registered) {
    const auto end = static_cast<std::size_t>(std::find(ring_faces.begin(), ring_faces.end(), g) - ring_faces.begin());
    if (registered && end == ring_faces.size()) {
      bool near = false;
      for (std::size_t i = 0; i < end && !near; ++i) near = grid_.box_meets(g, boxes[i].first, boxes[i].second);
      if (!near) return false;
    }
    const Triangle t = face_triangle(g, v.idx(), p);
    const Vec3 olo = t.p[0].cwiseMin(t.p[1]).cwiseMin(t.p[2]);
    const Vec3 ohi = t.p[0].cwiseMax(t.p[1]).cwiseMax(t.p[2]);
    FilteredTriangle other;
    bool built = false;
    for (std::size_t i = 0; i < end; ++i) {
      if ((olo.array() > boxes[i].second.array()).any() || (ohi.array() < boxes[i].first.array()).any()) continue;
      if (!built) {
        other = FilteredTriangle(t.p, t.id);
        built = true;
      }
      const double scale = (ohi.cwiseMax(boxes[i].second) - olo.cwiseMin(boxes[i].first)).maxCoeff();
      if (triangles_intersect_improperly(fan[i], other, scale)) return true;
    }
    return false;
  };
  // The face that refused this vertex's last move first: a vertex pressed
  // against another part of the model is mostly refused by the same face
  // again, and any face that cuts the fan refuses the move (the grid would
  // offer that face too), so the answer is the one the whole query gives.
  // The first face of the query that cuts the fan refuses the move: the
  // rest are not looked at.
  int blocking = -1;
  if (hint >= 0 && static_cast<std::size_t>(hint) < mesh_->n_faces() &&
      !(mesh_->has_face_status() && mesh_->status(Mesh::FaceHandle(hint)).deleted()) && cuts_fan(hint, grid_.registered(hint)))
    blocking = hint;
  if (blocking < 0) {
    if (++checker.stamp == 0) {
      std::fill(checker.stamps.begin(), checker.stamps.end(), 0);
      checker.stamp = 1;
    }
    grid_.any_near_once(lo, hi, checker.stamps, checker.stamp, [&](int g) {
      if (!cuts_fan(g, true)) return false;
      blocking = g;
      return true;
    });
  }
  if (blocking >= 0) {
    ++checker.rejected;
    checker.last_blocking_face = blocking;
    return false;
  }
  checker.moved.push_back(v.idx());
  return true;
}

int IntersectionGuard::bad_partner(int face, std::vector<std::uint32_t>& stamps, std::uint32_t stamp) const {
  const Triangle t = face_triangle(face, -1, Vec3::Zero());
  const Vec3 n = t.normal();
  if (0.5 * n.norm() < min_face_area_ || n.dot(start_normal_[static_cast<std::size_t>(face)]) <= 0.0) return -2;
  const Vec3 lo = t.p[0].cwiseMin(t.p[1]).cwiseMin(t.p[2]);
  const Vec3 hi = t.p[0].cwiseMax(t.p[1]).cwiseMax(t.p[2]);
  FilteredTriangle mine;
  bool built = false;
  int partner = -1;
  grid_.any_near_once(lo, hi, stamps, stamp, [&](int g) {
    if (g == face || (g < face && in_check_[static_cast<std::size_t>(g)])) return false;
    const Triangle other = face_triangle(g, -1, Vec3::Zero());
    const Vec3 olo = other.p[0].cwiseMin(other.p[1]).cwiseMin(other.p[2]);
    const Vec3 ohi = other.p[0].cwiseMax(other.p[1]).cwiseMax(other.p[2]);
    if ((olo.array() > hi.array()).any() || (ohi.array() < lo.array()).any()) return false;
    if (!built) {
      mine = FilteredTriangle(t.p, t.id);
      built = true;
    }
    const double scale = (ohi.cwiseMax(hi) - olo.cwiseMin(lo)).maxCoeff();
    if (!triangles_intersect_improperly(mine, FilteredTriangle(other.p, other.id), scale)) return false;
    partner = g;
    return true;
  });
  return partner;
}

std::vector<char> IntersectionGuard::apply_moves(Mesh& mesh, const std::vector<Move>& moves, int threads,
                                                 std::vector<int>* blocking) {
  std::vector<char> kept(moves.size(), 1);
  if (blocking) blocking->assign(moves.size(), -1);
  if (moves.empty()) return kept;
  move_of_.resize(mesh.n_vertices(), -1);
  in_check_.resize(mesh.n_faces(), 0);
  start_normal_.resize(mesh.n_faces(), Vec3::Zero());
  normal_known_.resize(mesh.n_faces(), 0);

  // The faces around the moved vertices, with their normals before the moves.
  std::vector<Vec3> start(moves.size());
  std::vector<int> check;
  for (std::size_t k = 0; k < moves.size(); ++k) {
    const Mesh::VertexHandle v(moves[k].vertex);
    move_of_[static_cast<std::size_t>(v.idx())] = static_cast<int>(k);
    start[k] = to_eigen(mesh.point(v));
    for (auto f : mesh.vf_range(v)) check.push_back(f.idx());
  }
  std::sort(check.begin(), check.end());
  check.erase(std::unique(check.begin(), check.end()), check.end());
  // Every face whose shape the moves change is among these; a face that
  // joins a later round for the face it cuts has its first shape still.
  std::vector<int> known;
  const auto note_start_normal = [&](int f) {
    if (normal_known_[static_cast<std::size_t>(f)]) return;
    const Triangle t = face_triangle(f, -1, Vec3::Zero());
    start_normal_[static_cast<std::size_t>(f)] = t.normal();
    normal_known_[static_cast<std::size_t>(f)] = 1;
    known.push_back(f);
  };
  for (int f : check) note_start_normal(f);
  for (const Move& m : moves) mesh.set_point(Mesh::VertexHandle(m.vertex), to_point(m.to));

  // The move of a face's highest-index vertex still moved, -1 if none.
  const auto last_move_of = [&](int face) {
    int best = -1;
    for (auto w : mesh.fv_range(Mesh::FaceHandle(face))) {
      const int k = move_of_[static_cast<std::size_t>(w.idx())];
      if (k >= 0 && kept[static_cast<std::size_t>(k)] &&
          (best < 0 || moves[static_cast<std::size_t>(best)].vertex < w.idx()))
        best = k;
    }
    return best;
  };
  std::vector<int> partner;
  std::vector<int> undo;
  while (!check.empty()) {
    for (int f : check) {
      note_start_normal(f);
      in_check_[static_cast<std::size_t>(f)] = 1;
    }
    partner.assign(check.size(), -1);
    worker_stamps_.resize(static_cast<std::size_t>(std::max(1, threads)));
    parallel_chunks(check.size(), threads, [&](std::size_t begin, std::size_t end, std::size_t worker) {
      WorkerStamps& w = worker_stamps_[worker];
      for (std::size_t i = begin; i < end; ++i) {
        if (++w.last == 0) {
          std::fill(w.marks.begin(), w.marks.end(), 0);
          w.last = 1;
        }
        partner[i] = bad_partner(check[i], w.marks, w.last);
      }
    });
    for (int f : check) in_check_[static_cast<std::size_t>(f)] = 0;
    // Each bad face gives back one move: its own highest-index one, or, when
    // the face it cuts has a higher one, that face's. The lowest such moves
    // go first, and a bad face one of whose moves already goes back this
    // round waits for the next check (that may have mended it): as in a pass
    // in vertex order, a move is refused only beside moves that stand.
    struct Cause {
      int vertex;    // of the move to give back
      int move;      // its index in `moves`
      int cut;       // the face it would cut (-1: its own faces)
      std::size_t i;  // the bad face's index in `check`
    };
    std::vector<Cause> causes;
    std::vector<int> next;
    for (std::size_t i = 0; i < check.size(); ++i) {
      if (partner[i] == -1) continue;
      int k = last_move_of(check[i]);
      int cut = partner[i];
      if (partner[i] >= 0) {
        const int j = last_move_of(partner[i]);
        if (j >= 0 && (k < 0 || moves[static_cast<std::size_t>(j)].vertex > moves[static_cast<std::size_t>(k)].vertex)) {
          k = j;
          cut = check[i];
        }
        next.push_back(partner[i]);
      }
      next.push_back(check[i]);
      if (k >= 0) causes.push_back({moves[static_cast<std::size_t>(k)].vertex, k, std::max(-1, cut), i});
      // k < 0: both faces as before the moves, not the moves' doing
    }
    std::sort(causes.begin(), causes.end(), [](const Cause& a, const Cause& b) {
      return a.vertex != b.vertex ? a.vertex < b.vertex : a.i < b.i;
    });
    undo.clear();
    const auto going_back = [&](int face) {
      if (face < 0) return false;
      for (auto w : mesh.fv_range(Mesh::FaceHandle(face))) {
        const int k = move_of_[static_cast<std::size_t>(w.idx())];
        if (k >= 0 && giving_back_[static_cast<std::size_t>(k)]) return true;
      }
      return false;
    };
    giving_back_.assign(moves.size(), 0);
    for (const Cause& c : causes) {
      if (giving_back_[static_cast<std::size_t>(c.move)] || going_back(check[c.i]) ||
          going_back(partner[c.i] >= 0 ? partner[c.i] : -1))
        continue;
      giving_back_[static_cast<std::size_t>(c.move)] = 1;
      undo.push_back(c.move);
      if (blocking) (*blocking)[static_cast<std::size_t>(c.move)] = c.cut;
    }
    if (undo.empty()) break;
    for (int k : undo) {
      const auto m = static_cast<std::size_t>(k);
      const Mesh::VertexHandle v(moves[m].vertex);
      kept[m] = 0;
      mesh.set_point(v, to_point(start[m]));
      for (auto f : mesh.vf_range(v)) next.push_back(f.idx());
    }
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    check.swap(next);
  }
  // A move sent back for a conflict with moves that then went back
  // themselves, or at a lower priority than needed, may stand alone where
  // the others ended: each tries again, one at a time, in the order given
  // (the sequential pass for the conflicts only). A quarter to a third of
  // the moves sent back stood so in the sub-voxel fit of the tooth pulp's
  // level of detail (measured with the fit on this batch, not kept).
  const std::size_t rejected_before = stats_.rejected_moves;
  for (std::size_t k = 0; k < moves.size(); ++k) {
    if (kept[k]) continue;
    const Mesh::VertexHandle v(moves[k].vertex);
    const Vec3& q = moves[k].to;
    if (!move_is_safe(v, q)) {
      if (blocking) (*blocking)[k] = last_blocking_face_;
      continue;
    }
    // move_is_safe compares with the faces as they are now; the batch's
    // promise is against the faces before the call: no face turned over.
    bool turned = false;
    for (auto f : mesh.vf_range(v)) {
      const Triangle t = face_triangle(f.idx(), v.idx(), q);
      turned = turned || t.normal().dot(start_normal_[static_cast<std::size_t>(f.idx())]) <= 0.0;
    }
    if (turned) {
      if (blocking) (*blocking)[k] = -1;
      continue;
    }
    mesh.set_point(v, to_point(q));
    kept[k] = 1;
    if (blocking) (*blocking)[k] = -1;
  }
  stats_.rejected_moves = rejected_before;
  for (int f : known) normal_known_[static_cast<std::size_t>(f)] = 0;
  for (std::size_t k = 0; k < moves.size(); ++k) {
    move_of_[static_cast<std::size_t>(moves[k].vertex)] = -1;
    if (!kept[k])
      ++stats_.rejected_moves;
    else if (moved_vertices_.size() <= mesh.n_faces())
      moved_vertices_.push_back(moves[k].vertex);
  }
  return kept;
}

bool IntersectionGuard::flip_is_safe(Mesh::EdgeHandle e, const Mesh::VertexHandle (&q)[4]) {
  const auto h = mesh_->halfedge_handle(e, 0);
  const std::vector<int> ignore{mesh_->face_handle(h).idx(),
                                mesh_->face_handle(mesh_->opposite_halfedge_handle(h)).idx()};
  const auto tri = [&](Mesh::VertexHandle a, Mesh::VertexHandle b, Mesh::VertexHandle c) {
    Triangle t;
    t.id = {a.idx(), b.idx(), c.idx()};
    t.p = {to_eigen(mesh_->point(a)), to_eigen(mesh_->point(b)), to_eigen(mesh_->point(c))};
    return t;
  };
  const Triangle t0 = tri(q[0], q[1], q[3]), t1 = tri(q[2], q[3], q[1]);
  last_blocking_face_ = -1;
  for (const Triangle* t : {&t0, &t1}) {
    const double area = 0.5 * t->normal().norm();
    if (area < min_face_area_ || !triangle_is_clear(*t, ignore, -1, Vec3::Zero(), last_blocking_face_)) {
      ++stats_.rejected_flips;
      return false;
    }
  }
  // The two new faces against each other share the new edge q1-q3.
  if (triangles_intersect_improperly(t0.p, t0.id, t1.p, t1.id)) {
    ++stats_.rejected_flips;
    return false;
  }
  // The flip keeps both face handles: register their new boxes.
  if (flipped_faces_.size() <= mesh_->n_faces()) flipped_faces_.insert(flipped_faces_.end(), ignore.begin(), ignore.end());
  for (int f : ignore)
    for (const Triangle* t : {&t0, &t1})
      grid_.insert_box(f, t->p[0].cwiseMin(t->p[1]).cwiseMin(t->p[2]), t->p[0].cwiseMax(t->p[1]).cwiseMax(t->p[2]));
  return true;
}

}  // namespace gdm
