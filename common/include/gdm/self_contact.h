// Where a model meets itself (issue 15): two parts of the surface that are
// not neighbours on the mesh face each other closer than a voxel. A model
// that grew around a cavity or a handle of the object from two sides stops
// there with two sheets a hair apart: closed, 2-manifold, genus 0 and free of
// self-intersections, yet not the object's surface. The report says so.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "gdm/mesh.h"

namespace gdm {

struct ContactRegion {
  std::size_t faces = 0;       // faces in contact (both sheets)
  double area = 0.0;           // their area, mm^2
  Vec3 centre = Vec3::Zero();  // area-weighted centre of those faces, mm
  bool across_object = true;   // the thin gap between the sheets lies on the object's side
};

struct ContactReport {
  std::vector<ContactRegion> regions;  // largest first
  std::size_t faces = 0;               // faces in contact, all regions
  double area = 0.0;                   // their area, mm^2
  // Of them, the regions across the object (seams: where the model's
  // fronts met head on, the surface is not the object's; a slit of
  // background between two parts of the object is the object's surface).
  std::size_t seam_faces = 0;
  double seam_area = 0.0;  // mm^2
};

// Faces f and g are in contact when g shares no vertex with f nor with a
// neighbour of f, their normals point at each other (n_f . n_g < -0.5, g in
// front of f), and f's centroid lies within `distance` (mm) of g. Regions are
// the edge-connected groups of faces in contact. `object_side(p)` says
// whether a point lies on the object's side of the threshold: the gap's
// midpoints vote for "across the object" (the model grew around something
// from two sides) or "across the background" (a thin slit of background
// between two parts of the object); without it every region counts as across
// the object. `threads` worker threads (0 = all cores); the report does not
// depend on it.
ContactReport find_self_contacts(const Mesh& mesh, double distance,
                                 const std::function<bool(const Vec3&)>& object_side = {}, int threads = 0);

// The faces of `mesh` in contact as find_self_contacts defines it (1 =
// in contact, by face index), and for each the midpoint of its gap (`gaps`,
// when given), on `threads` worker threads (0 = all cores; the result does
// not depend on it). With `only`, just the faces it flags are tested (every
// face is still a partner they may meet); the others are 0.
std::vector<char> contact_faces(const Mesh& mesh, double distance, std::vector<Vec3>* gaps = nullptr,
                                int threads = 0, const std::vector<char>* only = nullptr);

// The faces of `mesh` with another face behind them (opposite normals, not
// neighbours as above) closer than `distance` (mm): where the model is
// thinner than that. A shrinking model folded over on itself has them (a
// flap); a model of an object thicker than `distance` has none. `middles`
// (when given) receives the midpoint of each one's thickness. `threads` as
// for contact_faces.
std::vector<char> thin_faces(const Mesh& mesh, double distance, std::vector<Vec3>* middles = nullptr,
                             int threads = 0);

// Seams on more than this share of the model's area are worth starting from
// the object's voxels (DeformOptions::voxel_seed: no fronts meet, so no seam
// is left where the object has no handle; the T1 head at the defaults: 31 %
// of its area, 0.04 % from its voxels), at the voxel seed's cost in time.
constexpr double kSeamShareWorthAVoxelSeed = 0.01;
bool seams_worth_a_voxel_seed(const ContactReport& report, double model_area);

// One log line per region (at most `limit`, the largest), saying what it
// means; empty when there is no contact.
// `model_area` (mm^2, > 0): the seams' share of it is said too.
std::vector<std::string> describe_contacts(const ContactReport& report, std::size_t limit = 5, double model_area = 0.0);

}  // namespace gdm
