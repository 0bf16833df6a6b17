// The command line's reading: gdm::read_volume (gdm/image_io.h) does the
// reading and every check; this maps its errors onto the CLI's exit codes and
// hands the volume on as an ITK image.
#include "itkSymmetricEigenAnalysis.h"  // ITK's Eigen before the system one (gdm headers)

#include "image_input.h"

#include <algorithm>

#include "itkMinimumMaximumImageCalculator.h"

#include "cli_errors.h"
#include "gdm/image_io.h"

namespace gdm_cli {

void describe_image(const Image* image, InputInfo& info) {
  const auto region = image->GetLargestPossibleRegion();
  for (unsigned int d = 0; d < 3; ++d) {
    info.size[d] = region.GetSize()[d];
    info.spacing[d] = image->GetSpacing()[d];
    info.origin[d] = image->GetOrigin()[d];
    for (unsigned int c = 0; c < 3; ++c) info.direction[3 * d + c] = image->GetDirection()[d][c];
  }
  auto calculator = itk::MinimumMaximumImageCalculator<Image>::New();
  calculator->SetImage(image);
  calculator->Compute();
  info.minimum = calculator->GetMinimum();
  info.maximum = calculator->GetMaximum();
}

Image::Pointer read_input(const std::string& path, const std::string& series_uid, InputInfo& info,
                          std::ostream& log) {
  info.path = path;
  gdm::ReadOptions options;
  options.series_uid = series_uid;
  gdm::ImageInfo read;
  gdm::Volume volume;
  try {
    volume = gdm::read_volume(path, options, &read);
  } catch (const gdm::InvalidOption& e) {
    throw UsageError("--series " + series_uid + ": " + e.what());
  } catch (const gdm::Error& e) {
    throw InputError(e.what());
  }
  if (read.series_count > 1 && series_uid.empty())
    log << "the folder holds " << read.series_count << " DICOM series; using the one with most slices ("
        << read.slices << "): " << read.series_uid << " (choose another with --series UID)\n";
  for (const auto& warning : read.warnings) log << "warning: " << warning << "\n";
  info.format = read.format;
  info.series_uid = read.series_uid;
  info.files = read.slices;
  info.series_count = read.series_count;
  info.pixel_type = read.pixel_type;

  auto image = Image::New();
  Image::SizeType size;
  Image::SpacingType spacing;
  Image::PointType origin;
  Image::DirectionType direction;
  for (unsigned int d = 0; d < 3; ++d) {
    size[d] = read.dims[d];
    spacing[d] = read.spacing[d];
    origin[d] = read.origin[d];
    for (unsigned int c = 0; c < 3; ++c) direction[d][c] = read.direction[3 * d + c];
  }
  image->SetRegions(Image::RegionType(size));
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(direction);
  image->Allocate();
  std::copy(volume.values().begin(), volume.values().end(), image->GetBufferPointer());
  describe_image(image, info);
  return image;
}

}  // namespace gdm_cli
