// The gap gate: one physical size G decides where the model may pass
// (paper sections 1 and 3.1.3: a model that stays inside an object whose
// wall has gaps and holes). The model passes only where a ball of diameter G
// fits in the region it deforms through and can roll there from the seed:
// openings narrower than G are bridged, channels wider than G are followed,
// whatever the level of detail.
//
// The region the model may reach is the morphological opening of the free
// region (the object when growing, the background when shrinking) by a ball
// of radius G / 2, keeping only the balls whose centres are connected to the
// seed: the erosion's component of the seed, dilated again. Free voxels
// outside it are closed by mirroring their value about T (a voxel that was
// `delta` on the free side becomes `delta` on the blocked side), so the
// threshold crossing between a reachable and a closed voxel lies half-way,
// as between two voxels of the image. The work stays proportional to the
// region the balls sweep: the box the erosion is computed in grows from the
// seed only as far as the seed's component reaches.
#pragma once

#include <cstddef>
#include <vector>

#include "gdm/cost_terms.h"
#include "gdm/volume.h"

namespace gdm {

struct PassageOptions {
  double gap = 0.0;        // G, mm: diameter of the ball that must fit; at most two voxels = no gate
  double threshold = 0.0;  // T of eq. 2
  bool blocked_is_brighter = false;  // the region the model must not enter lies above T
  int threads = 0;                   // workers for the distance transforms (0 = all cores); the gate
                                     // does not depend on it
};

struct PassageGate {
  bool applied = false;            // false: G does not exceed two voxels, `volume` is empty, use the input
  Volume volume;                   // the input cropped to the reachable region (plus two voxels), closed voxels mirrored
  std::size_t reachable_voxels = 0;  // free voxels a ball of diameter G reaches from the seed
  std::size_t closed_voxels = 0;   // free voxels in the crop that it does not reach (gaps bridged, narrow channels)
  bool reaches_border = false;     // the reachable region touches the volume's border
};

// True when a gap of `gap` mm changes anything on this grid: a ball of
// radius G / 2 wider than the smallest spacing.
bool gap_gate_active(double gap, const Volume& volume);

// Builds the gate from the seed points (mm; those on the free side of T seed
// the erosion's component). Throws InvalidSeed when no seed point lies where
// a ball of diameter G fits (the seed sits in a gap narrower than G).
PassageGate gate_passages(const Volume& volume, const PassageOptions& options, const std::vector<Vec3>& seed_points);

}  // namespace gdm
