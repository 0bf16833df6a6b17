#include <sys/stat.h>

#include <cmath>
#include <sstream>

#include "itkImage.h"
#include "itkGDCMImageIO.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkImageFileReader.h"
#include "itkImageIOFactory.h"
#include "itkImageSeriesReader.h"
#include "itkMetaDataObject.h"
#include "itkMinimumMaximumImageCalculator.h"

#include "itkGDMVolumeConversion.h"

#include "image_input.h"  // after ITK (see the build notes on Eigen)

#include "cli_errors.h"
#include "mesh_writers.h"  // file_extension

namespace gdm_cli {
namespace {

using Image = itk::Image<float, 3>;

bool is_directory(const std::string& path) {
  struct stat s {};
  return ::stat(path.c_str(), &s) == 0 && S_ISDIR(s.st_mode);
}

bool exists(const std::string& path) {
  struct stat s {};
  return ::stat(path.c_str(), &s) == 0;
}

std::string format_name(const itk::ImageIOBase* io) {
  const std::string n = io->GetNameOfClass();
  if (n == "MetaImageIO") return "MetaImage";
  if (n == "NrrdImageIO") return "NRRD";
  if (n == "NiftiImageIO") return "NIfTI";
  if (n == "VTKImageIO") return "VTK image";
  if (n == "GDCMImageIO") return "DICOM file";
  return n;
}

// The image position (0020|0032) of a slice's dictionary, if present.
bool slice_position(const itk::MetaDataDictionary& d, double p[3]) {
  std::string value;
  if (!itk::ExposeMetaData<std::string>(d, "0020|0032", value)) return false;
  for (char& c : value)
    if (c == '\\') c = ' ';
  std::istringstream in(value);
  return static_cast<bool>(in >> p[0] >> p[1] >> p[2]);
}

Image::Pointer read_dicom_series(const std::string& folder, const std::string& wanted, InputInfo& info,
                                 std::ostream& log) {
  auto names = itk::GDCMSeriesFileNames::New();
  names->SetUseSeriesDetails(true);
  // A folder without DICOM is reported below; ITK's own warning would only repeat it.
  const bool warnings = itk::Object::GetGlobalWarningDisplay();
  itk::Object::SetGlobalWarningDisplay(false);
  names->SetDirectory(folder);
  const std::vector<std::string> uids = names->GetSeriesUIDs();
  itk::Object::SetGlobalWarningDisplay(warnings);
  if (uids.empty()) throw InputError("no DICOM series in the folder " + folder);
  info.series_count = uids.size();

  std::string chosen;
  if (!wanted.empty()) {
    for (const auto& uid : uids)
      if (uid == wanted || uid.rfind(wanted + ".", 0) == 0 || uid.rfind(wanted, 0) == 0) chosen = uid;
    if (chosen.empty()) {
      std::string list;
      for (const auto& uid : uids) list += "\n  " + uid;
      throw UsageError("--series " + wanted + ": no such series in " + folder + "; it holds:" + list);
    }
  } else {
    std::size_t most = 0;
    for (const auto& uid : uids) {
      const std::size_t n = names->GetFileNames(uid).size();
      if (n > most) {
        most = n;
        chosen = uid;
      }
    }
    if (uids.size() > 1)
      log << "the folder holds " << uids.size() << " DICOM series; using the one with most slices (" << most
          << "): " << chosen << " (choose another with --series UID)\n";
  }
  const std::vector<std::string> files = names->GetFileNames(chosen);
  info.series_uid = chosen;
  info.files = files.size();
  if (files.size() < 2)
    throw InputError("the DICOM series " + chosen + " in " + folder + " has " + std::to_string(files.size()) +
                     " slice; gdm needs a 3D volume");

  using Reader = itk::ImageSeriesReader<Image>;
  auto io = itk::GDCMImageIO::New();
  auto reader = Reader::New();
  reader->SetImageIO(io);
  reader->SetFileNames(files);
  try {
    reader->Update();
  } catch (const itk::ExceptionObject& e) {
    throw InputError("cannot read the DICOM series " + chosen + " in " + folder + ": " + e.GetDescription());
  }
  info.format = "DICOM series";
  info.pixel_type = itk::ImageIOBase::GetComponentTypeAsString(io->GetInternalComponentType());

  // A series without per-slice positions reads back with a slice spacing of 1.
  const auto& dictionaries = *reader->GetMetaDataDictionaryArray();
  double first[3], second[3];
  if (dictionaries.size() >= 2 && slice_position(*dictionaries[0], first) && slice_position(*dictionaries[1], second)) {
    const double d = std::sqrt((second[0] - first[0]) * (second[0] - first[0]) +
                               (second[1] - first[1]) * (second[1] - first[1]) +
                               (second[2] - first[2]) * (second[2] - first[2]));
    if (d == 0.0) throw InputError("the first two slices of the DICOM series " + chosen + " have the same position");
  } else {
    log << "warning: the DICOM series has no per-slice positions (0020|0032); the slice spacing "
        << reader->GetOutput()->GetSpacing()[2] << " mm may be wrong\n";
  }
  Image::Pointer image = reader->GetOutput();
  image->DisconnectPipeline();
  return image;
}

Image::Pointer read_file(const std::string& path, InputInfo& info) {
  itk::ImageIOBase::Pointer io =
      itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::ReadMode);
  if (!io)
    throw InputError("cannot read " + path +
                     ": not a readable image (supported: DICOM, .mha/.mhd, .nrrd/.nhdr, .nii/.nii.gz, .vtk; "
                     "is the header corrupt?)");
  io->SetFileName(path);
  try {
    io->ReadImageInformation();
  } catch (const itk::ExceptionObject& e) {
    throw InputError("cannot read the header of " + path + " (corrupt or unsupported): " + e.GetDescription());
  }
  info.format = format_name(io);
  info.pixel_type = itk::ImageIOBase::GetComponentTypeAsString(io->GetComponentType());
  const unsigned int dims = io->GetNumberOfDimensions();
  if (io->GetNumberOfComponents() != 1)
    throw InputError(path + " has " + std::to_string(io->GetNumberOfComponents()) +
                     " components per pixel; gdm needs a scalar image");
  if (dims < 3 || (dims == 3 && (io->GetDimensions(2) < 2)))
    throw InputError(path + " is a 2D image; gdm needs a 3D volume" +
                     (info.format == "DICOM file" ? std::string(" (pass the folder of the DICOM series)") : ""));
  for (unsigned int d = 3; d < dims; ++d)
    if (io->GetDimensions(d) > 1) throw InputError(path + " is a " + std::to_string(dims) + "D image; gdm needs a 3D volume");

  auto reader = itk::ImageFileReader<Image>::New();
  reader->SetImageIO(io);
  reader->SetFileName(path);
  try {
    reader->Update();
  } catch (const itk::ExceptionObject& e) {
    throw InputError("cannot read " + path + ": " + e.GetDescription());
  }
  Image::Pointer image = reader->GetOutput();
  image->DisconnectPipeline();
  return image;
}

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

}  // namespace

gdm::Volume read_input(const std::string& path, const std::string& series_uid, InputInfo& info,
                       std::ostream& log) {
  info.path = path;
  if (!exists(path)) throw InputError("no such file or folder: " + path);
  Image::Pointer image = is_directory(path) ? read_dicom_series(path, series_uid, info, log) : read_file(path, info);
  describe_image(image, info);
  for (unsigned int d = 0; d < 3; ++d) {
    if (info.size[d] < 2)
      throw InputError(path + " has only " + std::to_string(info.size[d]) + " voxel along axis " +
                       std::to_string(d) + "; gdm needs a 3D volume");
    if (!(info.spacing[d] > 0.0) || !std::isfinite(info.spacing[d]))
      throw InputError(path + " has an invalid spacing along axis " + std::to_string(d));
  }
  if (!std::isfinite(info.minimum) || !std::isfinite(info.maximum))
    throw InputError(path + " holds NaN or infinite values");
  if (info.minimum == info.maximum)
    throw InputError(path + " is constant (every voxel is " + std::to_string(info.minimum) + "): nothing to segment");
  return itk::GDMConversion::VolumeFromImage(image.GetPointer());
}

}  // namespace gdm_cli
