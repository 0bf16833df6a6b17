// The only translation unit that instantiates the ITK filter.
#include "itkGeometricallyDeformedModelImageToMeshFilter.h"
#include "itkMesh.h"
#include "itkTriangleCell.h"

#include "run_model.h"

#include <algorithm>
#include <chrono>
#include <unordered_map>

#include "cli_errors.h"
#include "mesh_writers.h"

namespace gdm_cli {
namespace {

// Double coordinates: float would round the core's exact, self-intersection-free
// geometry (nearly coplanar faces could then touch); the point data is the generation.
using MeshTraits = itk::DefaultStaticMeshTraits<int, 3, 3, double, double, int>;
using MeshType = itk::Mesh<int, 3, MeshTraits>;
using FilterType = itk::GeometricallyDeformedModelImageToMeshFilter<Image, MeshType>;

MeshType::Pointer to_itk(const SurfaceMesh& m) {
  auto mesh = MeshType::New();
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    MeshType::PointType p;
    for (unsigned int d = 0; d < 3; ++d) p[d] = m.points[i][d];
    mesh->SetPoint(i, p);
  }
  using Triangle = itk::TriangleCell<MeshType::CellType>;
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    MeshType::CellAutoPointer cell;
    cell.TakeOwnership(new Triangle);
    for (unsigned int k = 0; k < 3; ++k) cell->SetPointId(k, m.faces[f][k]);
    mesh->SetCell(f, cell);
  }
  return mesh;
}

// Points renumbered densely in identifier order; triangles only.
SurfaceMesh from_itk(const MeshType* mesh) {
  SurfaceMesh out;
  std::unordered_map<MeshType::PointIdentifier, std::uint32_t> ids;
  for (auto it = mesh->GetPoints()->Begin(); it != mesh->GetPoints()->End(); ++it) {
    ids[it.Index()] = static_cast<std::uint32_t>(out.points.size());
    out.points.push_back({it.Value()[0], it.Value()[1], it.Value()[2]});
    MeshType::PixelType generation = 0;
    mesh->GetPointData(it.Index(), &generation);
    out.generation.push_back(static_cast<int>(generation));
  }
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it) {
    const auto* cell = it.Value();
    if (cell->GetNumberOfPoints() != 3) continue;
    std::array<std::uint32_t, 3> face{};
    int k = 0;
    for (auto p = cell->PointIdsBegin(); p != cell->PointIdsEnd(); ++p) face[k++] = ids.at(*p);
    out.faces.push_back(face);
  }
  return out;
}

}  // namespace

// The core's reader (gdm/mesh_io.h): a hostile file (empty, no faces, bad
// counts or indices, random bytes) is an InputError, never a crash.
SurfaceMesh read_seed_mesh(const std::string& path) {
  try {
    return read_surface_mesh(path);
  } catch (const InputError& e) {
    std::string message = e.what();  // "cannot read the mesh <path>: <problem>"
    const std::string core = "cannot read the mesh ";
    if (message.compare(0, core.size(), core) == 0) message = "cannot read the seed mesh " + message.substr(core.size());
    throw InputError(message);
  }
}

ModelResult run_model(const Image* image, const gdm::DeformOptions& o, const ModelSeed& seed,
                      const ProgressCallback& progress) {
  auto filter = FilterType::New();
  filter->SetInput(image);
  filter->SetThreshold(o.threshold);
  filter->SetPolarity(o.polarity == gdm::Polarity::object_darker ? FilterType::PolarityEnum::ObjectDarker
                                                                 : FilterType::PolarityEnum::ObjectBrighter);
  filter->SetMode(o.mode == gdm::Mode::shrink ? FilterType::ModeEnum::Shrink : FilterType::ModeEnum::Grow);
  filter->SetDeformationWeight(o.a0);
  filter->SetImageEventWeight(o.a1);
  filter->SetTopologyWeight(o.a2);
  filter->SetIntensityScale(o.intensity_scale);
  filter->SetReach(o.reach);
  filter->SetNormalRings(static_cast<unsigned int>(o.normal_rings));
  filter->SetLocalFlip(o.local_flip);
  filter->SetMinimumStep(o.optimizer.min_step);
  filter->SetMaximumStep(o.optimizer.max_step);
  filter->SetMaximumStepReductions(static_cast<unsigned int>(o.optimizer.max_step_reductions));
  filter->SetGradientStep(o.optimizer.gradient_step);
  filter->SetLevelOfDetailFaceArea(o.lod_face_area);
  filter->SetLevelOfDetailTopologyExtent(o.lod_topology_extent);
  filter->SetMaximumTopologyRatio(o.max_topology_ratio);
  filter->SetRefinementTravel(o.refinement_travel);
  filter->SetNumberOfGlobalRefinements(static_cast<unsigned int>(o.global_refinements));
  filter->SetMaximumNumberOfCycles(static_cast<unsigned int>(o.max_cycles));
  filter->SetConvergenceTolerance(o.convergence_tolerance);
  filter->SetConvergenceWindow(static_cast<unsigned int>(o.convergence_window));
  filter->SetPreventSelfIntersection(o.prevent_self_intersection);
  filter->SetImproveTriangles(o.improve_triangles);
  filter->SetFlipMaximumDihedralAngle(o.flip_max_dihedral);
  filter->SetMaximumNumberOfFaces(static_cast<itk::SizeValueType>(o.max_faces));
  filter->SetSubvoxelFit(o.subvoxel_fit);
  filter->SetNumberOfFitPasses(static_cast<unsigned int>(std::max(o.fit_passes, 0)));
  filter->SetFitMaximumDistance(o.fit_max_distance);
  filter->SetFitSmoothing(o.fit_smoothing);
  filter->SetLevelOfDetailTolerance(o.lod_tolerance);
  filter->SetLevelOfDetailMinimumAngle(o.lod_min_angle);
  filter->SetLevelOfDetailRounds(static_cast<unsigned int>(std::max(o.lod_rounds, 0)));
  filter->SetFloatExactOutput(o.float_exact_output);
  if (o.threads > 0) filter->SetNumberOfWorkUnits(static_cast<itk::ThreadIdType>(o.threads));

  MeshType::Pointer seed_mesh;
  if (seed.use_mesh) {
    seed_mesh = to_itk(seed.mesh);
    filter->SetSeedMesh(seed_mesh);
  } else {
    FilterType::PointType center;
    for (unsigned int d = 0; d < 3; ++d) center[d] = seed.center[d];
    filter->SetSeedCenter(center);
    filter->SetSeedRadius(seed.radius);
    filter->SetSeedSubdivisionLevel(static_cast<unsigned int>(seed.level));
  }

  if (progress) {
    // The filter's figures of the cycle just done; ITK's own events before the
    // first cycle (cycle 0) and at the end (progress 1) are not cycles.
    filter->AddObserver(itk::ProgressEvent(), [&](const itk::EventObject&) {
      const double p = filter->GetProgress();
      if (filter->GetCurrentCycle() == 0 || p >= 1.0) return;
      CycleFigures c;
      c.cycle = filter->GetCurrentCycle();
      c.stage = filter->GetCurrentStage();
      c.vertices = filter->GetCurrentNumberOfVertices();
      c.faces = filter->GetCurrentNumberOfFaces();
      c.moving = filter->GetCurrentNumberOfMovingVertices();
      c.progress = p;
      progress(c);
    });
  }

  const auto start = std::chrono::steady_clock::now();
  try {
    filter->Update();
  } catch (const itk::ExceptionObject& e) {
    throw ModelError(std::string("the model could not be built: ") + e.GetDescription());
  }
  ModelResult result;
  result.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.mesh = from_itk(filter->GetOutput());
  result.stats.stop_reason = filter->GetStopReason();
  result.stats.cycles = filter->GetNumberOfCycles();
  result.stats.refinements = filter->GetNumberOfGlobalRefinementsPerformed();
  result.stats.rejected_moves = filter->GetNumberOfRejectedMoves();
  result.stats.flips = filter->GetNumberOfFlips();
  result.stats.border_vertices = filter->GetNumberOfBorderVertices();
  result.stats.fit_moves = filter->GetNumberOfFitMoves();
  result.stats.lod_splits = filter->GetNumberOfLevelOfDetailSplits();
  result.stats.lod_collapses = filter->GetNumberOfLevelOfDetailCollapses();
  result.stats.float_refused = filter->GetNumberOfFloatRefusedVertices();
  return result;
}

}  // namespace gdm_cli
