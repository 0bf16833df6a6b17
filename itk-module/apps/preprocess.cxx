#include "preprocess.h"

#include <sstream>

#include "itkOtsuThresholdImageFilter.h"
#include "itkRegionOfInterestImageFilter.h"
#include "itkSmoothingRecursiveGaussianImageFilter.h"

#include "cli_errors.h"

namespace gdm_cli {

Image::Pointer crop(const Image* image, const std::array<long, 6>& box) {
  const auto whole = image->GetLargestPossibleRegion();
  Image::RegionType region;
  for (unsigned int d = 0; d < 3; ++d) {
    region.SetIndex(d, whole.GetIndex(d) + box[d]);
    region.SetSize(d, static_cast<Image::SizeValueType>(box[d + 3] - box[d] + 1));
  }
  if (!whole.IsInside(region)) {
    std::ostringstream s;
    s << "--roi is not inside the volume (size " << whole.GetSize()[0] << " x " << whole.GetSize()[1] << " x "
      << whole.GetSize()[2] << " voxels; indices start at 0)";
    throw UsageError(s.str());
  }
  for (unsigned int d = 0; d < 3; ++d)
    if (region.GetSize(d) < 2) throw UsageError("--roi must span at least 2 voxels along every axis");
  auto filter = itk::RegionOfInterestImageFilter<Image, Image>::New();
  filter->SetInput(image);
  filter->SetRegionOfInterest(region);
  filter->Update();
  Image::Pointer out = filter->GetOutput();
  out->DisconnectPipeline();
  return out;
}

Image::Pointer smooth(const Image* image, double sigma_mm) {
  auto filter = itk::SmoothingRecursiveGaussianImageFilter<Image, Image>::New();
  filter->SetInput(image);
  filter->SetSigma(sigma_mm);
  try {
    filter->Update();
  } catch (const itk::ExceptionObject& e) {
    throw InputError(std::string("Gaussian smoothing failed (every axis needs at least 4 voxels): ") + e.GetDescription());
  }
  Image::Pointer out = filter->GetOutput();
  out->DisconnectPipeline();
  return out;
}

double otsu_threshold(const Image* image) {
  using Mask = itk::Image<unsigned char, 3>;
  auto filter = itk::OtsuThresholdImageFilter<Image, Mask>::New();
  filter->SetInput(image);
  filter->SetNumberOfHistogramBins(256);
  filter->Update();
  return filter->GetThreshold();
}

}  // namespace gdm_cli
