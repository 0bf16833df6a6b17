// The real tooth CT: the pulp chamber grown from a seed, compared with the
// marching-cubes iso-surface at the same threshold.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <iostream>
#include <vector>

#include "gtest/gtest.h"

#include "itkBinaryMask3DMeshSource.h"
#include "itkGDMVolumeConversion.h"
#include "itkGeometricallyDeformedModelImageToMeshFilter.h"
#include "itkImageFileReader.h"
#include "itkMesh.h"
#include "itksys/SystemTools.hxx"

#include "gdm/mesh_checks.h"
#include "gdm/phantoms.h"
#include "gdm/triangle_locator.h"

namespace
{
using ImageType = itk::Image<unsigned char, 3>;
using MeshType = itk::Mesh<float, 3>;
using Vec3 = gdm::Vec3;

constexpr double kThreshold = 115.0;

} // namespace

TEST(itkGDMTooth, PulpChamberAgainstMarchingCubes)
{
  const std::string file = std::string(GDM_SHARED_DIR) + "/data/tooth/tooth.mhd";
  if (!itksys::SystemTools::FileExists(file))
  {
    GTEST_SKIP() << "tooth data not found at " << file << " (set GDM_SHARED_DIR to the folder holding data/tooth)";
  }
  const auto image = itk::ReadImage<ImageType>(file);

  // The GDM, grown from the pulp chamber; the pulp is darker than the dentin.
  using FilterType = itk::GeometricallyDeformedModelImageToMeshFilter<ImageType, MeshType>;
  auto                  filter = FilterType::New();
  ImageType::PointType seed;
  image->TransformIndexToPhysicalPoint({ { 50, 47, 95 } }, seed);
  filter->SetInput(image);
  filter->SetThreshold(kThreshold);
  filter->SetPolarity(FilterType::PolarityEnum::ObjectDarker);
  FilterType::PointType center;
  center.CastFrom(seed);
  filter->SetSeedCenter(center);
  filter->SetSeedRadius(2.0);
  const auto start = std::chrono::steady_clock::now();
  ASSERT_NO_THROW(filter->Update());
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

  const gdm::Mesh        mesh = itk::GDMConversion::MeshFromITKMesh(filter->GetOutput());
  const gdm::MeshReport r = gdm::measure(mesh);
  EXPECT_TRUE(r.closed);
  EXPECT_TRUE(r.two_manifold);
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.self_intersections, 0u);
  EXPECT_EQ(filter->GetNumberOfBorderVertices(), 0u);

  // The pulp: the 6-connected voxels below the threshold reached from the seed
  // voxel. Everything else is set above the threshold, so that marching cubes
  // sees only the pulp's iso-surface.
  const auto *            values = image->GetBufferPointer();
  const std::vector<char> pulp =
    gdm::phantoms::region_below(itk::GDMConversion::VolumeFromImage(image.GetPointer()), { 50, 47, 95 }, kThreshold);
  auto masked = ImageType::New();
  masked->CopyInformation(image);
  masked->SetRegions(image->GetLargestPossibleRegion());
  masked->Allocate();
  auto mask = ImageType::New();
  mask->CopyInformation(image);
  mask->SetRegions(image->GetLargestPossibleRegion());
  mask->Allocate();
  for (std::size_t i = 0; i < pulp.size(); ++i)
  {
    masked->GetBufferPointer()[i] = pulp[i] ? values[i] : 255;
    mask->GetBufferPointer()[i] = pulp[i] ? 1 : 0;
  }

  // ITK's marching cubes on the pulp mask puts its vertices half-way along grid
  // edges; moving each to the linearly interpolated threshold crossing on its
  // edge gives the iso-surface at the threshold.
  using MCType = itk::BinaryMask3DMeshSource<ImageType, MeshType>;
  auto mc = MCType::New();
  mc->SetInput(mask);
  mc->SetObjectValue(1);
  mc->Update();
  const MeshType * mcMesh = mc->GetOutput();
  std::vector<Vec3> mcPoints(mcMesh->GetNumberOfPoints());
  std::size_t       snapped = 0;
  for (auto it = mcMesh->GetPoints()->Begin(); it != mcMesh->GetPoints()->End(); ++it)
  {
    itk::ContinuousIndex<double, 3> ci;
    image->TransformPhysicalPointToContinuousIndex(it.Value(), ci);
    Vec3 p(it.Value()[0], it.Value()[1], it.Value()[2]);
    int  halfAxis = -1, halves = 0;
    for (int d = 0; d < 3; ++d)
    {
      if (std::abs(ci[d] - std::floor(ci[d]) - 0.5) < 1e-6)
      {
        halfAxis = d;
        ++halves;
      }
    }
    if (halves == 1)
    {
      ImageType::IndexType a, b;
      for (int d = 0; d < 3; ++d)
      {
        a[d] = b[d] = std::lround(ci[d]);
      }
      a[halfAxis] = static_cast<long>(std::floor(ci[halfAxis]));
      b[halfAxis] = a[halfAxis] + 1;
      if (image->GetLargestPossibleRegion().IsInside(a) && image->GetLargestPossibleRegion().IsInside(b))
      {
        const double va = masked->GetPixel(a), vb = masked->GetPixel(b);
        if ((va - kThreshold) * (vb - kThreshold) < 0.0)
        {
          const double           t = (kThreshold - va) / (vb - va);
          itk::ContinuousIndex<double, 3> q = ci;
          q[halfAxis] = a[halfAxis] + t;
          ImageType::PointType pp;
          image->TransformContinuousIndexToPhysicalPoint(q, pp);
          p = Vec3(pp[0], pp[1], pp[2]);
          ++snapped;
        }
      }
    }
    mcPoints[it.Index()] = p;
  }
  std::vector<std::array<Vec3, 3>> triangles;
  for (auto it = mcMesh->GetCells()->Begin(); it != mcMesh->GetCells()->End(); ++it)
  {
    if (it.Value()->GetNumberOfPoints() != 3)
      continue;
    const auto * ids = it.Value()->GetPointIds();
    triangles.push_back({ mcPoints[ids[0]], mcPoints[ids[1]], mcPoints[ids[2]] });
  }
  const std::size_t itkMcFaces = triangles.size();
  const gdm::Volume maskedVolume = itk::GDMConversion::VolumeFromImage(masked.GetPointer());
  const std::size_t mcFaces = gdm::phantoms::marching_cubes_triangle_count(maskedVolume, kThreshold);

  const double           voxel = maskedVolume.voxel_size();
  const gdm::TriangleLocator mcSurface(std::move(triangles));
  double                 mean = 0.0, worst = 0.0;
  for (auto v : mesh.vertices())
  {
    const double d = mcSurface.distance(gdm::to_eigen(mesh.point(v))) / voxel;
    mean += d;
    worst = std::max(worst, d);
  }
  mean /= static_cast<double>(mesh.n_vertices());

  std::cout << "tooth pulp: " << gdm::to_string(r) << "\n  stop: " << filter->GetStopReason() << ", cycles "
            << filter->GetNumberOfCycles() << ", " << seconds << " s"
            << "\n  marching cubes: " << mcFaces << " faces (classic MC count), " << itkMcFaces
            << " faces (itk::BinaryMask3DMeshSource, " << snapped << " of " << mcPoints.size()
            << " vertices moved to the crossing)"
            << "\n  GDM vertex to MC surface: mean " << mean << " voxel, max " << worst << " voxel; GDM faces "
            << r.faces << " = " << static_cast<double>(r.faces) / mcFaces << " of MC" << std::endl;
  EXPECT_LE(mean, 0.5);
  EXPECT_LE(r.faces, mcFaces / 2);
}
