// Object methods, Set/Get of every parameter, conversions and bad input.
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <limits>
#include <sstream>

#include "gtest/gtest.h"

#include "itkGDMVolumeConversion.h"
#include "itkGeometricallyDeformedModelImageToMeshFilter.h"
#include "itkGeometricallyDeformedModelTestHelpers.h"
#include "itkMesh.h"
#include "itkQuadEdgeMesh.h"
#include "itkTestingMacros.h"

#include "gdm/option_catalogue.h"
#include "gdm/pipeline.h"
#include "gdm/mesh_checks.h"
#include "gdm/seed.h"

namespace
{
using ImageType = itk::Image<short, 3>;
using MeshType = itk::Mesh<float, 3>;
using QEMeshType = itk::QuadEdgeMesh<float, 3>;
using FilterType = itk::GeometricallyDeformedModelImageToMeshFilter<ImageType, MeshType>;

ImageType::Pointer
MakeBallImage(unsigned int n = 24)
{
  auto                  image = ImageType::New();
  ImageType::RegionType region;
  region.SetSize({ { n, n, n } });
  image->SetRegions(region);
  image->Allocate();
  ImageType::PointType center;
  center.Fill((n - 1) / 2.0);
  gdmtest::FillBall(image.GetPointer(), center, n / 4.0, 50.0, 150.0, 1.0);
  return image;
}

// ITK-style exercise: returns EXIT_FAILURE at the first mismatch.
int
ExerciseBasicsAndSetGet()
{
  auto filter = FilterType::New();
  ITK_EXERCISE_BASIC_OBJECT_METHODS(filter, GeometricallyDeformedModelImageToMeshFilter, ImageToMeshFilter);

  // Defaults are the core's.
  const gdm::DeformOptions d;
  if (!std::isnan(filter->GetThreshold()))
  {
    return EXIT_FAILURE;
  }
  ITK_TEST_SET_GET_VALUE(d.a0, filter->GetDeformationWeight());
  ITK_TEST_SET_GET_VALUE(d.a1, filter->GetImageEventWeight());
  ITK_TEST_SET_GET_VALUE(d.a2, filter->GetTopologyWeight());
  ITK_TEST_SET_GET_VALUE(d.lod_face_area, filter->GetLevelOfDetailFaceArea());
  ITK_TEST_SET_GET_VALUE(static_cast<unsigned int>(d.max_cycles), filter->GetMaximumNumberOfCycles());
  ITK_TEST_SET_GET_VALUE(d.max_topology_ratio, filter->GetMaximumTopologyRatio());
  ITK_TEST_SET_GET_VALUE(d.refinement_travel, filter->GetRefinementTravel());
  ITK_TEST_SET_GET_VALUE(d.gap, filter->GetGapSize());
  ITK_TEST_SET_GET_VALUE(d.refine_channels, filter->GetRefineChannels());
  ITK_TEST_SET_GET_VALUE(d.subvoxel_fit, filter->GetSubvoxelFit());
  ITK_TEST_SET_GET_VALUE(d.sharp_edges, filter->GetSharpEdges());
  ITK_TEST_SET_GET_VALUE(d.curvature_correction, filter->GetCurvatureCorrection());
  ITK_TEST_SET_GET_VALUE(static_cast<unsigned int>(d.fit_passes), filter->GetNumberOfFitPasses());
  ITK_TEST_SET_GET_VALUE(d.fit_max_distance, filter->GetFitMaximumDistance());
  ITK_TEST_SET_GET_VALUE(d.fit_smoothing, filter->GetFitSmoothing());
  ITK_TEST_SET_GET_VALUE(d.lod_tolerance, filter->GetLevelOfDetailTolerance());
  ITK_TEST_SET_GET_VALUE(d.lod_min_angle, filter->GetLevelOfDetailMinimumAngle());
  ITK_TEST_SET_GET_VALUE(static_cast<unsigned int>(d.lod_rounds), filter->GetLevelOfDetailRounds());
  ITK_TEST_SET_GET_VALUE(d.min_angle, filter->GetMinimumAngle());
  ITK_TEST_SET_GET_VALUE(static_cast<itk::SizeValueType>(d.face_budget), filter->GetFaceBudget());
  ITK_TEST_SET_GET_VALUE(d.float_exact_output, filter->GetFloatExactOutput());
  // Before a run the results and the current cycle's figures are 0.
  ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfFitMoves(), 0u);
  ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfLevelOfDetailSplits(), 0u);
  ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfLevelOfDetailCollapses(), 0u);
  ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfFloatRefusedVertices(), 0u);
  ITK_TEST_EXPECT_EQUAL(filter->GetNumberOfBudgetCollapses(), 0u);
  ITK_TEST_EXPECT_EQUAL(filter->GetCurrentCycle(), 0u);
  ITK_TEST_EXPECT_EQUAL(filter->GetCurrentNumberOfFaces(), 0u);
  ITK_TEST_EXPECT_EQUAL(filter->GetCurrentNumberOfMovingVertices(), 0u);

  filter->SetThreshold(12.5);
  ITK_TEST_SET_GET_VALUE(12.5, filter->GetThreshold());
  filter->SetPolarity(FilterType::PolarityEnum::ObjectDarker);
  ITK_TEST_SET_GET_VALUE(FilterType::PolarityEnum::ObjectDarker, filter->GetPolarity());
  filter->SetMode(FilterType::ModeEnum::Shrink);
  ITK_TEST_SET_GET_VALUE(FilterType::ModeEnum::Shrink, filter->GetMode());

  // Set/Get and clamping.
  ITK_TEST_SET_GET_VALUE(0.0, (filter->SetDeformationWeight(-1.0), filter->GetDeformationWeight()));
  ITK_TEST_SET_GET_VALUE(2.0, (filter->SetDeformationWeight(2.0), filter->GetDeformationWeight()));
  ITK_TEST_SET_GET_VALUE(0.0, (filter->SetImageEventWeight(-1.0), filter->GetImageEventWeight()));
  ITK_TEST_SET_GET_VALUE(3.0, (filter->SetImageEventWeight(3.0), filter->GetImageEventWeight()));
  ITK_TEST_SET_GET_VALUE(0.0, (filter->SetTopologyWeight(-1.0), filter->GetTopologyWeight()));
  ITK_TEST_SET_GET_VALUE(4.0, (filter->SetTopologyWeight(4.0), filter->GetTopologyWeight()));
  ITK_TEST_SET_GET_VALUE(0.0, (filter->SetIntensityScale(-1.0), filter->GetIntensityScale()));
  ITK_TEST_SET_GET_VALUE(7.0, (filter->SetIntensityScale(7.0), filter->GetIntensityScale()));
  ITK_TEST_SET_GET_VALUE(10.0, (filter->SetReach(20.0), filter->GetReach()));
  ITK_TEST_SET_GET_VALUE(0.01, (filter->SetReach(0.0), filter->GetReach()));
  ITK_TEST_SET_GET_VALUE(1.5, (filter->SetReach(1.5), filter->GetReach()));
  ITK_TEST_SET_GET_VALUE(4u, (filter->SetNormalRings(9), filter->GetNormalRings()));
  ITK_TEST_SET_GET_VALUE(1u, (filter->SetNormalRings(0), filter->GetNormalRings()));
  ITK_TEST_SET_GET_VALUE(3u, (filter->SetNormalRings(3), filter->GetNormalRings()));
  ITK_TEST_SET_GET_BOOLEAN(filter, LocalFlip, true);
  ITK_TEST_SET_GET_VALUE(0.01, (filter->SetMinimumStep(0.0), filter->GetMinimumStep()));
  ITK_TEST_SET_GET_VALUE(0.5, (filter->SetMinimumStep(0.5), filter->GetMinimumStep()));
  ITK_TEST_SET_GET_VALUE(10.0, (filter->SetMaximumStep(11.0), filter->GetMaximumStep()));
  ITK_TEST_SET_GET_VALUE(2.0, (filter->SetMaximumStep(2.0), filter->GetMaximumStep()));
  ITK_TEST_SET_GET_VALUE(16u, (filter->SetMaximumStepReductions(99), filter->GetMaximumStepReductions()));
  ITK_TEST_SET_GET_VALUE(2u, (filter->SetMaximumStepReductions(2), filter->GetMaximumStepReductions()));
  ITK_TEST_SET_GET_VALUE(1.0, (filter->SetGradientStep(5.0), filter->GetGradientStep()));
  ITK_TEST_SET_GET_VALUE(0.2, (filter->SetGradientStep(0.2), filter->GetGradientStep()));
  ITK_TEST_SET_GET_VALUE(0.5, (filter->SetLevelOfDetailFaceArea(0.1), filter->GetLevelOfDetailFaceArea()));
  ITK_TEST_SET_GET_VALUE(6.0, (filter->SetLevelOfDetailFaceArea(6.0), filter->GetLevelOfDetailFaceArea()));
  ITK_TEST_SET_GET_BOOLEAN(filter, LevelOfDetailTopologyExtent, true);
  ITK_TEST_SET_GET_VALUE(4u, (filter->SetNumberOfGlobalRefinements(7), filter->GetNumberOfGlobalRefinements()));
  ITK_TEST_SET_GET_VALUE(0u, (filter->SetNumberOfGlobalRefinements(0), filter->GetNumberOfGlobalRefinements()));
  ITK_TEST_SET_GET_VALUE(1u, (filter->SetMaximumNumberOfCycles(0), filter->GetMaximumNumberOfCycles()));
  ITK_TEST_SET_GET_VALUE(300u, (filter->SetMaximumNumberOfCycles(300), filter->GetMaximumNumberOfCycles()));
  ITK_TEST_SET_GET_VALUE(0.001, (filter->SetConvergenceTolerance(0.0), filter->GetConvergenceTolerance()));
  ITK_TEST_SET_GET_VALUE(0.3, (filter->SetConvergenceTolerance(0.3), filter->GetConvergenceTolerance()));
  ITK_TEST_SET_GET_VALUE(1u, (filter->SetConvergenceWindow(0), filter->GetConvergenceWindow()));
  ITK_TEST_SET_GET_VALUE(8u, (filter->SetConvergenceWindow(8), filter->GetConvergenceWindow()));
  ITK_TEST_SET_GET_BOOLEAN(filter, PreventSelfIntersection, true);
  ITK_TEST_SET_GET_BOOLEAN(filter, ImproveTriangles, true);
  ITK_TEST_SET_GET_VALUE(89.9, (filter->SetFlipMaximumDihedralAngle(95.0), filter->GetFlipMaximumDihedralAngle()));
  ITK_TEST_SET_GET_VALUE(0.0, (filter->SetFlipMaximumDihedralAngle(-5.0), filter->GetFlipMaximumDihedralAngle()));
  ITK_TEST_SET_GET_VALUE(15.0, (filter->SetFlipMaximumDihedralAngle(15.0), filter->GetFlipMaximumDihedralAngle()));
  ITK_TEST_SET_GET_VALUE(20u, (filter->SetMaximumNumberOfFaces(3), filter->GetMaximumNumberOfFaces()));
  ITK_TEST_SET_GET_VALUE(5000u, (filter->SetMaximumNumberOfFaces(5000), filter->GetMaximumNumberOfFaces()));
  ITK_TEST_SET_GET_BOOLEAN(filter, SubvoxelFit, true);
  filter->SubvoxelFitOff();
  ITK_TEST_SET_GET_BOOLEAN(filter, CurvatureCorrection, true);
  filter->CurvatureCorrectionOn();
  ITK_TEST_SET_GET_VALUE(true, filter->GetDeformOptions().curvature_correction);
  filter->CurvatureCorrectionOff();
  ITK_TEST_SET_GET_BOOLEAN(filter, SharpEdges, true);
  filter->SharpEdgesOff();
  ITK_TEST_SET_GET_VALUE(false, filter->GetDeformOptions().sharp_edges);
  ITK_TEST_SET_GET_VALUE(6u, (filter->SetNumberOfFitPasses(6), filter->GetNumberOfFitPasses()));
  ITK_TEST_SET_GET_VALUE(0.75, (filter->SetFitMaximumDistance(0.75), filter->GetFitMaximumDistance()));
  ITK_TEST_SET_GET_VALUE(1.5, (filter->SetFitSmoothing(1.5), filter->GetFitSmoothing()));
  ITK_TEST_SET_GET_VALUE(0.1, (filter->SetLevelOfDetailTolerance(0.1), filter->GetLevelOfDetailTolerance()));
  ITK_TEST_SET_GET_VALUE(12.0, (filter->SetLevelOfDetailMinimumAngle(12.0), filter->GetLevelOfDetailMinimumAngle()));
  ITK_TEST_SET_GET_VALUE(3u, (filter->SetLevelOfDetailRounds(3), filter->GetLevelOfDetailRounds()));
  ITK_TEST_SET_GET_VALUE(20.0, (filter->SetMinimumAngle(20.0), filter->GetMinimumAngle()));
  ITK_TEST_SET_GET_VALUE(1500u, (filter->SetFaceBudget(1500), filter->GetFaceBudget()));
  ITK_TEST_SET_GET_VALUE(0.8, (filter->SetMaximumTopologyRatio(0.8), filter->GetMaximumTopologyRatio()));
  ITK_TEST_SET_GET_VALUE(1.25, (filter->SetRefinementTravel(1.25), filter->GetRefinementTravel()));
  ITK_TEST_SET_GET_VALUE(4.5, (filter->SetGapSize(4.5), filter->GetGapSize()));
  // RefineChannels (on by default, issue 14) reaches the core's options, and
  // SetOption by the catalogue's name reaches the member.
  ITK_TEST_SET_GET_BOOLEAN(filter, RefineChannels, false);
  filter->RefineChannelsOff();
  ITK_TEST_SET_GET_VALUE(false, filter->GetDeformOptions().refine_channels);
  filter->SetOption("refine_channels", 1.0);
  ITK_TEST_SET_GET_VALUE(true, filter->GetRefineChannels());
  // NumberOfCoarseLevels (multi-resolution growth, off by default) reaches
  // the core's options, is clamped to [0, 4], and SetOption reaches it.
  ITK_TEST_SET_GET_VALUE(0u, filter->GetNumberOfCoarseLevels());
  ITK_TEST_SET_GET_VALUE(2u, (filter->SetNumberOfCoarseLevels(2), filter->GetNumberOfCoarseLevels()));
  ITK_TEST_SET_GET_VALUE(2, filter->GetDeformOptions().coarse_levels);
  ITK_TEST_SET_GET_VALUE(4u, (filter->SetNumberOfCoarseLevels(9), filter->GetNumberOfCoarseLevels()));
  filter->SetOption("coarse_levels", 1.0);
  ITK_TEST_SET_GET_VALUE(1u, filter->GetNumberOfCoarseLevels());
  filter->SetNumberOfCoarseLevels(0);
  // VoxelSeed (off by default) reaches the core's options, and SetOption reaches it.
  ITK_TEST_SET_GET_VALUE(false, filter->GetVoxelSeed());
  ITK_TEST_SET_GET_BOOLEAN(filter, VoxelSeed, true);
  filter->VoxelSeedOn();
  ITK_TEST_SET_GET_VALUE(true, filter->GetDeformOptions().voxel_seed);
  filter->SetOption("voxel_seed", 0.0);
  ITK_TEST_SET_GET_VALUE(false, filter->GetVoxelSeed());
  ITK_TEST_SET_GET_BOOLEAN(filter, FloatExactOutput, true);
  filter->FloatExactOutputOff();
  FilterType::PointType center;
  center[0] = 1.0;
  center[1] = -2.0;
  center[2] = 3.5;
  filter->SetSeedCenter(center);
  ITK_TEST_SET_GET_VALUE(center, filter->GetSeedCenter());
  ITK_TEST_SET_GET_VALUE(0.0, (filter->SetSeedRadius(-2.0), filter->GetSeedRadius()));
  ITK_TEST_SET_GET_VALUE(2.5, (filter->SetSeedRadius(2.5), filter->GetSeedRadius()));
  ITK_TEST_SET_GET_VALUE(4u, (filter->SetSeedSubdivisionLevel(12), filter->GetSeedSubdivisionLevel()));
  ITK_TEST_SET_GET_VALUE(2u, (filter->SetSeedSubdivisionLevel(2), filter->GetSeedSubdivisionLevel()));
  auto seed = MeshType::New();
  filter->SetSeedMesh(seed);
  ITK_TEST_SET_GET_VALUE(static_cast<const MeshType *>(seed.GetPointer()), filter->GetSeedMesh());
  filter->SetNumberOfWorkUnits(2);

  // The core options follow the parameters.
  const gdm::DeformOptions o = filter->GetDeformOptions();
  if (o.mode != gdm::Mode::shrink || o.polarity != gdm::Polarity::object_darker || o.threshold != 12.5 ||
      o.a0 != 2.0 || o.a1 != 3.0 || o.a2 != 4.0 || o.intensity_scale != 7.0 || o.reach != 1.5 ||
      o.normal_rings != 3 || o.optimizer.min_step != 0.5 || o.optimizer.max_step != 2.0 ||
      o.optimizer.max_step_reductions != 2 || o.optimizer.gradient_step != 0.2 || o.lod_face_area != 6.0 ||
      o.global_refinements != 0 || o.max_cycles != 300 || o.convergence_tolerance != 0.3 ||
      o.convergence_window != 8 || o.flip_max_dihedral != 15.0 || o.max_faces != 5000 || o.threads != 2 ||
      o.subvoxel_fit || o.fit_passes != 6 || o.fit_max_distance != 0.75 || o.fit_smoothing != 1.5 || o.lod_tolerance != 0.1 ||
      o.lod_min_angle != 12.0 || o.lod_rounds != 3 || o.max_topology_ratio != 0.8 || o.refinement_travel != 1.25 ||
      o.min_angle != 20.0 || o.face_budget != 1500 || o.float_exact_output)
  {
    std::cerr << "GetDeformOptions does not follow the parameters" << std::endl;
    return EXIT_FAILURE;
  }

  // PrintSelf names every parameter.
  std::ostringstream printed;
  filter->Print(printed);
  for (const char * name :
       { "SeedMesh", "Threshold", "Polarity", "Mode", "DeformationWeight", "ImageEventWeight", "TopologyWeight",
         "IntensityScale", "Reach", "NormalRings", "LocalFlip", "MinimumStep", "MaximumStep", "MaximumStepReductions",
         "GradientStep", "LevelOfDetailFaceArea", "LevelOfDetailTopologyExtent", "NumberOfGlobalRefinements",
         "MaximumNumberOfCycles", "ConvergenceTolerance", "ConvergenceWindow", "PreventSelfIntersection",
         "ImproveTriangles", "FlipMaximumDihedralAngle", "MaximumNumberOfFaces", "SubvoxelFit", "CurvatureCorrection", "SharpEdges", "NumberOfFitPasses",
         "FitMaximumDistance", "FitSmoothing", "LevelOfDetailTolerance", "LevelOfDetailMinimumAngle", "LevelOfDetailRounds", "MinimumAngle", "FaceBudget",
         "MaximumTopologyRatio", "RefinementTravel", "GapSize", "RefineChannels", "NumberOfCoarseLevels", "NumberOfGapClosedVoxels", "FillCavities", "NumberOfFilledCavities", "FilledCavityVolume", "NumberOfCavitiesBehindNarrowOpenings", "NumberOfCappedHandles", "FloatExactOutput", "SeedCenter", "SeedRadius",
         "SeedSubdivisionLevel", "StopReason", "NumberOfCycles", "NumberOfGlobalRefinementsPerformed",
         "NumberOfRejectedMoves", "NumberOfFlips", "NumberOfBorderVertices", "NumberOfFitMoves",
         "NumberOfLevelOfDetailSplits", "NumberOfLevelOfDetailCollapses", "NumberOfFloatRefusedVertices", "NumberOfBudgetCollapses",
         "CurrentCycle", "CurrentStage", "CurrentNumberOfVertices", "CurrentNumberOfFaces",
         "CurrentNumberOfMovingVertices", "CurrentNumberOfActiveVertices", "CurrentNumberOfSplits",
         "CurrentMeanCost" })
  {
    if (printed.str().find(std::string(name) + ":") == std::string::npos)
    {
      std::cerr << "PrintSelf does not print " << name << std::endl;
      return EXIT_FAILURE;
    }
  }
  return EXIT_SUCCESS;
}

} // namespace

TEST(itkGDMBasics, ObjectMethodsAndSetGet)
{
  EXPECT_EQ(ExerciseBasicsAndSetGet(), EXIT_SUCCESS);
}

TEST(itkGDMBasics, VolumeConversionKeepsGeometry)
{
  auto                  image = ImageType::New();
  ImageType::RegionType region;
  region.SetIndex({ { 2, -1, 3 } });
  region.SetSize({ { 4, 5, 6 } });
  image->SetRegions(region);
  image->Allocate();
  const double spacing[3] = { 0.7, 0.9, 1.6 };
  image->SetSpacing(spacing);
  const double origin[3] = { -3.0, 4.0, 10.0 };
  image->SetOrigin(origin);
  ImageType::DirectionType direction;
  direction.Fill(0.0);
  direction[0][1] = 1.0;
  direction[1][2] = -1.0;
  direction[2][0] = 1.0;
  image->SetDirection(direction);
  itk::ImageRegionIteratorWithIndex<ImageType> it(image, region);
  for (it.GoToBegin(); !it.IsAtEnd(); ++it)
  {
    const auto & i = it.GetIndex();
    it.Set(static_cast<short>(i[0] + 10 * i[1] + 100 * i[2]));
  }

  const gdm::Volume volume = itk::GDMConversion::VolumeFromImage(image.GetPointer());
  EXPECT_EQ(volume.dims()[0], 4);
  EXPECT_EQ(volume.dims()[1], 5);
  EXPECT_EQ(volume.dims()[2], 6);
  // Every voxel lands at the same physical point with the same value.
  for (it.GoToBegin(); !it.IsAtEnd(); ++it)
  {
    ImageType::PointType p;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), p);
    const gdm::Vec3 q(p[0], p[1], p[2]);
    EXPECT_NEAR(volume.sample(q), it.Get(), 1e-6);
    const gdm::Vec3 ci = volume.to_continuous_index(q);
    EXPECT_NEAR(ci.x(), it.GetIndex()[0] - region.GetIndex()[0], 1e-9);
    EXPECT_NEAR(ci.y(), it.GetIndex()[1] - region.GetIndex()[1], 1e-9);
    EXPECT_NEAR(ci.z(), it.GetIndex()[2] - region.GetIndex()[2], 1e-9);
  }
}

TEST(itkGDMBasics, MeshConversionsRoundTrip)
{
  gdm::Mesh  sphere = gdm::make_geodesic_sphere(gdm::Vec3(1.0, 2.0, 3.0), 4.0, 1);
  const auto generation = gdm::generation_property(sphere);
  for (auto v : sphere.vertices())
  {
    sphere.property(generation, v) = v.idx() % 7;
  }

  auto mesh = MeshType::New();
  itk::GDMConversion::MeshToITKMesh(sphere, mesh.GetPointer());
  EXPECT_EQ(mesh->GetNumberOfPoints(), sphere.n_vertices());
  EXPECT_EQ(mesh->GetNumberOfCells(), sphere.n_faces());
  float data = -1.0f;
  ASSERT_TRUE(mesh->GetPointData(5, &data));
  EXPECT_EQ(data, 5.0f);

  auto qe = QEMeshType::New();
  itk::GDMConversion::MeshToITKMesh(sphere, qe.GetPointer());
  EXPECT_EQ(qe->GetNumberOfPoints(), sphere.n_vertices());
  EXPECT_EQ(qe->GetNumberOfFaces(), sphere.n_faces());
  EXPECT_EQ(qe->GetNumberOfEdges(), sphere.n_edges());

  for (const gdm::Mesh & back :
       { itk::GDMConversion::MeshFromITKMesh(mesh.GetPointer()), itk::GDMConversion::MeshFromITKMesh(qe.GetPointer()) })
  {
    const gdm::MeshReport r = gdm::measure(back);
    EXPECT_EQ(r.faces, sphere.n_faces());
    EXPECT_EQ(r.vertices, sphere.n_vertices());
    EXPECT_TRUE(r.closed && r.two_manifold);
    EXPECT_EQ(r.genus, 0);
    EXPECT_NEAR(r.volume, gdm::enclosed_volume(sphere), 1e-4);  // orientation kept (float points)
  }
}

TEST(itkGDMBasics, BadInputMessages)
{
  // A 2D image.
  {
    using Image2D = itk::Image<short, 2>;
    auto                image = Image2D::New();
    Image2D::RegionType region;
    region.SetSize({ { 16, 16 } });
    image->SetRegions(region);
    image->Allocate();
    image->FillBuffer(0);
    auto filter = itk::GeometricallyDeformedModelImageToMeshFilter<Image2D, MeshType>::New();
    filter->SetInput(image);
    filter->SetThreshold(1.0);
    const std::string text = gdmtest::ExceptionText([&] { filter->Update(); });
    std::cout << "2D image: " << text << std::endl;
    EXPECT_NE(text.find("must be 3D"), std::string::npos) << text;
  }

  FilterType::PointType center;
  center.Fill(11.5);

  // An empty image.
  {
    auto                  image = ImageType::New();
    ImageType::RegionType region;
    region.SetSize({ { 0, 0, 0 } });
    image->SetRegions(region);
    image->Allocate();
    auto filter = FilterType::New();
    filter->SetInput(image);
    filter->SetThreshold(1.0);
    filter->SetSeedCenter(center);
    filter->SetSeedRadius(2.0);
    const std::string text = gdmtest::ExceptionText([&] { filter->Update(); });
    std::cout << "empty image: " << text << std::endl;
    EXPECT_NE(text.find("volume dimension"), std::string::npos) << text;
  }

  // A single slice (a 3D image with one voxel along z).
  {
    auto                  image = ImageType::New();
    ImageType::RegionType region;
    region.SetSize({ { 16, 16, 1 } });
    image->SetRegions(region);
    image->Allocate();
    image->FillBuffer(3);
    auto filter = FilterType::New();
    filter->SetInput(image);
    filter->SetThreshold(1.0);
    filter->SetSeedCenter(center);
    filter->SetSeedRadius(2.0);
    const std::string text = gdmtest::ExceptionText([&] { filter->Update(); });
    std::cout << "single slice: " << text << std::endl;
    EXPECT_NE(text.find("volume dimension"), std::string::npos) << text;
  }

  const auto image = MakeBallImage();
  auto       run = [&](const std::function<void(FilterType *)> & configure) {
    auto filter = FilterType::New();
    filter->SetInput(image);
    filter->SetThreshold(125.0);
    filter->SetSeedCenter(center);
    filter->SetSeedRadius(2.0);
    configure(filter.GetPointer());
    return gdmtest::ExceptionText([&] { filter->Update(); });
  };

  // No threshold.
  std::string text = run([](FilterType * f) { f->SetThreshold(std::numeric_limits<double>::quiet_NaN()); });
  std::cout << "no threshold: " << text << std::endl;
  EXPECT_NE(text.find("the threshold must be a finite number"), std::string::npos) << text;

  // A threshold outside the value range.
  text = run([](FilterType * f) { f->SetThreshold(1000.0); });
  std::cout << "threshold out of range: " << text << std::endl;
  EXPECT_NE(text.find("is outside the value range"), std::string::npos) << text;

  // No seed.
  text = run([](FilterType * f) { f->SetSeedRadius(0.0); });
  std::cout << "no seed: " << text << std::endl;
  EXPECT_NE(text.find("no seed"), std::string::npos) << text;

  // A seed outside the image.
  text = run([](FilterType * f) {
    FilterType::PointType far;
    far.Fill(100.0);
    f->SetSeedCenter(far);
  });
  std::cout << "seed outside the image: " << text << std::endl;
  EXPECT_NE(text.find("is outside the volume"), std::string::npos) << text;

  // A seed outside the object for the chosen polarity (in the bright ball
  // while the object is darker).
  text = run([](FilterType * f) { f->SetPolarity(FilterType::PolarityEnum::ObjectDarker); });
  std::cout << "seed outside the object: " << text << std::endl;
  EXPECT_NE(text.find("is not inside the object"), std::string::npos) << text;

  // An open seed mesh.
  text = run([](FilterType * f) {
    gdm::Mesh open = gdm::make_icosahedron(gdm::Vec3(11.5, 11.5, 11.5), 2.0);
    open.request_face_status();
    open.request_edge_status();
    open.request_vertex_status();
    open.delete_face(*open.faces_begin(), false);
    open.garbage_collection();
    auto seed = MeshType::New();
    itk::GDMConversion::MeshToITKMesh(open, seed.GetPointer());
    f->SetSeedMesh(seed);
  });
  std::cout << "open seed mesh: " << text << std::endl;
  EXPECT_NE(text.find("not closed"), std::string::npos) << text;

  // A weight the core refuses.
  text = run([](FilterType * f) { f->SetDeformationWeight(0.0); });
  std::cout << "a0 = 0: " << text << std::endl;
  EXPECT_NE(text.find("a0"), std::string::npos) << text;
}

TEST(itkGDMBasics, SeedMeshInput)
{
  const auto image = MakeBallImage();
  auto       seed = MeshType::New();
  itk::GDMConversion::MeshToITKMesh(gdm::make_geodesic_sphere(gdm::Vec3(11.5, 11.5, 11.5), 2.0, 1),
                                    seed.GetPointer());
  auto filter = FilterType::New();
  filter->SetInput(image);
  filter->SetSeedMesh(seed);
  filter->SetThreshold(125.0);
  ASSERT_NO_THROW(filter->Update());
  const gdm::Mesh        result = itk::GDMConversion::MeshFromITKMesh(filter->GetOutput());
  const gdm::MeshReport r = gdm::measure(result);
  std::cout << gdm::to_string(r) << " stop: " << filter->GetStopReason() << std::endl;
  EXPECT_TRUE(r.closed && r.two_manifold);
  EXPECT_EQ(r.genus, 0);
  EXPECT_EQ(r.self_intersections, 0u);
  // The ball has radius 6 about (11.5, 11.5, 11.5).
  double mean = 0.0;
  for (auto v : result.vertices())
  {
    mean += std::abs((gdm::to_eigen(result.point(v)) - gdm::Vec3(11.5, 11.5, 11.5)).norm() - 6.0);
  }
  mean /= static_cast<double>(result.n_vertices());
  EXPECT_LT(mean, 0.25);
}

// A filter on a ball image (MakeBallImage) with T 110 and a seed of radius
// 2.5 at (13, 13, 13).
FilterType::Pointer
MakeBallFilter(const ImageType * image)
{
  auto filter = FilterType::New();
  filter->SetInput(image);
  filter->SetThreshold(110.0);
  FilterType::PointType center;
  center.Fill(13.0);
  filter->SetSeedCenter(center);
  filter->SetSeedRadius(2.5);
  return filter;
}

// One pipeline: the filter gives the mesh gdm::extract_surface gives for the
// same volume, seed and options (the filter's float mesh holds the model's
// float-exact points, so they compare exactly).
TEST(itkGDMBasics, SameMeshAsThePipeline)
{
  const auto image = MakeBallImage(28);
  auto       filter = MakeBallFilter(image);
  filter->SetLevelOfDetailFaceArea(6.0);
  filter->SetNumberOfWorkUnits(1);
  ASSERT_NO_THROW(filter->Update());
  const gdm::Mesh fromFilter = itk::GDMConversion::MeshFromITKMesh(filter->GetOutput());

  gdm::PipelineOptions options;
  options.threshold_otsu = false;
  options.threshold = 110.0;
  options.seed.kind = gdm::SeedKind::point;
  options.seed.point = gdm::Vec3(13.0, 13.0, 13.0);
  options.seed.radius = 2.5;
  options.deform.lod_face_area = 6.0;
  options.deform.threads = 2;  // the result does not depend on it
  const gdm::PipelineResult direct =
    gdm::extract_surface(itk::GDMConversion::VolumeFromImage(image.GetPointer()), options);
  ASSERT_TRUE(direct.failure.empty()) << direct.failure;
  ASSERT_EQ(fromFilter.n_vertices(), direct.mesh.n_vertices());
  ASSERT_EQ(fromFilter.n_faces(), direct.mesh.n_faces());
  std::size_t different = 0;
  for (auto v : direct.mesh.vertices())
  {
    if (fromFilter.point(gdm::Mesh::VertexHandle(v.idx())) != direct.mesh.point(v))
    {
      ++different;
    }
  }
  EXPECT_EQ(different, 0u) << "of " << direct.mesh.n_vertices() << " vertices";
  EXPECT_EQ(filter->GetNumberOfCycles(), static_cast<itk::SizeValueType>(direct.deform.cycles));
}

// FaceBudget reaches the core: the output has about that many faces (within
// 5 %), the collapses are reported, and a budget above the face limit is refused.
TEST(itkGDMBasics, FaceBudget)
{
  auto filter = MakeBallFilter(MakeBallImage(28));
  filter->SetFaceBudget(300);
  ASSERT_NO_THROW(filter->Update());
  const double faces = static_cast<double>(filter->GetOutput()->GetNumberOfCells());
  EXPECT_NEAR(faces, 300.0, 15.0);
  EXPECT_GT(filter->GetNumberOfBudgetCollapses(), 0u);
  filter->SetMaximumNumberOfFaces(200);
  const std::string text = gdmtest::ExceptionText([&] { filter->Update(); });
  EXPECT_NE(text.find("face_budget 300 is above max_faces 200"), std::string::npos) << text;
}

// Every option of the catalogue is reachable by its name, also those without
// a Set/Get of their own; the catalogue's range is the check.
TEST(itkGDMBasics, OptionsByCatalogueName)
{
  auto filter = FilterType::New();
  filter->SetOption("lod_tolerance", 0.1);
  EXPECT_EQ(filter->GetLevelOfDetailTolerance(), 0.1);
  EXPECT_EQ(filter->GetOption("lod_tolerance"), 0.1);
  filter->SetOption("polarity", 1.0);
  EXPECT_EQ(filter->GetPolarity(), FilterType::PolarityEnum::ObjectDarker);
  for (const auto & option : gdm::deform_option_catalogue())
  {
    const double value = filter->GetOption(option.name);
    EXPECT_TRUE(gdm::accepts(option, value)) << option.name;
    EXPECT_NO_THROW(filter->SetOption(option.name, value)) << option.name;
    EXPECT_EQ(filter->GetOption(option.name), value) << option.name;
  }
  EXPECT_THROW(filter->SetOption("lod_tolerance", 0.001), itk::ExceptionObject);
  EXPECT_THROW(filter->SetOption("no_such_option", 1.0), itk::ExceptionObject);
  std::ostringstream printed;
  filter->Print(printed);
  EXPECT_NE(printed.str().find("lod_tolerance=0.1"), std::string::npos) << printed.str();
}
