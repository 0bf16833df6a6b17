// The model's topology (issue 15): `solid` is the paper's genus-0 model of
// the object's outer surface (cavities filled, handles capped: cavities.h);
// `exact` goes past the paper's single genus-0 model where the data is not a
// ball. An enclosed cavity (background the outside cannot reach, a hollow
// shell's inside) becomes its own closed component with inward orientation:
// a separate model is grown in the cavity (the cavity is its object), its
// faces are reversed so its normals point into the cavity, away from the
// object, and it is added to the outer model only when the union stays free
// of self-intersections. A handle's cap (the membrane the fill left across
// its hole) is opened into a tube through the hole (handles.cpp): the patches
// of the converged model on the membrane's two sides are removed, their
// boundary loops joined by a tube of new rings, and the model deformed once
// more on the volume without that membrane, so the tube settles on the
// hole's wall under the intersection guard; each opened cap raises the genus
// by one. A cap that cannot be opened safely stays, and is counted. Pockets
// joined to the outside only through narrow openings stay filled as in
// `solid` (they are not enclosed).
#pragma once

#include <cstddef>
#include <functional>
#include <string>

#include "gdm/cavities.h"
#include "gdm/cost_terms.h"
#include "gdm/mesh.h"
#include "gdm/volume.h"

namespace gdm {

struct DeformOptions;
struct DeformResult;
struct CycleReport;
using DeformObserver = std::function<bool(const CycleReport&)>;  // as in deformer.h

enum class Topology {
  solid,  // one closed genus-0 surface: the object's outer surface, cavities filled, handles capped
  exact,  // enclosed cavities as their own closed inward components, handles as tubes (genus up)
};
// "solid" or "exact".
std::string to_string(Topology topology);

struct CavitySurfaces {
  std::size_t added = 0;           // cavities added as inward components
  std::size_t added_faces = 0;     // their faces
  std::size_t not_modelled = 0;    // enclosed cavities (of at least kCavitySpeckVoxels voxels) left filled:
                                   // too thin for a seed, the cavity's model did not converge, or it would
                                   // have touched the outer model
  std::size_t narrow_pockets = 0;  // pockets joined to the outside only through narrow openings: filled as
                                   // in `solid` (they are not enclosed)
};

// What the cavity's own model needs: the volume the outer model grew in (the
// input, or the gap gate's), the cavity fill computed on it, the threshold
// and polarity of the object, and the options of each cavity's model (its
// polarity is reversed here: the cavity is the object it grows in).
struct CavitySurfaceInput {
  const Volume* volume = nullptr;     // the volume the fill was computed on
  const CavityFill* fill = nullptr;   // fill_cavities on `volume`
  double threshold = 0.0;             // T
  Polarity polarity = Polarity::object_brighter;  // the object's polarity (not the cavity's)
  std::size_t max_faces = 0;          // faces all cavity models together may have; 0 = no limit
};

// Grows a model in each enclosed cavity of `input.fill` (largest first),
// reverses it and appends it to `mesh` (the outer model) when the union is
// free of self-intersections. `grow` runs one cavity's model: it gets the
// cavity's volume (a box around the cavity, other background mirrored to the
// object's side, so the cavity is the only region on its side of T) with the
// cavity's polarity, and the seed; it returns false when the model is not
// usable. Deterministic: the same for any thread count when `grow` is.
CavitySurfaces add_cavity_surfaces(
    Mesh& mesh, const CavitySurfaceInput& input,
    const std::function<bool(Mesh& seed, const Volume& cavity_volume, Polarity cavity_polarity)>& grow);

struct OpenedHandles {
  std::size_t opened = 0;     // membranes replaced by a tube through the hole
  std::size_t kept_caps = 0;  // membranes left as caps (their patches are not two discs, or the band would
                              // not be closed, 2-manifold and free of self-intersections)
  Volume volume;              // the fill's volume with the opened membranes' voxels as in the input (empty
                              // when none was opened): what the model is deformed on again
};

// On a model converged on fill.volume (computed on `volume`): for each
// membrane of `fill`, the model's two patches on the membrane's sides are
// removed and their boundary loops stitched by a band through the hole
// (handles.cpp). Each opening raises the genus by one. Only changes that keep
// the model closed, 2-manifold and free of new self-intersections are made.
OpenedHandles open_handles(Mesh& mesh, const Volume& volume, const CavityFill& fill);

// deform()'s last step with the exact topology: the enclosed cavities
// of `fill` (computed on `volume`, the volume the outer model grew in) added
// to `mesh` by add_cavity_surfaces, and each handle's cap opened into a tube
// (open_handles, then deform() again on the volume without those membranes,
// no global refinement; reverted when that run does not converge), each cavity's model grown by deform()
// with `options` (the cavity's polarity, solid, no face budget); counts into
// `result` (handles_opened, cavity_components, cavity_component_faces,
// cavities_not_modelled, faces). Shrinking, the same: the opened model is
// deformed again in shrink mode, and each cavity's model grows from a seed
// in the cavity. Nothing for solid or when the outer model did not converge.
// Every extra run reports its cycles to `observer`; when the observer cancels
// one (a time limit, an aborted filter), the model is left as it was before
// that run and result.reason is StopReason::cancelled.
void add_cavity_components(Mesh& mesh, const Volume& volume, const CavityFill& fill, const DeformOptions& options,
                           DeformResult& result, const DeformObserver& observer = {});

// The genus and components a closed orientable mesh has by its Euler
// characteristic: chi = 2 * components - 2 * genus. False when the numbers
// disagree (odd 2c - chi, negative genus) or the mesh is not closed.
bool euler_consistent(int euler, int components, int genus, bool closed);

}  // namespace gdm
