// The core's pipeline steps (gdm/volume_ops.h, gdm/seeding.h: no ITK) against
// the ITK filters the gdm command used before issue 12, on the embedded
// phantom and, when present, the real tooth CT. The ITK side is a copy of
// itk-module/apps/preprocess.cxx and seeding.cxx (the reference).
#include <algorithm>
#include <array>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <string>

#include "gtest/gtest.h"

#include "itkGDMVolumeConversion.h"  // first: ITK's Eigen before the gdm headers

#include "itkBinaryThresholdImageFilter.h"
#include "itkConnectedComponentImageFilter.h"
#include "itkImageFileReader.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkOtsuThresholdImageFilter.h"
#include "itkRelabelComponentImageFilter.h"
#include "itkSignedMaurerDistanceMapImageFilter.h"
#include "itkSmoothingRecursiveGaussianImageFilter.h"
#include "itksys/SystemTools.hxx"

#include "gdm/seeding.h"
#include "gdm/volume_ops.h"

namespace
{
using Image = itk::Image<float, 3>;  // as the gdm command reads every input

struct ItkSeed
{
  std::array<long, 3> index{ 0, 0, 0 };
  double              depth = 0.0;
  std::size_t         region_voxels = 0;
  std::size_t         regions = 0;
};

// itk-module/apps/seeding.cxx find_auto_seed (the reference).
ItkSeed
ItkAutoSeed(const Image * image, double threshold, bool object_darker)
{
  using Mask = itk::Image<unsigned char, 3>;
  using Labels = itk::Image<unsigned int, 3>;
  using Distance = itk::Image<float, 3>;

  auto side = itk::BinaryThresholdImageFilter<Image, Mask>::New();
  side->SetInput(image);
  if (object_darker)
  {
    side->SetLowerThreshold(itk::NumericTraits<float>::NonpositiveMin());
    side->SetUpperThreshold(std::nextafter(static_cast<float>(threshold), -std::numeric_limits<float>::infinity()));
  }
  else
  {
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

  ItkSeed seed;
  seed.regions = relabel->GetNumberOfObjects();
  if (seed.regions == 0)
  {
    return seed;
  }
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

  const auto region = image->GetLargestPossibleRegion();
  const auto spacing = image->GetSpacing();
  double     best = -1.0;
  itk::ImageRegionConstIteratorWithIndex<Distance> it(distance->GetOutput(), region);
  for (it.GoToBegin(); !it.IsAtEnd(); ++it)
  {
    const double inside = it.Get();
    if (inside <= 0.0)
    {
      continue;
    }
    const auto idx = it.GetIndex();
    double     depth = inside;
    for (unsigned int d = 0; d < 3; ++d)
    {
      const long lo = idx[d] - region.GetIndex(d);
      const long hi = static_cast<long>(region.GetSize(d)) - 1 - lo;
      depth = std::min(depth, (static_cast<double>(std::min(lo, hi)) + 0.5) * spacing[d]);
    }
    if (depth > best)
    {
      best = depth;
      for (unsigned int d = 0; d < 3; ++d)
      {
        seed.index[d] = idx[d];
      }
    }
  }
  seed.depth = best;
  return seed;
}

// itk-module/apps/preprocess.cxx otsu_threshold and smooth.
double
ItkOtsu(const Image * image)
{
  using Mask = itk::Image<unsigned char, 3>;
  auto filter = itk::OtsuThresholdImageFilter<Image, Mask>::New();
  filter->SetInput(image);
  filter->SetNumberOfHistogramBins(256);
  filter->Update();
  return filter->GetThreshold();
}

Image::Pointer
ItkSmooth(const Image * image, double sigma_mm)
{
  auto filter = itk::SmoothingRecursiveGaussianImageFilter<Image, Image>::New();
  filter->SetInput(image);
  filter->SetSigma(sigma_mm);
  filter->Update();
  Image::Pointer out = filter->GetOutput();
  out->DisconnectPipeline();
  return out;
}

void
ExpectSameSeed(const Image * image, double threshold, gdm::Polarity polarity, const std::string & what)
{
  const bool    darker = polarity == gdm::Polarity::object_darker;
  const ItkSeed reference = ItkAutoSeed(image, threshold, darker);
  ASSERT_GT(reference.regions, 0u) << what;
  const gdm::Volume   volume = itk::GDMConversion::VolumeFromImage(image);
  const gdm::AutoSeed core = gdm::find_auto_seed(volume, threshold, polarity);
  std::cout << what << " T=" << threshold << (darker ? " darker" : " brighter") << ": ITK seed voxel ("
            << reference.index[0] << ", " << reference.index[1] << ", " << reference.index[2]
            << ") depth " << reference.depth << " mm, regions " << reference.regions << ", largest "
            << reference.region_voxels << " voxels; core (" << core.index[0] << ", " << core.index[1] << ", "
            << core.index[2] << ") depth " << core.depth << " mm, regions " << core.regions << ", largest "
            << core.region_voxels << "; depth difference " << core.depth - reference.depth << " mm" << std::endl;
  EXPECT_EQ(core.regions, reference.regions) << what;
  EXPECT_EQ(core.region_voxels, reference.region_voxels) << what;
  for (unsigned int d = 0; d < 3; ++d)
  {
    EXPECT_EQ(core.index[d], reference.index[d]) << what << " axis " << d;
  }
  EXPECT_NEAR(core.depth, reference.depth, 1e-6) << what;
  Image::PointType p;
  image->TransformIndexToPhysicalPoint({ { reference.index[0], reference.index[1], reference.index[2] } }, p);
  for (unsigned int d = 0; d < 3; ++d)
  {
    EXPECT_NEAR(core.center[d], p[d], 1e-9) << what;
  }
}

void
ExpectSameOtsu(const Image * image, const std::string & what)
{
  const double itk_t = ItkOtsu(image);
  const double core_t = gdm::otsu_threshold(itk::GDMConversion::VolumeFromImage(image), 256);
  std::cout << std::setprecision(9) << what << ": Otsu ITK " << itk_t << ", core " << core_t << " (difference " << core_t - itk_t << ")"
            << std::endl;
  EXPECT_EQ(static_cast<float>(core_t), static_cast<float>(itk_t)) << what;
}

double
ReportGaussian(const Image * image, double sigma_mm, const std::string & what)
{
  const Image::Pointer reference = ItkSmooth(image, sigma_mm);
  const gdm::Volume    volume = itk::GDMConversion::VolumeFromImage(image);
  const gdm::Volume    core = gdm::gaussian_smooth(volume, sigma_mm);
  const gdm::Volume    ref = itk::GDMConversion::VolumeFromImage(reference.GetPointer());
  double               worst = 0.0, sum = 0.0;
  for (std::size_t i = 0; i < core.voxel_count(); ++i)
  {
    const double d = std::abs(static_cast<double>(core.values()[i]) - ref.values()[i]);
    worst = std::max(worst, d);
    sum += d;
  }
  const double range = volume.max_value() - volume.min_value();
  std::cout << what << ": Gaussian sigma " << sigma_mm << " mm, core vs ITK recursive: max |difference| " << worst
            << " (" << 100.0 * worst / range << "% of the range " << range << "), mean "
            << sum / static_cast<double>(core.voxel_count()) << std::endl;
  return worst / range;
}

std::string
PhantomFile()
{
  return std::string(GDM_DATA_DIR) + "/phantom.mha";
}

std::string
ToothFile()
{
  return std::string(GDM_SHARED_DIR) + "/data/tooth/tooth.mhd";
}

} // namespace

TEST(itkGDMPipelineCrossCheck, PhantomOtsuSeedAndGaussianMatchITK)
{
  const auto image = itk::ReadImage<Image>(PhantomFile());
  ExpectSameOtsu(image, "phantom");
  ExpectSameSeed(image, 400.0, gdm::Polarity::object_brighter, "phantom");
  EXPECT_LT(ReportGaussian(image, 1.0, "phantom"), 0.02);
  // The smoothed phantom: non-integer values for Otsu's bins and the seed.
  const Image::Pointer smoothed = ItkSmooth(image, 1.0);
  ExpectSameOtsu(smoothed, "phantom smoothed by ITK");
  ExpectSameSeed(smoothed, 400.0, gdm::Polarity::object_brighter, "phantom smoothed by ITK");
}

TEST(itkGDMPipelineCrossCheck, ToothOtsuSeedAndGaussianMatchITK)
{
  if (!itksys::SystemTools::FileExists(ToothFile()))
  {
    GTEST_SKIP() << "tooth data not found at " << ToothFile()
                 << " (set GDM_SHARED_DIR to the folder holding data/tooth)";
  }
  const auto image = itk::ReadImage<Image>(ToothFile());
  ExpectSameOtsu(image, "tooth");
  ExpectSameSeed(image, 115.0, gdm::Polarity::object_darker, "tooth");
  ExpectSameSeed(image, 115.0, gdm::Polarity::object_brighter, "tooth");
  EXPECT_LT(ReportGaussian(image, 1.0, "tooth"), 0.02);
  const Image::Pointer smoothed = ItkSmooth(image, 1.0);
  ExpectSameOtsu(smoothed, "tooth smoothed by ITK");
  ExpectSameSeed(smoothed, 115.0, gdm::Polarity::object_darker, "tooth smoothed by ITK");
}
