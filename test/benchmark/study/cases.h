// The study's cases: analytic phantoms (exact ground truth), real scans
// (reference: iso-surface of the 2x-upsampled volume) and scaling series.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "gdm/deformer.h"
#include "gdm/mesh.h"
#include "study_types.h"

namespace study {

struct Case {
  std::string group;  // "phantom", "scan", "scaling: volume size", "scaling: surface area"
  std::string name;   // shown in the report
  std::string id;     // file-safe
  Image image;
  double threshold = 125.0;
  bool object_brighter = true;
  gdm::Mode mode = gdm::Mode::grow;
  Point seed{0, 0, 0};       // grow: centre of the seed icosahedron (radius seed_radius mm)
  double seed_radius = 3.0;  // shrink: the seed is an ellipsoid inscribed in the volume
  // Exact unsigned distance to the true surface (mm) for phantoms; empty for scans.
  std::function<double(const Point&)> exact_distance;
  // Phantoms: the same distance signed, positive outside the true object; it
  // tells a leak (surface outside the object) from a miss. Empty for scans.
  std::function<double(const Point&)> signed_distance;
  // The gap size G (mm) our GDM rows run with (DeformOptions::gap): the case's
  // object has openings in its wall narrower than G that the model must not
  // pass. 0: none (the default). With G > 0 the study adds a row without it.
  double gap = 0.0;
  // The signed distance on the grid (phantoms) or the volume itself (scans),
  // and the level of its reference surface: the truth the coverage is measured on.
  Image truth_field;
  double truth_level = 0.0;
  std::string note;  // preprocessing, shown in the report
  // Topology cases (issue 15): the exact distance (mm) to the object's outer
  // surface only, the truth for our GDM with the solid topology (cavities
  // filled); exact_distance is then the distance to all its surfaces. Empty
  // for a scan: the outer component of the reference iso-surface is used.
  std::function<double(const Point&)> outer_distance;
  std::string truth_note;  // topology cases: what the outer and the whole truth are, for the report
  int truth_components = 0;  // topology phantoms: the object's surfaces (closed components); 0: unknown (scans)
  int truth_genus = -1;      // topology phantoms: their genus summed; -1: unknown (scans)
  double voxel_size() const;
};

struct CaseSet {
  std::vector<Case> cases;
  std::vector<std::string> skipped;  // "name: reason"
};

// The Gaussian-noise phantoms' noise: sigma in the image's units (the
// contrast is 150) and the first seed of the noise fields (one per shape).
struct PhantomNoise {
  double sigma = 20.0;  // 13 % of the contrast
  unsigned seed = 7;
};

// quick: one small phantom only.
CaseSet phantom_cases(bool quick, const PhantomNoise& noise = {});
CaseSet scan_cases(const std::string& data_dir);
// Opened bottles and the channel phantom (issue 14): where a method leaks
// through an opening narrower than the gap, or misses a channel wider than it.
// quick: the smaller opening only.
CaseSet opening_cases(bool quick);
// Objects that are not a ball (issue 15): a hollow sphere (an enclosed
// cavity), a torus and a double torus (handles, genus 1 and 2), and the
// whole tooth from a seed in the dentin (its pulp chamber; skipped when
// data_dir has no tooth). Group "topology"; not part of the quick study.
CaseSet topology_cases(const std::string& data_dir);
CaseSet volume_scaling_cases(bool quick);
CaseSet area_scaling_cases(bool quick);

// The closed seed mesh GDM (and, in index units, ITK's simplex) starts from:
// growing, a geodesic sphere of `level` (0: the icosahedron, the study's seed;
// 1: the command line's default seed) at the case's seed.
gdm::Mesh seed_mesh(const Case& c, int level = 0);

}  // namespace study
