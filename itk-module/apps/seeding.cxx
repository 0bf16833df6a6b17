#include "seeding.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "itkBinaryThresholdImageFilter.h"
#include "itkConnectedComponentImageFilter.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkLinearInterpolateImageFunction.h"
#include "itkRelabelComponentImageFilter.h"
#include "itkSignedMaurerDistanceMapImageFilter.h"

#include "cli_errors.h"

namespace gdm_cli {

double voxel_size(const Image* image) {
  const auto s = image->GetSpacing();
  return std::min({s[0], s[1], s[2]});
}

AutoSeed find_auto_seed(const Image* image, double threshold, bool object_darker) {
  using Mask = itk::Image<unsigned char, 3>;
  using Labels = itk::Image<unsigned int, 3>;
  using Distance = itk::Image<float, 3>;

  // The object side of T (strictly beyond it, as the core's image event).
  auto side = itk::BinaryThresholdImageFilter<Image, Mask>::New();
  side->SetInput(image);
  if (object_darker) {
    side->SetLowerThreshold(itk::NumericTraits<float>::NonpositiveMin());
    side->SetUpperThreshold(std::nextafter(static_cast<float>(threshold), -std::numeric_limits<float>::infinity()));
  } else {
    side->SetLowerThreshold(std::nextafter(static_cast<float>(threshold), std::numeric_limits<float>::infinity()));
    side->SetUpperThreshold(itk::NumericTraits<float>::max());
  }
  side->SetInsideValue(1);
  side->SetOutsideValue(0);

  auto components = itk::ConnectedComponentImageFilter<Mask, Labels>::New();
  components->SetInput(side->GetOutput());
  components->SetFullyConnected(false);
  auto relabel = itk::RelabelComponentImageFilter<Labels, Labels>::New();
  relabel->SetInput(components->GetOutput());
  relabel->Update();

  AutoSeed seed;
  seed.regions = relabel->GetNumberOfObjects();
  if (seed.regions == 0)
    throw UsageError("--seed auto: no voxel is " + std::string(object_darker ? "below" : "above") +
                     " the threshold " + std::to_string(threshold) + "; check --threshold and --polarity");
  seed.region_voxels = relabel->GetSizeOfObjectsInPixels()[0];

  auto largest = itk::BinaryThresholdImageFilter<Labels, Mask>::New();
  largest->SetInput(relabel->GetOutput());
  largest->SetLowerThreshold(1);
  largest->SetUpperThreshold(1);
  largest->SetInsideValue(1);
  largest->SetOutsideValue(0);
  auto distance = itk::SignedMaurerDistanceMapImageFilter<Mask, Distance>::New();
  distance->SetInput(largest->GetOutput());
  distance->SetUseImageSpacing(true);
  distance->SetInsideIsPositive(true);
  distance->SetSquaredDistance(false);
  distance->Update();

  // The deepest voxel, also counting the volume's border as boundary (the
  // distance map does not); the first in raster order on ties.
  const auto region = image->GetLargestPossibleRegion();
  const auto spacing = image->GetSpacing();
  double best = -1.0;
  itk::ImageRegionConstIteratorWithIndex<Distance> it(distance->GetOutput(), region);
  for (it.GoToBegin(); !it.IsAtEnd(); ++it) {
    const double inside = it.Get();
    if (inside <= 0.0) continue;
    const auto idx = it.GetIndex();
    double depth = inside;
    for (unsigned int d = 0; d < 3; ++d) {
      const long lo = idx[d] - region.GetIndex(d);
      const long hi = static_cast<long>(region.GetSize(d)) - 1 - lo;
      depth = std::min(depth, (static_cast<double>(std::min(lo, hi)) + 0.5) * spacing[d]);
    }
    if (depth > best) {
      best = depth;
      for (unsigned int d = 0; d < 3; ++d) seed.index[d] = idx[d];
    }
  }
  if (best <= 0.0) throw UsageError("--seed auto: the largest object region has no interior voxel");
  seed.depth = best;
  seed.radius = 0.5 * best;
  seed.center = index_to_point(image, seed.index);
  return seed;
}

std::array<double, 3> index_to_point(const Image* image, const std::array<long, 3>& index) {
  Image::IndexType i;
  for (unsigned int d = 0; d < 3; ++d) i[d] = index[d];
  Image::PointType p;
  image->TransformIndexToPhysicalPoint(i, p);
  return {p[0], p[1], p[2]};
}

bool inside_volume(const Image* image, const std::array<double, 3>& point) {
  Image::PointType p;
  for (unsigned int d = 0; d < 3; ++d) p[d] = point[d];
  itk::ContinuousIndex<double, 3> ci;
  image->TransformPhysicalPointToContinuousIndex(p, ci);
  const auto region = image->GetLargestPossibleRegion();
  for (unsigned int d = 0; d < 3; ++d) {
    const double lo = static_cast<double>(region.GetIndex(d));
    const double hi = lo + static_cast<double>(region.GetSize(d)) - 1.0;
    if (!(ci[d] >= lo && ci[d] <= hi)) return false;
  }
  return true;
}

double value_at(const Image* image, const std::array<double, 3>& point) {
  auto interpolator = itk::LinearInterpolateImageFunction<Image, double>::New();
  interpolator->SetInputImage(image);
  Image::PointType p;
  for (unsigned int d = 0; d < 3; ++d) p[d] = point[d];
  itk::ContinuousIndex<double, 3> ci;
  image->TransformPhysicalPointToContinuousIndex(p, ci);
  return interpolator->EvaluateAtContinuousIndex(ci);
}

SurfaceMesh volume_box(const Image* image) {
  const auto region = image->GetLargestPossibleRegion();
  SurfaceMesh box;
  for (int corner = 0; corner < 8; ++corner) {
    itk::ContinuousIndex<double, 3> ci;
    for (unsigned int d = 0; d < 3; ++d) {
      const double lo = static_cast<double>(region.GetIndex(d));
      const double hi = lo + static_cast<double>(region.GetSize(d)) - 1.0;
      ci[d] = (corner >> d) & 1 ? hi - 1.0 : lo + 1.0;
    }
    Image::PointType p;
    image->TransformContinuousIndexToPhysicalPoint(ci, p);
    box.points.push_back({p[0], p[1], p[2]});
  }
  // Corner c has bit d set when it is at the high end of axis d.
  box.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
               {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  // Outward in physical space: flip when the direction cosines mirror.
  double volume = 0.0;
  for (const auto& f : box.faces) {
    const auto& a = box.points[f[0]];
    const auto& b = box.points[f[1]];
    const auto& c = box.points[f[2]];
    volume += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  }
  if (volume < 0.0)
    for (auto& f : box.faces) std::swap(f[1], f[2]);
  box.generation.assign(box.points.size(), 0);
  return box;
}

}  // namespace gdm_cli
