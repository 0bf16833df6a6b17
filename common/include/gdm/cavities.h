// Enclosed cavities and handles filled before the model grows (issue 15's
// "solid" topology): a model growing in an object that encloses a region of
// background (a hollow shell, the pulp chamber inside dentin) reaches that
// region from every side; its fronts meet there and stop a hair apart, and
// the genus-0 result carries a double-walled sheet through the object. The
// model is meant to be the object's outer surface, so the background the
// outside cannot reach is given to the object first: the model then grows
// through it and no sheet forms.
//
// A cavity is enclosed by the object the model grows in (the object's
// connected region of the seed): background reachable from the volume's
// border only by crossing that object. A wall between the seed's object and
// another (a closed bottle's wall, with the model inside and dark outside
// all round) is no cavity.
//
// "Reach" is decided apart from the gap (which says where the model may
// pass inside the object): the outside reaches in only where a ball of
// diameter W (the cavity opening, three voxels unless set, or the gap G when
// that is larger) fits and rolls in from outside the volume. A pocket of
// background the ball cannot reach is filled when it is wide somewhere
// inside (a ball of diameter W fits in it: a chamber behind canals one or
// two voxels wide, the tooth's pulp) or when no path at all leads out (an
// enclosed cavity); thin grooves and slits the ball cannot enter, but that
// hold no wider chamber, stay open (a narrow slit between two parts of a
// concave object is not closed into a ring). W at most two voxels: any
// 6-connected path of background reaches, as before the opening existed.
//
// Handles: a genus-0 model grown in a torus goes round the tube from both
// sides and its fronts meet across it. So the background the outside
// reaches is grown from outside the volume voxel by voxel, the widest
// places first (largest distance to the object), and a voxel is only taken
// when it is a simple point (Bertrand and Malandain 1994, 6-adjacency for
// the background, 26 for the object): the reached background keeps the
// topology of the outside, and what it cannot take without closing a loop
// through a hole is left to the object. That is a membrane across each hole
// of a handle, where the hole is narrowest (the last place the widest-first
// growth reaches from both sides: issue 15's "cap at the narrowest place");
// it is thickened so the model can grow into it, and reported.
//
// Or the dual (handle_repair cut, growing a solid model): the object is
// grown from its deepest voxel voxel by voxel, the deepest places first
// (largest distance to the background), by simple points (26-adjacency for
// the object, 6 for the rest); what it cannot take without closing a loop
// round a hole is given to the background. That is a cut across each
// handle's body where it is thinnest (the last place the deepest-first
// growth reaches from both sides): the hole stays open and the model
// follows it, parting at the cut, where a membrane would close the hole
// (measured on the scans of ../shared/data: README, stop 52).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "gdm/volume.h"

namespace gdm {

// How a handle of the object is removed so that the genus-0 model does not
// meet itself around it (cap_handles).
enum class HandleRepair {
  membrane,  // background across the hole given to the object, at the hole's narrowest place: the
             // model closes the hole (a torus becomes a disc)
  cut,       // the object across the handle's body given to the background, at its thinnest place:
             // the model follows the hole and parts at the cut (a torus becomes a C)
};
// "membrane", "cut".
std::string to_string(HandleRepair repair);

struct CavityOptions {
  double threshold = 0.0;            // T of eq. 2
  bool background_is_brighter = false;  // the background lies above T (an object darker than T)
  double gap = 0.0;                  // G, mm: a ball of diameter G must fit where the outside reaches in
                                     // when G exceeds the opening (the gap bridges such openings anyway)
  double opening = 0.0;              // W, mm: pockets the outside reaches only through openings narrower
                                     // than a ball of diameter W are filled when they are wider inside;
                                     // 0 = three voxels; at most two voxels = any 6-connected path reaches
  bool cap_handles = true;           // remove each handle of the object, as handle_repair says
  HandleRepair handle_repair = HandleRepair::membrane;  // membrane: across each handle's hole at its
                                     // narrowest place; cut: across the handle's body at its thinnest
  bool skip_growth_without_handles = true;  // with cap_handles, skip the growth when the object's region
                                     // (with what is filled) has no handle (voxel_topology.h): the same
                                     // fill for a fraction of the time; false = always grow (tests)
  double membrane = 0.0;             // mm: how far each membrane is thickened on either side (within
                                     // the hole); 0 = 3.5 voxels
  std::vector<Vec3> seed_points;     // mm: the object the model grows in is the 6-connected object
                                     // region of those that lie on the object's side of T
  bool every_component = false;      // the object is every voxel on its side of T inside the box around
                                     // seed_points (all its components), not only the seed's region: a
                                     // model shrinking from outside (section 5's duality) has no point
                                     // inside the object, and it meets every component its seed encloses
  int threads = 0;                   // workers for the distance transforms (0 = all cores); the fill
                                     // does not depend on it
};

// The ball diameter (mm) the fill uses for "reach" with these options on this grid: the larger of
// the opening (three voxels when 0) and the gap; at most two voxels means paths.
double cavity_opening_width(const CavityOptions& options, const Volume& volume);

enum class CavityKind {
  enclosed,         // no path of background leads from it to the outside
  narrow_openings,  // a chamber the outside reaches only through openings narrower than W
  handle,           // a membrane across a handle's hole, at its narrowest place
  cut,              // a cut across a handle's body, at its thinnest place (object given to the background)
};
// "enclosed", "narrow_openings", "handle", "cut" (the report's JSON and Python spell kinds so).
std::string to_string(CavityKind kind);

struct Cavity {
  CavityKind kind = CavityKind::enclosed;
  std::size_t voxels = 0;      // background voxels filled (cut: object voxels given to the background)
  Vec3 centre = Vec3::Zero();  // their centroid, mm
  // narrow_openings: the separate openings where the outside meets the filled
  // region (26-connected groups of its voxels next to reached background) and
  // the centre of the largest; handle: 1 and the membrane's centre.
  std::size_t openings = 0;
  Vec3 opening_centre = Vec3::Zero();
  // handle: the hole's width across the membrane, mm (twice the largest
  // distance of a membrane voxel to the object); cut: the body's thickness
  // across the cut (twice the largest distance of a cut voxel to the
  // background); narrow_openings: W.
  double width = 0.0;
};

// A region of fewer voxels than this is a speck of noise inside the object
// or a voxel-sized handle of its rough surface: filled like any other, but
// logs count it apart (no alarm on a noisy ball).
constexpr std::size_t kCavitySpeckVoxels = 8;

struct CavityFill {
  bool applied = false;        // false: nothing filled, `volume` is empty, use the input
  Volume volume;               // the input with every filled voxel mirrored about T to the object's side
                               // (and every cut voxel to the background's)
  std::vector<Cavity> cavities;  // one per filled region (6-connected cavities, 26-connected membranes),
                                 // largest first
  std::size_t voxels = 0;      // all filled voxels
  std::size_t cut_voxels = 0;  // all cut voxels (handle_repair cut)
  double opening = 0.0;        // the ball diameter used for reach, mm (cavity_opening_width)
  bool grew = false;           // the handle growth ran (cap_handles, and the region had a handle or
                               // skip_growth_without_handles was off)
};

// Finds the background the outside does not reach, and the membranes that
// cap handles, and fills them. Work and memory grow with the box around the
// seed's object (plus a margin of W / 2): a few passes over it and two or
// three distance transforms; single-threaded, so the same for any thread count.
CavityFill fill_cavities(const Volume& volume, const CavityOptions& options);

}  // namespace gdm
