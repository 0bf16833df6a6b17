// Keeps the model free of self-intersections (beyond the paper, section 7):
// every vertex move, and every edge flip, is checked against the nearby faces
// with exact predicates before it is applied.
#pragma once

#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "gdm/face_grid.h"
#include "gdm/mesh.h"
#include "gdm/predicates.h"

namespace gdm {

struct GuardStatistics {
  std::size_t rejected_moves = 0;  // moves vetoed for an intersection or a degenerate face
  std::size_t rejected_flips = 0;
};

class IntersectionGuard {
 public:
  // `margin` must bound how far any vertex moves between two rebuilds.
  IntersectionGuard(const Mesh& mesh, double margin, double min_face_area);

  // Re-registers every face (after topology changes or once per cycle).
  void rebuild();
  void note_face(Mesh::FaceHandle f) { grid_.insert(*mesh_, f); }
  // Registers a box the face will stay within (besides its own).
  void note_box(int face, const Vec3& lo, const Vec3& hi) { grid_.insert_box(face, lo, hi); }
  // Readies the guard for a round of moves of at most the margin each, as
  // rebuild() does, but registers again only the faces whose box changed: a
  // deformation cycle moves few vertices, and rebuilding the grid every
  // cycle took a sixth of the run on the CT head phantom. Only the faces
  // around the vertices of moves it allowed since the last call, and of the
  // flips it allowed, are looked at (the caller moves vertices only where
  // move_is_safe said yes, between calls): a cycle's cost follows its moves,
  // not the model's size (issue 17: the scan of every face's box each cycle
  // was 8 % of the CT series' time).
  void prepare_moves();
  // Registers the faces added (by splits) since rebuild() or prepare_moves().
  void note_new_faces() { grid_.register_new_faces(*mesh_); }
  // The mesh's faces renumbered by its garbage collection (FaceGrid::renumber):
  // instead of a rebuild, for a caller that registered every change as it
  // made it (note_face after moves and collapses, note_new_faces after
  // splits, flips through flip_is_safe), so nothing waits for prepare_moves().
  void renumber_faces(const std::vector<int>& to);

  // Would moving v to p leave every face non-degenerate, with its orientation
  // kept, and free of improper intersections with all other faces? `hint`: a
  // face likely to cut the moved fan (the one that refused v's last move),
  // tested first; the answer does not depend on it.
  bool move_is_safe(Mesh::VertexHandle v, const Vec3& p, int hint = -1);

  // One thread's share of checks made at the same time as other threads'
  // (issue 17): its scratch, its marks for the grid's query, and what the
  // guard learns from its checks until absorb() takes it in.
  struct Checker {
    std::vector<std::uint32_t> stamps;
    std::uint32_t stamp = 0;
    std::vector<int> ring_faces;
    std::vector<FilteredTriangle> fan;
    std::vector<std::pair<Vec3, Vec3>> boxes;
    std::vector<int> moved;          // vertices of the moves it allowed
    std::size_t rejected = 0;        // moves it refused
    int last_blocking_face = -1;     // as last_blocking_face(), for its last refusal
  };
  // move_is_safe() with the checker's state instead of the guard's: the
  // guard and the mesh are only read, so threads may check at once, each
  // with its own checker, moves far enough apart that none reads what
  // another's move changes (reach()). The same answer as move_is_safe().
  bool move_is_safe(Mesh::VertexHandle v, const Vec3& p, int hint, Checker& checker) const;
  // Takes in a checker's allowed moves (for prepare_moves()) and refusals.
  void absorb(Checker& checker);
  // A check of a move of v reads vertices within this distance of v (its
  // fan, the faces the grid offers near it) and nothing else of the mesh,
  // as long as every face stays within the box it is registered with: moves
  // within the margin keep them so, longer ones need their boxes registered
  // first (note_box(), as the sub-voxel fit does).
  double reach() const { return 2.0 * grid_.widest_box() + margin_; }

  // Many moves at once (issue 17: the guard's one-at-a-time checks were the
  // sequential quarter of a run). Every vertex of `moves` (each listed once)
  // is moved to its target; then the faces around them are checked, in
  // parallel, for what move_is_safe checks: a face degenerate or turned over
  // against its orientation before the moves, or cutting another face
  // improperly. For each face found bad, the move of its highest-index moved
  // vertex (or of the face it cuts) is taken back, and the faces those moves
  // touch are checked again, until none is bad: lower indices keep their
  // moves, as in a pass in vertex order. Moves still sent back then try
  // once more alone, in order, against where the others ended. Returns per
  // move whether it stayed; `blocking`, if given, gets per move the face
  // that made it go back (-1: none, or its own faces). Each decision depends on positions only, never
  // on the thread count. `mesh` is the guarded mesh; every move must stay
  // within the margin, as for move_is_safe().
  struct Move {
    int vertex;
    Vec3 to;
  };
  std::vector<char> apply_moves(Mesh& mesh, const std::vector<Move>& moves, int threads,
                                std::vector<int>* blocking = nullptr);

  // Would the flip creating (q0, q1, q3) and (q2, q3, q1) from the faces
  // around edge e keep the mesh free of intersections?
  // On a refusal, last_blocking_face() is the face a new face would cut (-1:
  // the new faces are degenerate or cut each other).
  bool flip_is_safe(Mesh::EdgeHandle e, const Mesh::VertexHandle (&quad)[4]);

  const GuardStatistics& statistics() const { return stats_; }
  // The face the last refused move would have cut (-1: refused for a
  // degenerate or flipped face of its own fan).
  int last_blocking_face() const { return last_blocking_face_; }
  // Counts a move the caller knows the guard refuses (the same move, the
  // same faces as at an earlier refusal), without checking it again.
  void count_rejected_move() { ++stats_.rejected_moves; }
  // The same for a flip.
  void count_rejected_flip() { ++stats_.rejected_flips; }

 private:
  struct Triangle {
    std::array<Vec3, 3> p;
    std::array<int, 3> id;
    // (p1 - p0) x (p2 - p0): the face's normal, twice its area long.
    Vec3 normal() const { return (p[1] - p[0]).cross(p[2] - p[0]); }
  };
  // Whether t cuts no face near it (but those ignored); else `blocking` is
  // the face it cuts.
  bool triangle_is_clear(const Triangle& t, const std::vector<int>& ignore_faces, int moved_vertex,
                         const Vec3& moved_to, int& blocking);
  Triangle face_triangle(int face, int moved_vertex, const Vec3& moved_to) const;

  const Mesh* mesh_;
  double margin_;
  double min_face_area_;
  FaceGrid grid_;
  GuardStatistics stats_;
  int last_blocking_face_ = -1;
  // Since the last rebuild or prepare_moves(): the vertices of allowed moves,
  // the faces of allowed flips (their boxes may have changed).
  std::vector<int> moved_vertices_;
  std::vector<int> flipped_faces_;
  std::vector<int> changed_faces_;  // prepare_moves()'s scratch
  std::vector<char> face_listed_;   // prepare_moves()'s scratch, per face (all 0 between calls)
  // apply_moves()'s scratch, per vertex and per face (kept: a deformation
  // cycle calls it with few moves on a large mesh).
  std::vector<int> move_of_;       // per vertex: its index in the moves, -1 if none
  std::vector<char> in_check_;     // per face: in this round's check
  std::vector<Vec3> start_normal_;  // per face checked: its normal before the moves
  std::vector<char> normal_known_;  // per face: start_normal_ set in this call
  std::vector<char> giving_back_;   // per move: taken back in this round
  // What is wrong with a face after apply_moves() moved its vertices: -1
  // nothing, -2 its own shape (degenerate, or turned over), else the first
  // face it cuts (faces in this round's check with a lower index are left
  // to their own check: each pair once).
  // `stamps`, `stamp`: the calling thread's marks for the grid's query.
  int bad_partner(int face, std::vector<std::uint32_t>& stamps, std::uint32_t stamp) const;
  struct WorkerStamps {
    std::vector<std::uint32_t> marks;
    std::uint32_t last = 0;
  };
  std::vector<WorkerStamps> worker_stamps_;

  // move_is_safe()'s checker, kept to spare an allocation per call.
  Checker own_;
};

}  // namespace gdm
