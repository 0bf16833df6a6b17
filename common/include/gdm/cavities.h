// Enclosed cavities filled before the model grows (issue 15's "solid"
// topology): a model growing in an object that encloses a region of
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
// "Reach" is what the gap size G says everywhere else (passage.h): with G at
// most two voxels, any 6-connected path of background voxels to the
// volume's border; with a larger G, only where a ball of diameter G fits and
// rolls in from outside the volume, so a chamber joined to the outside by
// canals narrower than G is a cavity too (and grooves narrower than G in the
// outer surface are bridged, as the model bridges them).
#pragma once

#include <cstddef>
#include <vector>

#include "gdm/volume.h"

namespace gdm {

struct CavityOptions {
  double threshold = 0.0;            // T of eq. 2
  bool background_is_brighter = false;  // the background lies above T (an object darker than T)
  double gap = 0.0;                  // G, mm: the outside reaches in only through openings a ball of
                                     // diameter G passes; at most two voxels = any 6-connected path
  std::vector<Vec3> seed_points;     // mm: the object the model grows in is the 6-connected object
                                     // region of those that lie on the object's side of T
};

struct Cavity {
  std::size_t voxels = 0;    // background voxels filled
  Vec3 centre = Vec3::Zero();  // their centroid, mm
};

// A cavity of fewer voxels than this is a speck of noise inside the object:
// filled like any other, but logs count it apart (no alarm on a noisy ball).
constexpr std::size_t kCavitySpeckVoxels = 8;

struct CavityFill {
  bool applied = false;        // false: no cavity, `volume` is empty, use the input
  Volume volume;               // the input with every cavity voxel mirrored about T to the object's side
  std::vector<Cavity> cavities;  // one per 6-connected cavity, largest first
  std::size_t voxels = 0;      // all cavity voxels
};

// Finds the background the outside does not reach and fills it. The work
// and memory are one pass over the volume (plus a distance transform of the
// volume and a margin of G / 2 when the gap decides reach).
CavityFill fill_cavities(const Volume& volume, const CavityOptions& options);

}  // namespace gdm
