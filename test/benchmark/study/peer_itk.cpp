// ITK part of the benchmark study (see peer_itk.h). No gdm, VTK or CGAL header here.
#include "peer_itk.h"

#include <chrono>
#include <cmath>
#include <map>
#include <stdexcept>

#include "itkBinaryMask3DMeshSource.h"
#include "itkBinaryThresholdImageFilter.h"
#include "itkDeformableSimplexMesh3DBalloonForceFilter.h"
#include "itkFlipImageFilter.h"
#include "itkGDCMImageIO.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkGradientMagnitudeRecursiveGaussianImageFilter.h"
#include "itkGradientRecursiveGaussianImageFilter.h"
#include "itkImage.h"
#include "itkImageFileReader.h"
#include "itkImageSeriesReader.h"
#include "itkMesh.h"
#include "itkMultiThreaderBase.h"
#include "itkRegularSphereMeshSource.h"
#include "itkRescaleIntensityImageFilter.h"
#include "itkSimplexMesh.h"
#include "itkSimplexMeshToTriangleMeshFilter.h"
#include "itkTriangleCell.h"
#include "itkTriangleMeshToSimplexMeshFilter.h"
#include "itksys/SystemTools.hxx"

namespace study {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

using FloatImage = itk::Image<float, 3>;
using TriangleMesh = itk::Mesh<double, 3>;

FloatImage::Pointer to_itk(const Image& image, bool index_space) {
  auto out = FloatImage::New();
  FloatImage::RegionType region;
  FloatImage::SizeType size;
  for (int a = 0; a < 3; ++a) size[a] = static_cast<itk::SizeValueType>(image.dims[a]);
  region.SetSize(size);
  out->SetRegions(region);
  FloatImage::SpacingType spacing;
  FloatImage::PointType origin;
  for (int a = 0; a < 3; ++a) {
    spacing[a] = index_space ? 1.0 : image.spacing[a];
    origin[a] = index_space ? 0.0 : image.origin[a];
  }
  out->SetSpacing(spacing);
  out->SetOrigin(origin);
  out->Allocate();
  std::copy(image.values.begin(), image.values.end(), out->GetBufferPointer());
  return out;
}

// Triangles of an itk::Mesh whose cells are triangles; points mapped by `map`.
template <typename TMesh, typename Map>
Surface to_surface(const TMesh* mesh, Map map) {
  Surface s;
  const auto* points = mesh->GetPoints();
  std::vector<int> index_of;
  // Point identifiers may not be contiguous: renumber.
  std::map<typename TMesh::PointIdentifier, int> ids;
  for (auto it = points->Begin(); it != points->End(); ++it) {
    ids[it.Index()] = static_cast<int>(s.points.size());
    const auto& p = it.Value();
    s.points.push_back(map(Point{p[0], p[1], p[2]}));
  }
  for (auto it = mesh->GetCells()->Begin(); it != mesh->GetCells()->End(); ++it) {
    const auto* cell = it.Value();
    if (cell->GetNumberOfPoints() != 3) continue;
    auto pid = cell->PointIdsBegin();
    s.faces.push_back({ids.at(pid[0]), ids.at(pid[1]), ids.at(pid[2])});
  }
  return s;
}

}  // namespace

void set_itk_threads(int threads) { itk::MultiThreaderBase::SetGlobalDefaultNumberOfThreads(threads); }

PeerResult run_itk_binary_mask(const Image& image, double threshold, bool object_brighter) {
  auto input = to_itk(image, false);
  using MaskImage = itk::Image<unsigned char, 3>;
  auto threshold_filter = itk::BinaryThresholdImageFilter<FloatImage, MaskImage>::New();
  threshold_filter->SetInput(input);
  if (object_brighter) {
    threshold_filter->SetLowerThreshold(static_cast<float>(std::nextafter(threshold, 1e30)));
  } else {
    threshold_filter->SetUpperThreshold(static_cast<float>(std::nextafter(threshold, -1e30)));
  }
  threshold_filter->SetInsideValue(1);
  threshold_filter->SetOutsideValue(0);
  auto source = itk::BinaryMask3DMeshSource<MaskImage, TriangleMesh>::New();
  source->SetInput(threshold_filter->GetOutput());
  source->SetObjectValue(1);
  const auto t0 = Clock::now();
  source->Update();
  PeerResult r;
  r.seconds = seconds_since(t0);
  r.surface = to_surface(source->GetOutput(), [](const Point& p) { return p; });
  return r;
}

PeerResult run_itk_simplex(const Image& image, const Point& seed, const SimplexOptions& o) {
  auto input = to_itk(image, true);
  // ITK's simplex filters need the triangle mesh's coordinate type to be the simplex mesh's (float here).
  using SimplexMesh = itk::SimplexMesh<float, 3>;
  using FloatMesh = itk::Mesh<float, 3>;
  using GradientImage = itk::Image<itk::CovariantVector<float, 3>, 3>;
  const auto t0 = Clock::now();
  // Edge map: Gaussian gradient magnitude scaled to [0, 1]; its gradient pulls towards edges.
  auto magnitude = itk::GradientMagnitudeRecursiveGaussianImageFilter<FloatImage, FloatImage>::New();
  magnitude->SetInput(input);
  magnitude->SetSigma(o.sigma);
  auto rescale = itk::RescaleIntensityImageFilter<FloatImage, FloatImage>::New();
  rescale->SetInput(magnitude->GetOutput());
  rescale->SetOutputMinimum(0.0f);
  rescale->SetOutputMaximum(1.0f);
  auto gradient = itk::GradientRecursiveGaussianImageFilter<FloatImage, GradientImage>::New();
  gradient->SetInput(rescale->GetOutput());
  gradient->SetSigma(o.sigma);
  gradient->Update();

  using SphereSource = itk::RegularSphereMeshSource<FloatMesh>;
  auto sphere = SphereSource::New();
  SphereSource::PointType center;
  SphereSource::VectorType scale;
  for (int a = 0; a < 3; ++a) {
    center[a] = (seed[a] - image.origin[a]) / image.spacing[a];
    scale[a] = o.radii[a];
  }
  sphere->SetCenter(center);
  sphere->SetScale(scale);
  sphere->SetResolution(static_cast<unsigned int>(o.resolution));
  auto to_simplex = itk::TriangleMeshToSimplexMeshFilter<FloatMesh, SimplexMesh>::New();
  to_simplex->SetInput(sphere->GetOutput());
  auto deform = itk::DeformableSimplexMesh3DBalloonForceFilter<SimplexMesh, SimplexMesh>::New();
  deform->SetInput(to_simplex->GetOutput());
  deform->SetGradient(gradient->GetOutput());
  deform->SetAlpha(o.alpha);
  deform->SetBeta(o.beta);
  deform->SetGamma(o.gamma);
  deform->SetKappa(o.kappa);
  deform->SetRigidity(1);
  deform->SetIterations(o.iterations);
  auto to_triangles = itk::SimplexMeshToTriangleMeshFilter<SimplexMesh, FloatMesh>::New();
  to_triangles->SetInput(deform->GetOutput());
  to_triangles->Update();
  PeerResult r;
  r.seconds = seconds_since(t0);
  r.surface = to_surface(to_triangles->GetOutput(), [&](const Point& p) {
    return Point{image.origin[0] + image.spacing[0] * p[0], image.origin[1] + image.spacing[1] * p[1],
                 image.origin[2] + image.spacing[2] * p[2]};
  });
  r.note = std::to_string(o.iterations) + " iterations, resolution " + std::to_string(o.resolution);
  return r;
}

Image read_scan(const std::string& path) {
  FloatImage::Pointer image;
  try {
    if (itksys::SystemTools::FileIsDirectory(path)) {
      auto names = itk::GDCMSeriesFileNames::New();
      names->SetUseSeriesDetails(true);
      names->SetDirectory(path);
      const auto series = names->GetSeriesUIDs();
      if (series.empty()) throw std::runtime_error("no DICOM series in " + path);
      auto reader = itk::ImageSeriesReader<FloatImage>::New();
      reader->SetImageIO(itk::GDCMImageIO::New());
      reader->SetFileNames(names->GetFileNames(series.front()));
      reader->Update();
      image = reader->GetOutput();
    } else {
      image = itk::ReadImage<FloatImage>(path);
    }
  } catch (const itk::ExceptionObject& e) {
    throw std::runtime_error("cannot read " + path + ": " + e.GetDescription());
  }
  // Undo axis flips so that the grid is axis aligned with positive spacing.
  const auto dir = image->GetDirection();
  itk::FixedArray<bool, 3> flip;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b)
      if (a != b && std::abs(dir[a][b]) > 1e-3)
        throw std::runtime_error(path + ": oblique or permuted direction cosines are not supported by the study");
    flip[a] = dir[a][a] < 0;
  }
  auto flipper = itk::FlipImageFilter<FloatImage>::New();
  flipper->SetInput(image);
  flipper->SetFlipAxes(flip);
  flipper->SetFlipAboutOrigin(false);
  flipper->Update();
  FloatImage::Pointer out = flipper->GetOutput();
  Image result;
  const auto size = out->GetLargestPossibleRegion().GetSize();
  FloatImage::PointType first;
  out->TransformIndexToPhysicalPoint(out->GetLargestPossibleRegion().GetIndex(), first);
  for (int a = 0; a < 3; ++a) {
    result.dims[a] = static_cast<int>(size[a]);
    result.spacing[a] = out->GetSpacing()[a];
    result.origin[a] = first[a];
  }
  const auto* buffer = out->GetBufferPointer();
  result.values.assign(buffer, buffer + out->GetLargestPossibleRegion().GetNumberOfPixels());
  return result;
}

}  // namespace study
