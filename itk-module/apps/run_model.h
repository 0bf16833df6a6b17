// Runs itk::GeometricallyDeformedModelImageToMeshFilter (the one code path
// to the core) on the preprocessed image.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>

#include "image_input.h"  // ITK first (see the build notes on Eigen)
#include "progress.h"
#include "surface_mesh.h"

#include "gdm/deformer.h"

namespace gdm_cli {

struct ModelSeed {
  bool use_mesh = false;
  SurfaceMesh mesh;                     // when use_mesh
  std::array<double, 3> center{0, 0, 0};  // mm, the sphere otherwise
  double radius = 1.0;                  // mm
  int level = 1;                        // icosahedron subdivisions
};

struct ModelResult {
  SurfaceMesh mesh;
  ModelStats stats;
};

// Called once per deformation cycle with the filter's figures of that cycle.
using ProgressCallback = std::function<void(const CycleFigures&)>;

// Throws ModelError with the filter's message when the run fails.
ModelResult run_model(const Image* image, const gdm::DeformOptions& options, const ModelSeed& seed,
                      const ProgressCallback& progress);

// Reads a seed mesh (.ply, .obj, .off, .stl, .vtk) with the core's reader
// (gdm/mesh_io.h); throws InputError naming the file and the problem.
SurfaceMesh read_seed_mesh(const std::string& path);

}  // namespace gdm_cli
