// ITK side of the plugin: volume files and DICOM series into gdm::Volume.
// ITK's headers come first: ITK carries its own Eigen 3.3, which must be seen
// before the system Eigen 3.4 that the gdm headers include.
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

#include <itkGDCMImageIO.h>
#include <itkGDCMSeriesFileNames.h>
#include <itkImage.h>
#include <itkImageFileReader.h>
#include <itkImageIOFactory.h>
#include <itkImageSeriesReader.h>

#ifdef GDM_HAVE_ITK_VOLUME_CONVERSION
#include "itkGDMVolumeConversion.h"
#endif

#include "gdm/errors.h"
#include "volume_io.h"

namespace gdm_meshlab {
namespace {

using Image = itk::Image<float, 3>;

bool is_directory(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool exists(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0;
}

gdm::Volume convert(const Image* image) {
#ifdef GDM_HAVE_ITK_VOLUME_CONVERSION
  return itk::GDMConversion::VolumeFromImage<float>(image);
#else
  const auto size = image->GetLargestPossibleRegion().GetSize();
  const gdm::Index3 dims{static_cast<int>(size[0]), static_cast<int>(size[1]), static_cast<int>(size[2])};
  const std::size_t n = size[0] * size[1] * size[2];
  const float* buffer = image->GetBufferPointer();
  std::vector<float> values(buffer, buffer + n);
  gdm::Vec3 spacing, origin;
  Eigen::Matrix3d direction;
  for (int i = 0; i < 3; ++i) {
    spacing[i] = image->GetSpacing()[i];
    origin[i] = image->GetOrigin()[i];
    for (int j = 0; j < 3; ++j) direction(i, j) = image->GetDirection()(i, j);
  }
  return gdm::Volume(dims, std::move(values), spacing, origin, direction);
#endif
}

Image::Pointer read_file(const std::string& path) {
  auto io = itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::ImageIOFactory::FileModeEnum::ReadMode);
  if (!io) throw std::runtime_error("no ITK reader recognises the volume file '" + path +
                                    "' (expected .mha, .mhd, .nrrd, .nhdr, .nii, .nii.gz or a DICOM directory)");
  io->SetFileName(path);
  io->ReadImageInformation();
  if (io->GetNumberOfDimensions() != 3)
    throw std::runtime_error("the volume file '" + path + "' has " + std::to_string(io->GetNumberOfDimensions()) +
                             " dimensions; a 3D volume is needed");
  if (io->GetNumberOfComponents() != 1)
    throw std::runtime_error("the volume file '" + path + "' has " + std::to_string(io->GetNumberOfComponents()) +
                             " components per voxel; a scalar volume is needed");
  auto reader = itk::ImageFileReader<Image>::New();
  reader->SetFileName(path);
  reader->Update();
  return reader->GetOutput();
}

Image::Pointer read_dicom_directory(const std::string& path, std::string* series_note) {
  auto names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(true);
  names->SetDirectory(path);
  const auto& uids = names->GetSeriesUIDs();
  if (uids.empty())
    throw std::runtime_error("the directory '" + path + "' holds no DICOM series");
  const auto files = names->GetFileNames(uids.front());
  if (files.size() < 2)
    throw std::runtime_error("the DICOM series in '" + path + "' has fewer than two slices");
  auto reader = itk::ImageSeriesReader<Image>::New();
  reader->SetImageIO(itk::GDCMImageIO::New());
  reader->SetFileNames(files);
  reader->Update();
  std::ostringstream s;
  s << "DICOM series " << uids.front() << " (" << files.size() << " slices";
  if (uids.size() > 1) s << "; " << uids.size() - 1 << " other series ignored";
  s << ")";
  *series_note = s.str();
  return reader->GetOutput();
}

}  // namespace

gdm::Volume read_volume(const std::string& path, std::string* description) {
  if (path.empty()) throw std::runtime_error("no volume file given (parameter VolumeFile is empty)");
  if (!exists(path)) throw std::runtime_error("the volume file '" + path + "' does not exist");
  Image::Pointer image;
  std::string source = "file";
  try {
    image = is_directory(path) ? read_dicom_directory(path, &source) : read_file(path);
  } catch (const itk::ExceptionObject& e) {
    throw std::runtime_error("ITK could not read the volume '" + path + "': " + e.GetDescription());
  }
  gdm::Volume volume = convert(image.GetPointer());
  if (description) {
    std::ostringstream s;
    s << "read " << source << " '" << path << "': " << volume.dims()[0] << " x " << volume.dims()[1] << " x "
      << volume.dims()[2] << " voxels, spacing " << volume.spacing().x() << " x " << volume.spacing().y() << " x "
      << volume.spacing().z() << " mm, values [" << volume.min_value() << ", " << volume.max_value() << "]";
    *description = s.str();
  }
  return volume;
}

}  // namespace gdm_meshlab
