// Tests of gdm::read_volume (gdm/image_io.h). Every hostile input is built
// here, in a temporary folder: crafted headers, truncated files, DICOM series
// with a duplicated, missing or displaced slice, NaN voxels, a FIFO.
// Each hostile test also prints what ITK 5.2 does with the same file on its
// own ("ITK alone: ..."), the behaviour the checks of read_volume replace.
#include "itkGDCMImageIO.h"
#include "itkImage.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkGDCMSeriesFileNames.h"
#include "itkImageSeriesReader.h"
#include "itkImageSeriesWriter.h"
#include "itkMetaDataObject.h"
#include "itkSymmetricEigenAnalysis.h"  // ITK's Eigen before the system one

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>

#include "gdm/image_io.h"

namespace fs = std::filesystem;

namespace {

using ShortImage = itk::Image<short, 3>;
using FloatImage = itk::Image<float, 3>;

fs::path work_root() { return fs::temp_directory_path() / ("gdm_image_io_" + std::to_string(::getpid())); }

// Removes this process's temporary folder when the tests end.
struct RemoveWorkRoot : ::testing::Environment {
  void TearDown() override {
    std::error_code ignored;
    fs::remove_all(work_root(), ignored);
  }
};
const auto* const remove_work_root = ::testing::AddGlobalTestEnvironment(new RemoveWorkRoot);

fs::path work_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  fs::path dir = work_root() / (std::string(info->test_suite_name()) + "." + info->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

// The small test volume: 12 x 10 x 8 shorts, every voxel different,
// anisotropic spacing, an origin and a rotated direction.
ShortImage::Pointer small_volume(bool rotated = true) {
  auto image = ShortImage::New();
  image->SetRegions(ShortImage::RegionType(ShortImage::SizeType{{12, 10, 8}}));
  image->Allocate();
  short* p = image->GetBufferPointer();
  for (int i = 0; i < 12 * 10 * 8; ++i) p[i] = static_cast<short>((i * 37) % 1000 - 300);
  ShortImage::SpacingType spacing;
  spacing[0] = 0.75;
  spacing[1] = 0.5;
  spacing[2] = 1.25;
  image->SetSpacing(spacing);
  ShortImage::PointType origin;
  origin[0] = 10.5;
  origin[1] = -20.25;
  origin[2] = 30.0;
  image->SetOrigin(origin);
  ShortImage::DirectionType d;
  d.SetIdentity();
  if (rotated) {  // 90 degrees about z
    d[0][0] = 0;
    d[0][1] = -1;
    d[1][0] = 1;
    d[1][1] = 0;
  }
  image->SetDirection(d);
  return image;
}

template <typename TImage>
void write(const TImage* image, const fs::path& path, bool compress = false) {
  auto writer = itk::ImageFileWriter<TImage>::New();
  writer->SetInput(image);
  writer->SetFileName(path.string());
  writer->SetUseCompression(compress);
  writer->Update();
}

// A DICOM series of `image` with per-slice position tags. `position(k)` may
// displace slice k; files are s-001.dcm, s-002.dcm, ...
std::vector<fs::path> write_dicom_series(const ShortImage* image, const fs::path& folder,
                                         const std::function<void(int, ShortImage::PointType&)>& position = {}) {
  fs::create_directories(folder);
  using Slice = itk::Image<short, 2>;
  auto io = itk::GDCMImageIO::New();
  io->KeepOriginalUIDOn();
  auto writer = itk::ImageSeriesWriter<ShortImage, Slice>::New();
  const auto size = image->GetLargestPossibleRegion().GetSize();
  const auto spacing = image->GetSpacing();
  const auto& dir = image->GetDirection();
  const std::string root = "1.2.826.0.1.3680043.9.7433.2";
  std::vector<std::unique_ptr<itk::MetaDataDictionary>> owned;
  std::vector<itk::MetaDataDictionary*> dictionaries;
  std::vector<std::string> names;
  std::vector<fs::path> paths;
  std::ostringstream orientation;
  orientation.precision(10);
  orientation << dir[0][0] << "\\" << dir[1][0] << "\\" << dir[2][0] << "\\" << dir[0][1] << "\\" << dir[1][1]
              << "\\" << dir[2][1];
  for (unsigned int k = 0; k < size[2]; ++k) {
    owned.push_back(std::make_unique<itk::MetaDataDictionary>());
    auto& d = *owned.back();
    ShortImage::PointType p;
    image->TransformIndexToPhysicalPoint({{0, 0, static_cast<long>(k)}}, p);
    if (position) position(static_cast<int>(k), p);
    std::ostringstream pos, pixel_spacing;
    pos.precision(10);
    pos << p[0] << "\\" << p[1] << "\\" << p[2];
    pixel_spacing << spacing[1] << "\\" << spacing[0];
    itk::EncapsulateMetaData<std::string>(d, "0008|0060", "CT");
    itk::EncapsulateMetaData<std::string>(d, "0028|0004", "MONOCHROME2");
    itk::EncapsulateMetaData<std::string>(d, "0008|0016", "1.2.840.10008.5.1.4.1.1.2");
    itk::EncapsulateMetaData<std::string>(d, "0008|0018", root + ".3." + std::to_string(k + 1));
    itk::EncapsulateMetaData<std::string>(d, "0020|000d", root + ".1");
    itk::EncapsulateMetaData<std::string>(d, "0020|000e", root + ".2");
    itk::EncapsulateMetaData<std::string>(d, "0020|0052", root + ".4");
    itk::EncapsulateMetaData<std::string>(d, "0020|0013", std::to_string(k + 1));
    itk::EncapsulateMetaData<std::string>(d, "0020|0032", pos.str());
    itk::EncapsulateMetaData<std::string>(d, "0020|0037", orientation.str());
    itk::EncapsulateMetaData<std::string>(d, "0028|0030", pixel_spacing.str());
    itk::EncapsulateMetaData<std::string>(d, "0018|0050", "7.5");  // SliceThickness: not the spacing
    itk::EncapsulateMetaData<std::string>(d, "0028|1052", "0");
    itk::EncapsulateMetaData<std::string>(d, "0028|1053", "1");
    dictionaries.push_back(&d);
    char name[32];
    std::snprintf(name, sizeof name, "s-%03u.dcm", k + 1);
    paths.push_back(folder / name);
    names.push_back(paths.back().string());
  }
  writer->SetInput(image);
  writer->SetImageIO(io);
  writer->SetFileNames(names);
  writer->SetMetaDataDictionaryArray(&dictionaries);
  writer->Update();
  return paths;
}

// What ITK 5.2 alone makes of `path` (ImageFileReader<float>, no checks).
std::string itk_alone(const fs::path& path) {
  std::ostringstream s;
  auto reader = itk::ImageFileReader<FloatImage>::New();
  reader->SetFileName(path.string());
  const auto start = std::chrono::steady_clock::now();
  try {
    reader->Update();
    const auto* image = reader->GetOutput();
    std::size_t non_finite = 0, zeros = 0;
    const std::size_t n = image->GetBufferedRegion().GetNumberOfPixels();
    for (std::size_t i = 0; i < n; ++i) {
      const float v = image->GetBufferPointer()[i];
      non_finite += std::isfinite(v) ? 0 : 1;
      zeros += v == 0.0f ? 1 : 0;
    }
    s << "read without error: size " << image->GetBufferedRegion().GetSize() << ", spacing " << image->GetSpacing()
      << ", " << zeros << " zero and " << non_finite << " non-finite voxels of " << n;
  } catch (const itk::ExceptionObject& e) {
    s << "exception: " << e.GetDescription();
  } catch (const std::exception& e) {
    s << "std exception: " << e.what();
  }
  s << " (" << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s)";
  std::cout << "ITK alone on " << path.filename() << ": " << s.str() << std::endl;
  return s.str();
}

// What ITK 5.2 alone makes of a DICOM folder (GDCMSeriesFileNames, the first
// series, ImageSeriesReader<float>).
std::string itk_alone_series(const fs::path& folder) {
  std::ostringstream s;
  try {
    auto names = itk::GDCMSeriesFileNames::New();
    names->SetUseSeriesDetails(true);
    names->SetDirectory(folder.string());
    const auto files = names->GetFileNames(names->GetSeriesUIDs().front());
    auto reader = itk::ImageSeriesReader<FloatImage>::New();
    reader->SetImageIO(itk::GDCMImageIO::New());
    reader->SetFileNames(files);
    reader->Update();
    s << "read without error: " << files.size() << " files, size " << reader->GetOutput()->GetBufferedRegion().GetSize()
      << ", spacing " << reader->GetOutput()->GetSpacing();
  } catch (const itk::ExceptionObject& e) {
    s << "exception: " << e.GetDescription();
  }
  std::cout << "ITK alone on the series in " << folder.filename() << ": " << s.str() << std::endl;
  return s.str();
}

// read_volume must throw E with every one of `parts` in its message.
template <typename E = gdm::InvalidInput>
void expect_refused(const fs::path& path, const std::vector<std::string>& parts, const gdm::ReadOptions& options = {}) {
  try {
    gdm::read_volume(path.string(), options);
    ADD_FAILURE() << path << " was read; expected a refusal naming: " << parts.front();
  } catch (const E& e) {
    const std::string m = e.what();
    std::cout << "read_volume on " << path.filename() << ": " << m << std::endl;
    for (const auto& part : parts) EXPECT_NE(m.find(part), std::string::npos) << "message: " << m;
    EXPECT_NE(m.find(path.filename().string()), std::string::npos) << "the message names no file: " << m;
  } catch (const std::exception& e) {
    ADD_FAILURE() << path << ": wrong exception type: " << e.what();
  }
}

void write_text(const fs::path& path, const std::string& text) { std::ofstream(path, std::ios::binary) << text; }

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::string mha_header(const std::string& dims, const std::string& spacing, const std::string& type,
                       const std::string& data = "LOCAL") {
  return "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = False\nCompressedData = False\n"
         "DimSize = " + dims + "\nElementSpacing = " + spacing + "\nElementType = " + type +
         "\nElementDataFile = " + data + "\n";
}

void expect_same(const gdm::Volume& v, const ShortImage* ref, const std::string& what, bool direction = true) {
  const auto size = ref->GetLargestPossibleRegion().GetSize();
  ASSERT_EQ(v.dims()[0], static_cast<int>(size[0])) << what;
  ASSERT_EQ(v.dims()[1], static_cast<int>(size[1])) << what;
  ASSERT_EQ(v.dims()[2], static_cast<int>(size[2])) << what;
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(v.spacing()[d], ref->GetSpacing()[d], 1e-5) << what << " spacing " << d;
    EXPECT_NEAR(v.origin()[d], ref->GetOrigin()[d], 1e-4) << what << " origin " << d;
    if (direction)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(v.direction()(d, c), ref->GetDirection()[d][c], 1e-5) << what << " direction " << d << c;
  }
  const short* p = ref->GetBufferPointer();
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < v.values().size(); ++i) wrong += v.values()[i] == static_cast<float>(p[i]) ? 0 : 1;
  EXPECT_EQ(wrong, 0u) << what << ": voxel values differ";
}

// ITK's own reading of `path` as a float image (ImageFileReader), and
// whether read_volume gives the same: every value bit for bit, and the
// same dims, spacing, origin and direction. read_volume reads the pixels
// through the file's ImageIO straight into the volume's values (issue 17:
// one float copy of the volume instead of two), so what ImageFileReader
// makes of a file is the reference.
void expect_as_itk_reads(const fs::path& path) {
  const std::string what = path.filename().string();
  auto reader = itk::ImageFileReader<FloatImage>::New();
  reader->SetFileName(path.string());
  reader->Update();
  const FloatImage* ref = reader->GetOutput();
  gdm::ImageInfo info;
  gdm::Volume v;
  try {
    v = gdm::read_volume(path.string(), {}, &info);
  } catch (const std::exception& e) {
    ADD_FAILURE() << what << ": " << e.what();
    return;
  }
  const auto size = ref->GetLargestPossibleRegion().GetSize();
  for (int d = 0; d < 3; ++d) {
    EXPECT_EQ(v.dims()[d], static_cast<int>(size[d])) << what;
    EXPECT_EQ(v.spacing()[d], ref->GetSpacing()[d]) << what << " spacing " << d;
    EXPECT_EQ(v.origin()[d], ref->GetOrigin()[d]) << what << " origin " << d;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(v.direction()(d, c), ref->GetDirection()[d][c]) << what << " direction " << d << c;
  }
  ASSERT_EQ(v.values().size(), ref->GetLargestPossibleRegion().GetNumberOfPixels()) << what;
  const float* p = ref->GetBufferPointer();
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < v.values().size(); ++i)
    wrong += std::memcmp(&v.values()[i], &p[i], sizeof(float)) == 0 ? 0 : 1;
  EXPECT_EQ(wrong, 0u) << what << ": values differ from ITK's reading";
}

// The small volume's values as pixel type T, scaled to use T's range (the
// integers beyond a float's 24 bits round, the doubles have fractions).
template <typename T>
typename itk::Image<T, 3>::Pointer typed_volume(double scale, double shift) {
  const auto source = small_volume();
  auto image = itk::Image<T, 3>::New();
  image->SetRegions(source->GetLargestPossibleRegion());
  image->SetSpacing(source->GetSpacing());
  image->SetOrigin(source->GetOrigin());
  image->SetDirection(source->GetDirection());
  image->Allocate();
  const short* from = source->GetBufferPointer();
  T* to = image->GetBufferPointer();
  for (std::size_t i = 0; i < source->GetLargestPossibleRegion().GetNumberOfPixels(); ++i)
    to[i] = static_cast<T>(static_cast<double>(from[i] + 300) * scale + shift);
  return image;
}

}  // namespace

// ------------------------------------------------------------- formats --

TEST(Formats, EveryFormatReadsTheSameVolume) {
  const fs::path dir = work_dir();
  const auto image = small_volume();
  write(image.GetPointer(), dir / "v.mha");
  write(image.GetPointer(), dir / "v.mhd");
  write(image.GetPointer(), dir / "v.nrrd");
  write(image.GetPointer(), dir / "v.nii");
  write(image.GetPointer(), dir / "v.nii.gz");
  write_dicom_series(image.GetPointer(), dir / "dicom");
  const auto axis_aligned = small_volume(false);
  write(axis_aligned.GetPointer(), dir / "v.vtk");  // legacy VTK has no direction

  const std::vector<std::pair<std::string, std::string>> cases{
      {"v.mha", "MetaImage"}, {"v.mhd", "MetaImage"}, {"v.nrrd", "NRRD"}, {"v.nii", "NIfTI"},
      {"v.nii.gz", "NIfTI"},  {"dicom", "DICOM series"}, {"v.vtk", "VTK image"}};
  for (const auto& [name, format] : cases) {
    gdm::ImageInfo info;
    gdm::Volume v;
    try {
      v = gdm::read_volume((dir / name).string(), {}, &info);
    } catch (const std::exception& e) {
      ADD_FAILURE() << name << ": " << e.what();
      continue;
    }
    EXPECT_EQ(info.format, format);
    EXPECT_TRUE(info.warnings.empty()) << name << ": " << (info.warnings.empty() ? "" : info.warnings.front());
    expect_same(v, name == "v.vtk" ? axis_aligned.GetPointer() : image.GetPointer(), name);
    EXPECT_EQ(info.dims[2], 8u);
    EXPECT_EQ(info.minimum, -300);
    EXPECT_EQ(info.maximum, 699);
    EXPECT_EQ(info.pixel_type, "short") << name;
    if (name == "dicom") {
      EXPECT_EQ(info.slices, 8u);
      EXPECT_EQ(info.series_count, 1u);
      EXPECT_EQ(info.series_uid.rfind("1.2.826.0.1.3680043.9.7433.2.2", 0), 0u) << info.series_uid;
    }
  }
}

// Every scalar pixel type a volume file holds, in the formats that hold it,
// and a MetaImage with a fourth axis of one voxel, read as ITK's
// ImageFileReader reads them (expect_as_itk_reads).
TEST(Formats, EveryPixelTypeReadsAsItkReads) {
  const fs::path dir = work_dir();
  const auto both = [&](const auto& image, const std::string& name) {
    for (const std::string ext : {".mha", ".nrrd", ".nii.gz"}) {
      write(image.GetPointer(), dir / (name + ext), ext == ".nii.gz");
      expect_as_itk_reads(dir / (name + ext));
    }
  };
  both(typed_volume<unsigned char>(0.25, 0.0), "uchar");
  both(typed_volume<signed char>(0.125, -64.0), "char");
  both(typed_volume<unsigned short>(60.0, 1.0), "ushort");
  both(typed_volume<short>(1.0, -300.0), "short");
  both(typed_volume<unsigned int>(16777.0, 16777217.0), "uint");
  both(typed_volume<int>(-16777.0, 3.0), "int");
  both(typed_volume<float>(0.001, -0.25), "float");
  both(typed_volume<double>(1e-7, 1.0 / 3.0), "double");
  // A fourth axis of one voxel (the IO's region has four axes).
  {
    using Image4 = itk::Image<short, 4>;
    auto image = Image4::New();
    image->SetRegions(Image4::RegionType(Image4::SizeType{{5, 4, 3, 1}}));
    image->Allocate();
    for (std::size_t i = 0; i < 60; ++i) image->GetBufferPointer()[i] = static_cast<short>(7 * i - 100);
    Image4::SpacingType spacing;
    for (int d = 0; d < 4; ++d) spacing[d] = 0.5 + d;
    image->SetSpacing(spacing);
    write(image.GetPointer(), dir / "four.mha");
    expect_as_itk_reads(dir / "four.mha");
  }
}

// The shared folder's files read as ITK reads them (a NIfTI with a
// left-right flip, MetaImages of bytes and shorts).
TEST(RealData, EveryFileOfTheSharedFolderReadsAsItkReads) {
  const fs::path data = fs::path(GDM_SHARED_DIR) / "data";
  if (!fs::is_directory(data)) GTEST_SKIP() << "no real data: " << data << " is absent";
  for (const std::string f : {"tooth/tooth.mhd", "mri-head-t1/chris_t1.nii.gz", "mri-epi/mha.mha", "neghip/neghip.mhd"})
    if (fs::exists(data / f)) expect_as_itk_reads(data / f);
}

TEST(Formats, MissingFileAndUnknownSeries) {
  const fs::path dir = work_dir();
  expect_refused(dir / "none.mha", {"no such file or folder"});
  write_dicom_series(small_volume().GetPointer(), dir / "dicom");
  gdm::ReadOptions options;
  options.series_uid = "1.2.3.4";
  expect_refused<gdm::InvalidOption>(dir / "dicom", {"no such series 1.2.3.4"}, options);
  options.series_uid = "1.2.826.0.1.3680043.9.7433.2.2";  // a prefix of the UID GDCM reports
  EXPECT_NO_THROW(gdm::read_volume((dir / "dicom").string(), options));
}

TEST(Formats, TwoDimensionalAndConstantImagesAreRefused) {
  const fs::path dir = work_dir();
  using Image2 = itk::Image<unsigned char, 2>;
  auto slice = Image2::New();
  slice->SetRegions(Image2::RegionType(Image2::SizeType{{16, 16}}));
  slice->Allocate();
  slice->FillBuffer(7);
  write(slice.GetPointer(), dir / "slice.mha");
  expect_refused(dir / "slice.mha", {"is a 2D image; gdm needs a 3D volume"});
  auto flat = small_volume();
  flat->FillBuffer(5);
  write(flat.GetPointer(), dir / "flat.mha");
  expect_refused<gdm::InvalidVolume>(dir / "flat.mha", {"is constant"});
}

// ---------------------------------------- a. headers claiming too much --

TEST(Hostile, MetaImageHeaderClaimsFarMoreVoxels) {
  const fs::path dir = work_dir();
  const std::string voxels(32 * 32 * 32, '\x07');
  write_text(dir / "liar.mha", mha_header("1024 1024 1024", "1 1 1", "MET_UCHAR") + voxels);
  write_text(dir / "liar.mhd", mha_header("1024 1024 1024", "1 1 1", "MET_UCHAR", "liar.raw"));
  write_text(dir / "liar.raw", voxels);
  gdm::ReadOptions unlimited;
  unlimited.memory_limit = 0;  // the size check, not the memory limit, must refuse
  const auto start = std::chrono::steady_clock::now();
  expect_refused(dir / "liar.mha", {"header claims 1073741824 voxels", "but the file holds 32768 bytes"}, unlimited);
  expect_refused(dir / "liar.mhd", {"header claims 1073741824 voxels", "its data file", "liar.raw"}, unlimited);
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 2.0)
      << "refused only after a large allocation";
}

// A legacy VTK image whose header claims 1e11 points, or more than its data:
// refused from the file's size even without a memory limit (ITK would try to
// allocate it).
TEST(Hostile, VtkImageClaimingMorePointsThanItHolds) {
  const fs::path dir = work_dir();
  const std::string head = "# vtk DataFile Version 3.0\nhostile\n";
  write_text(dir / "huge.vtk", head + "BINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 10000 10000 1000\n"
                               "SPACING 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 100000000000\nSCALARS s short 1\n"
                               "LOOKUP_TABLE default\n" + std::string(4096, '\x01'));
  gdm::ReadOptions unlimited;
  unlimited.memory_limit = 0;
  expect_refused(dir / "huge.vtk", {"the header claims 100000000000 voxels", "truncated or a header that lies"}, unlimited);
  expect_refused(dir / "huge.vtk", {"the header claims 100000000000 voxels"});  // before the memory limit
  write_text(dir / "short.vtk", head + "BINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 8 8 8\nSPACING 1 1 1\n"
                                "ORIGIN 0 0 0\nPOINT_DATA 512\nSCALARS s short 1\nLOOKUP_TABLE default\n" +
                                std::string(1000, '\x01'));
  expect_refused(dir / "short.vtk", {"the header claims 512 voxels (1024 bytes of data)", "holds 1000 bytes"});
  std::string values;
  for (int i = 0; i < 100; ++i) values += std::to_string(i % 7) + " ";
  write_text(dir / "ascii.vtk", head + "ASCII\nDATASET STRUCTURED_POINTS\nDIMENSIONS 8 8 8\nSPACING 1 1 1\n"
                                "ORIGIN 0 0 0\nPOINT_DATA 512\nSCALARS s short 1\nLOOKUP_TABLE default\n" + values);
  expect_refused(dir / "ascii.vtk", {"the header claims 512 voxels"});
}

TEST(Hostile, MemoryLimitRefusesBeforeReading) {
  const fs::path dir = work_dir();
  write(small_volume().GetPointer(), dir / "v.mha");
  gdm::ReadOptions small;
  small.memory_limit = 1000;  // bytes; the volume is 960 voxels = 3840 bytes as float
  expect_refused(dir / "v.mha", {"12 x 10 x 8 voxels", "more than the memory limit"}, small);
  write_dicom_series(small_volume().GetPointer(), dir / "dicom");
  expect_refused(dir / "dicom", {"12 x 10 x 8 voxels", "more than the memory limit"}, small);
  small.memory_limit = 4000;
  EXPECT_NO_THROW(gdm::read_volume((dir / "v.mha").string(), small));
}

// ------------------------------------------------------ b. truncated --

TEST(Hostile, MetaImageHoldingAThirdOfItsVoxels) {
  const fs::path dir = work_dir();
  write_text(dir / "third.mha", mha_header("30 30 30", "1 1 1", "MET_SHORT") + std::string(30 * 30 * 30 * 2 / 3, '\x01'));
  itk_alone(dir / "third.mha");
  expect_refused(dir / "third.mha", {"header claims 27000 voxels", "but the file holds"});
}

TEST(Hostile, NiftiGzCutInHalf) {
  const fs::path dir = work_dir();
  write(small_volume().GetPointer(), dir / "whole.nii.gz");
  const std::string bytes = slurp(dir / "whole.nii.gz");
  write_text(dir / "half.nii.gz", bytes.substr(0, bytes.size() / 2));
  itk_alone(dir / "half.nii.gz");
  expect_refused(dir / "half.nii.gz", {"header claims 960 voxels", "but the gzip stream holds"});
}

TEST(Hostile, NiftiGzWithTheHeaderOnly) {
  const fs::path dir = work_dir();
  write(small_volume().GetPointer(), dir / "whole.nii");
  const std::string header = slurp(dir / "whole.nii").substr(0, 352);
  gzFile f = gzopen((dir / "header-only.nii.gz").string().c_str(), "wb");
  ASSERT_NE(f, nullptr);
  gzwrite(f, header.data(), static_cast<unsigned>(header.size()));
  gzclose(f);
  itk_alone(dir / "header-only.nii.gz");
  expect_refused(dir / "header-only.nii.gz", {"header claims 960 voxels", "but the gzip stream holds 0 bytes"});
  // The uncompressed file cut after its header, too.
  write_text(dir / "header-only.nii", header);
  itk_alone(dir / "header-only.nii");
  expect_refused(dir / "header-only.nii", {"header claims 960 voxels", "but the file holds 0 bytes"});
}

TEST(Hostile, NrrdHoldingHalfItsVoxels) {
  const fs::path dir = work_dir();
  write_text(dir / "half.nrrd", "NRRD0004\ntype: short\ndimension: 3\nsizes: 20 20 20\nspacings: 1 1 1\n"
                                "endian: little\nencoding: raw\n\n" + std::string(20 * 20 * 20, '\x02'));
  itk_alone(dir / "half.nrrd");
  expect_refused(dir / "half.nrrd", {"header claims 8000 voxels", "but the file holds"});
}

// ------------------------------------------------- c. DICOM geometry --

TEST(Dicom, IntactSeriesSpacingComesFromThePositions) {
  const fs::path dir = work_dir();
  const auto image = small_volume();
  write_dicom_series(image.GetPointer(), dir / "dicom");
  gdm::ImageInfo info;
  const gdm::Volume v = gdm::read_volume((dir / "dicom").string(), {}, &info);
  expect_same(v, image.GetPointer(), "dicom");
  EXPECT_NEAR(info.spacing[2], 1.25, 1e-6) << "SliceThickness is 7.5, the positions 1.25 apart";
}

TEST(Dicom, DuplicatedFileIsRefused) {
  const fs::path dir = work_dir();
  const auto files = write_dicom_series(small_volume().GetPointer(), dir / "dicom");
  fs::copy_file(files[3], dir / "dicom" / "copy-of-s-004.dcm");
  itk_alone_series(dir / "dicom");
  expect_refused(dir / "dicom", {"the same slice twice", "s-004.dcm", "copy-of-s-004.dcm", "duplicated file"});
}

TEST(Dicom, DuplicatedPositionIsRefused) {
  const fs::path dir = work_dir();
  const auto image = small_volume();
  write_dicom_series(image.GetPointer(), dir / "dicom", [&](int k, ShortImage::PointType& p) {
    if (k == 5) image->TransformIndexToPhysicalPoint({{0, 0, 4}}, p);
  });
  itk_alone_series(dir / "dicom");
  expect_refused(dir / "dicom", {"two slices at the same position", "duplicated slice"});
}

TEST(Dicom, MissingSliceIsRefused) {
  const fs::path dir = work_dir();
  const auto files = write_dicom_series(small_volume().GetPointer(), dir / "dicom");
  fs::remove(files[4]);
  itk_alone_series(dir / "dicom");
  expect_refused(dir / "dicom", {"missing slices", "a gap of 2.5 mm", "s-004.dcm", "s-006.dcm"});
}

TEST(Dicom, UnevenSpacingIsRefused) {
  const fs::path dir = work_dir();
  const auto image = small_volume();
  write_dicom_series(image.GetPointer(), dir / "dicom", [&](int k, ShortImage::PointType& p) {
    if (k >= 4) p[2] += 0.3;  // the step between slices 3 and 4: 1.55 mm instead of 1.25
  });
  itk_alone_series(dir / "dicom");
  expect_refused(dir / "dicom", {"non-uniform slice spacing", "1.55 mm", "median step 1.25 mm"});
}

TEST(Dicom, GantryTiltIsRefused) {
  const fs::path dir = work_dir();
  const auto image = small_volume();
  write_dicom_series(image.GetPointer(), dir / "dicom", [&](int k, ShortImage::PointType& p) {
    p[1] += 0.4 * k;  // along y: about 17.7 degrees
  });
  itk_alone_series(dir / "dicom");
  expect_refused(dir / "dicom", {"gantry tilt of 17.7", "degrees", "resample the series"});
}

TEST(Dicom, TinyTiltIsReported) {
  const fs::path dir = work_dir();
  const auto image = small_volume();
  write_dicom_series(image.GetPointer(), dir / "dicom", [&](int k, ShortImage::PointType& p) {
    p[1] += 0.0005 * k;  // 0.0035 mm over 8.75 mm: 0.023 degrees
  });
  gdm::ImageInfo info;
  ASSERT_NO_THROW(gdm::read_volume((dir / "dicom").string(), {}, &info));
  ASSERT_EQ(info.warnings.size(), 1u);
  EXPECT_NE(info.warnings[0].find("gantry tilt of 0.0229"), std::string::npos) << info.warnings[0];
}

TEST(Dicom, RealCtPhantomSeries) {
  const fs::path series = fs::path(GDM_SHARED_DIR) / "data" / "ct-phantom-dicom" / "series";
  if (!fs::is_directory(series)) GTEST_SKIP() << "no real DICOM data: " << series << " is absent";
  gdm::ImageInfo info;
  const gdm::Volume v = gdm::read_volume(series.string(), {}, &info);
  EXPECT_EQ(info.format, "DICOM series");
  EXPECT_EQ(info.slices, 28u);
  EXPECT_EQ(v.dims()[0], 512);
  EXPECT_EQ(v.dims()[2], 28);
  EXPECT_NEAR(v.spacing()[0], 0.4512, 1e-4);
  EXPECT_NEAR(v.spacing()[1], 0.4512, 1e-4);
  EXPECT_NEAR(v.spacing()[2], 5.0, 1e-4);
  EXPECT_LT(info.minimum, -900.0) << "rescale intercept -1024 applied";
}

TEST(RealData, EveryFileOfTheSharedFolderReads) {
  const fs::path data = fs::path(GDM_SHARED_DIR) / "data";
  const std::vector<std::string> files{"tooth/tooth.mhd", "mri-head-t1/chris_t1.nii.gz", "mri-epi/mha.mha",
                                       "neghip/neghip.mhd"};
  if (!fs::is_directory(data)) GTEST_SKIP() << "no real data: " << data << " is absent";
  for (const auto& f : files) {
    if (!fs::exists(data / f)) continue;
    gdm::ImageInfo info;
    EXPECT_NO_THROW(gdm::read_volume((data / f).string(), {}, &info)) << f;
    EXPECT_TRUE(info.warnings.empty()) << f;
  }
}

// ----------------------------------------------------- d. bad spacing --

TEST(Hostile, MetaImageSpacingZeroNegativeNaN) {
  const fs::path dir = work_dir();
  const std::string voxels(4 * 4 * 4, '\x03');
  const std::vector<std::pair<std::string, std::string>> cases{
      {"zero.mha", "1 0 1"}, {"negative.mha", "1 1 -2"}, {"nan.mha", "nan 1 1"}};
  for (const auto& [name, spacing] : cases) {
    std::string data = voxels;
    data[5] = '\x09';
    write_text(dir / name, mha_header("4 4 4", spacing, "MET_UCHAR") + data);
    itk_alone(dir / name);
    expect_refused(dir / name, {"spacing (ElementSpacing) along axis", "positive finite"});
  }
}

TEST(Hostile, NrrdSpacingZeroNegativeNaN) {
  const fs::path dir = work_dir();
  std::string data(4 * 4 * 4, '\x03');
  data[5] = '\x09';
  const std::vector<std::pair<std::string, std::string>> cases{
      {"zero.nrrd", "spacings: 1 0 1\n"},
      {"negative.nrrd", "spacings: 1 1 -2\n"},
      {"nan.nrrd", "spacings: nan 1 1\n"},
      {"zero-direction.nrrd", "space: left-posterior-superior\nspace directions: (1,0,0) (0,0,0) (0,0,1)\n"},
      {"nan-direction.nrrd", "space: left-posterior-superior\nspace directions: (1,0,0) (0,1,0) (nan,0,0)\n"}};
  for (const auto& [name, field] : cases) {
    write_text(dir / name, "NRRD0004\ntype: unsigned char\ndimension: 3\nsizes: 4 4 4\n" + field +
                               "encoding: raw\n\n" + data);
    itk_alone(dir / name);
    expect_refused(dir / name, {"spacing", "along axis", "positive finite"});
  }
}

TEST(Hostile, NiftiSpacingZeroNegativeNaN) {
  const fs::path dir = work_dir();
  write(small_volume(false).GetPointer(), dir / "v.nii");
  const std::string good = slurp(dir / "v.nii");
  const std::vector<std::pair<std::string, float>> cases{
      {"zero.nii", 0.0f}, {"negative.nii", -0.5f}, {"nan.nii", std::numeric_limits<float>::quiet_NaN()}};
  for (const auto& [name, value] : cases) {
    std::string bytes = good;
    std::memcpy(&bytes[80 + 4], &value, 4);  // pixdim[2]: the y spacing
    write_text(dir / name, bytes);
    itk_alone(dir / name);
    expect_refused(dir / name, {"spacing (pixdim) along axis 1", "positive finite"});
  }
  // A refusal closes the file it checked (the header check once leaked its
  // gzFile, a descriptor per refused file; LeakSanitizer found it).
  const auto open_files = [] {
    return std::distance(fs::directory_iterator("/proc/self/fd"), fs::directory_iterator{});
  };
  const auto before = open_files();
  for (int i = 0; i < 20; ++i) EXPECT_THROW(gdm::read_volume((dir / "zero.nii").string()), gdm::InvalidInput);
  EXPECT_EQ(open_files(), before);
}

// ---------------------------------------------- e. not a regular file --

TEST(Hostile, FifoIsRefusedAtOnce) {
  const fs::path dir = work_dir();
  const fs::path fifo = dir / "pipe.mha";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const auto start = std::chrono::steady_clock::now();
  expect_refused(fifo, {"is a FIFO", "not a regular file"});
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 1.0);
  if (fs::exists("/dev/null")) expect_refused("/dev/null", {"is a character device"});
}

// --------------------------------------------------- f. NaN and Inf --

TEST(Hostile, NonFiniteVoxels) {
  const fs::path dir = work_dir();
  auto image = FloatImage::New();
  image->SetRegions(FloatImage::RegionType(FloatImage::SizeType{{8, 8, 8}}));
  image->Allocate();
  for (int i = 0; i < 512; ++i) image->GetBufferPointer()[i] = static_cast<float>(i % 17);
  image->GetBufferPointer()[10] = std::numeric_limits<float>::quiet_NaN();
  image->GetBufferPointer()[20] = std::numeric_limits<float>::quiet_NaN();
  image->GetBufferPointer()[30] = std::numeric_limits<float>::infinity();
  write(image.GetPointer(), dir / "some-nan.mha");
  expect_refused(dir / "some-nan.mha", {"holds 3 non-finite voxels (2 NaN, 1 infinite) of 512"});
  image->FillBuffer(std::numeric_limits<float>::quiet_NaN());
  write(image.GetPointer(), dir / "all-nan.nrrd");
  expect_refused(dir / "all-nan.nrrd", {"holds 512 non-finite voxels (512 NaN, 0 infinite) of 512"});
}

// ------------------------------------------------ g. found by fuzzing --

// fuzz_image_reader (test/fuzz/corpus/fuzz_image_reader/leak_mha_missing_data_file):
// an ElementDataFile naming a file that does not exist, with a space in its
// name, went past the header check to ITK, whose MetaIO leaks its stream
// when it cannot open the data file (LeakSanitizer). Now refused before ITK
// reads the data, like a missing name without a space.
TEST(Fuzz, MetaImageDataFileWithASpaceThatDoesNotExist) {
  const fs::path dir = work_dir();
  write_text(dir / "spaced.mhd", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", "no such file.raw"));
  expect_refused(dir / "spaced.mhd", {"its data file", "no such file.raw", "does not exist"});
  write_text(dir / "fuzzed.mha", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", "= MET_UCHArix = 1 0 0 0 1 0 0 0 1") +
                                      std::string(60, '\x07'));
  expect_refused(dir / "fuzzed.mha", {"its data file", "does not exist"});
  // fuzz_image_reader (corpus/fuzz_image_reader/leak_mha_data_file_nul): the
  // name ends at a NUL byte for MetaIO; what follows ('%', spaces) is not part of it.
  write_text(dir / "nul.mha", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", std::string("LColor\0%Jo 1 2", 14)) +
                                  std::string(60, '\x07'));
  expect_refused(dir / "nul.mha", {"its data file", "LColor does not exist"});
  // fuzz_image_reader (corpus/fuzz_image_reader/crash_mha_pattern_step_0): a
  // name with '%' is a file pattern for MetaIO, which divides by its step:
  // step 0 (or words that are no numbers) ended the process with SIGFPE.
  write_text(dir / "step0.mhd", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", "slice%03d.raw 1 3 0"));
  expect_refused(dir / "step0.mhd", {"data file pattern 'slice%03d.raw 1 3 0'", "step > 0"});
  write_text(dir / "garbage.mhd", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", "LOC%lementDataFile = LOC%Jo"));
  expect_refused(dir / "garbage.mhd", {"data file pattern", "step > 0"});
  // corpus/fuzz_image_reader/crash_mha_pattern_format_L: MetaIO gives the
  // pattern to snprintf as its format; "%L" (no conversion) stopped
  // AddressSanitizer inside MetaIO. Only one integer field is a pattern.
  for (const char* pattern : {"LOCJA%L", "slice%s.raw 1 3 1", "slice%n.raw 1 3 1", "slice%d%d.raw 1 3 1",
                              "slice%.3d.raw 1 3 1", "slice%01234d.raw 1 3 1", "slice%ld.raw 1 3 1", "slice%-3d.raw 1 3 1"}) {
    write_text(dir / "format.mhd", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", pattern));
    expect_refused(dir / "format.mhd", {"data file pattern", "one integer field"});
  }
  write_text(dir / "backwards.mhd", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", "slice%03d.raw 3 1 1"));
  expect_refused(dir / "backwards.mhd", {"data file pattern", "first <= last"});
  // crash_mha_pattern_dimsize_nan: the step of "<pattern> <first> <last>" is
  // (last - first) / slices; a DimSize of nan was cast to an integer (UB).
  write_text(dir / "nan-dims.mhd", mha_header("5 4 nan", "0.5 1 2", "MET_UCHAR", "slice%03d.raw 1 3"));
  EXPECT_THROW(gdm::read_volume((dir / "nan-dims.mhd").string()), gdm::InvalidInput);
  for (int k = 1; k <= 3; ++k) {  // a well-formed pattern still reads
    char name[32];
    std::snprintf(name, sizeof name, "slice%03d.raw", k);
    write_text(dir / name, std::string(20, static_cast<char>(k)));
  }
  write_text(dir / "pattern.mhd", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", "slice%03d.raw 1 3 1"));
  EXPECT_EQ(gdm::read_volume((dir / "pattern.mhd").string()).max_value(), 3.0);
  for (int k = 1; k <= 3; ++k) {  // "%i", and a literal percent sign
    char name[32];
    std::snprintf(name, sizeof name, "s%%_%i.raw", k);
    write_text(dir / name, std::string(20, static_cast<char>(k + 1)));
  }
  write_text(dir / "percent.mhd", mha_header("5 4 3", "0.5 1 2", "MET_UCHAR", "s%%_%i.raw 1 3 1"));
  EXPECT_EQ(gdm::read_volume((dir / "percent.mhd").string()).max_value(), 4.0);
  // The same name present is read as one file.
  std::string voxels(60, '\x07');
  voxels[5] = '\x30';
  write_text(dir / "no such file.raw", voxels);
  EXPECT_EQ(gdm::read_volume((dir / "spaced.mhd").string()).voxel_count(), 60u);
}

// fuzz_image_reader (corpus timeout_nii_sform_1e22, timeout_nii_offset_1e38): finite but absurd
// orientations (an sform mixing 1e22 and 1e-19, codes 29550 and 26473, an
// origin of -1.7e38 mm)
// kept ITK's SVD iterating. Refused before ITK reads the header.
TEST(Fuzz, NiftiWithAnAbsurdOrientationIsRefused) {
  const fs::path dir = work_dir();
  write(small_volume(false).GetPointer(), dir / "v.nii");
  const std::string good = slurp(dir / "v.nii");
  const auto with = [&](const std::string& name, const std::function<void(std::string&)>& change) {
    std::string bytes = good;
    change(bytes);
    write_text(dir / name, bytes);
    return dir / name;
  };
  const auto put16 = [](std::string& b, int at, std::int16_t v) { std::memcpy(&b[at], &v, 2); };
  const auto putf = [](std::string& b, int at, float v) { std::memcpy(&b[at], &v, 4); };
  expect_refused(with("code.nii", [&](std::string& b) { put16(b, 254, 29550); }), {"sform_code is 29550", "0 to 5"});
  expect_refused(with("huge.nii", [&](std::string& b) {
                   put16(b, 254, 1);
                   putf(b, 280 + 4, 5.8e8f);
                 }),
                 {"sform gives axis 1 a voxel step of", "between 1e-6 and 1e6 mm"});
  expect_refused(with("flat.nii", [&](std::string& b) {
                   put16(b, 254, 1);
                   for (int r = 0; r < 3; ++r)
                     for (int c = 0; c < 3; ++c) putf(b, 280 + 16 * r + 4 * c, r == 0 ? 1.0f : 0.0f);
                 }),
                 {"sform is degenerate"});
  expect_refused(with("far.nii", [&](std::string& b) {
                   put16(b, 254, 1);
                   putf(b, 312 + 12, -1.7e38f);
                 }),
                 {"srow_z[3] is", "within 1e9 mm"});
  expect_refused(with("quatern.nii", [&](std::string& b) {
                   put16(b, 252, 1);
                   put16(b, 254, 0);
                   putf(b, 256, 2.0f);
                 }),
                 {"quatern_b is", "at most 1"});
  EXPECT_GT(gdm::read_volume((dir / "v.nii").string()).voxel_count(), 0u);
}

// fuzz_image_reader (corpus timeout_mha_ndims_3e6, crash_mha_key_past_255_bytes,
// crash_mha_data_file_not_ascii):
// MetaIO trusts its header. "NDims = 3000000e+00" made it read three million
// numbers per array field (a hang); a key of 300 bytes overflowed its name
// buffer (abort); bytes above 0x7e in the data file's name made it read past
// its word array (ASan). The header's grammar is now checked before MetaIO sees it.
TEST(Fuzz, MalformedMetaImageHeadersAreRefusedBeforeMetaIO) {
  const fs::path dir = work_dir();
  std::string voxels(60, '\x07');
  voxels[5] = '\x30';
  const auto header = [](const std::string& ndims, const std::string& extra) {
    return "ObjectType = Image\nNDims = " + ndims + "\n" + extra + "DimSize = 5 4 3\nElementSpacing = 0.5 1 2\n" +
           "ElementType = MET_UCHAR\nElementDataFile = LOCAL\n";
  };
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases{
      {header("3000000e+00", ""), {"line 2", "NDims '3000000e+00'", "integer 1 to 8"}},
      {header("-3", ""), {"NDims '-3'"}},
      {header("3", std::string(300, 'k') + " = 1\n"), {"line 3", "longer than 128"}},
      {header("3", "Elem\xff" "ent = 1\n"), {"line 3", "not a letter, digit", "255"}},
      {header("3", "Comment = caf\xc3\xa9\n"), {"line 3", "not printable ASCII"}},
      {header("3", "just words\n"), {"line 3", "is not 'Key = value'"}},
      {header("3", "Offset = 1 2\n"), {"line 3", "2 numbers for Offset; 3 are needed"}},
      {header("3", "TransformMatrix = 1 0 0 0 1 0 0 0\n"), {"8 numbers for TransformMatrix; 9 are needed"}},
      {header("3", "NDims = 2\n"), {"line 3", "repeats the field NDims"}},
      {"ObjectType = Image\nDimSize = 5 4 3\nElementDataFile = LOCAL\n", {"line 2", "DimSize before NDims"}},
      {"ObjectType = Image\nNDims = 3\nDimSize = 5 4 2.5\nElementDataFile = LOCAL\n", {"DimSize of 2.5"}},
      {"ObjectType = Image\nNDims = 3\nDimSize = 5 4 3\n", {"no ElementDataFile line"}},
      {"ObjectType = Image\nNDims = 3\nDimSize = 5 4 3\nElementDataFile = \x8d\x8d.raw\n", {"line 4", "141"}},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path file = dir / ("bad" + std::to_string(i) + ".mha");
    const bool ends_early = cases[i].first.find("ElementDataFile") == std::string::npos;
    write_text(file, cases[i].first + (ends_early ? "" : voxels));
    std::vector<std::string> expected = cases[i].second;
    expected.push_back("not a well-formed MetaImage header");
    expect_refused(file, expected);
  }
  // The same header, well formed, reads; so do ITK's own extra fields.
  write_text(dir / "good.mha", header("3", "Offset = 1 2 3\nTransformMatrix = 1 0 0 0 1 0 0 0 1\n"
                                           "ITK_InputFilterName = MetaImageIO\nAnatomicalOrientation = RAI\n") + voxels);
  EXPECT_EQ(gdm::read_volume((dir / "good.mha").string()).voxel_count(), 60u);
}

// fuzz_image_reader (corpus oom_mha_parsed_as_dicom): a .mha starting with
// "DICM" went to every ITK reader; GDCM took it for DICOM and allocated the
// 1.4 GB one element claimed. A file's extension now names its one reader.
TEST(Fuzz, AFileIsReadByTheReaderItsExtensionNames) {
  const fs::path dir = work_dir();
  write(small_volume(false).GetPointer(), dir / "v.nrrd");
  fs::copy_file(dir / "v.nrrd", dir / "nrrd-named.mha");
  expect_refused(dir / "nrrd-named.mha", {"nrrd-named.mha", "not a readable image of the format its name gives",
                                           "starts like a NRRD file", "rename it .nrrd"});
  // corpus crash_mha_starting_nrrd: such a file went past the MetaImage
  // checks (it looked like NRRD) to MetaIO, which read past the bytes above
  // 0x7e of its data file's name.
  write_text(dir / "nrrd-magic.mha",
             "NRRDObjectType = Image\nNDims = 3\nDimSize = 5 4 3\nElementDataFile = \x8d\x8d.raw\n");
  expect_refused(dir / "nrrd-magic.mha", {"nrrd-magic.mha", "starts like a NRRD file"});
  const auto slices = write_dicom_series(small_volume(false).GetPointer(), dir / "dicom");
  fs::copy_file(slices.front(), dir / "dicom-named.nrrd");
  expect_refused(dir / "dicom-named.nrrd", {"not a readable image of the format its name gives"});
  EXPECT_GT(gdm::read_volume((dir / "dicom").string()).voxel_count(), 0u);
  EXPECT_GT(gdm::read_volume((dir / "v.nrrd").string()).voxel_count(), 0u);
}

std::size_t open_file_descriptors() {
  std::size_t n = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator("/proc/self/fd")) ++n;
  return n;
}

// fuzz_image_reader (test/fuzz/corpus/fuzz_image_reader/leak_nii_bad_pixdim):
// a NIfTI header with a bad pixdim was refused while the header check still
// held the file open through zlib (LeakSanitizer: zlib's buffers; here: one
// file descriptor lost per refused file, which a long-lived front end such
// as the MeshLab plugin runs out of). Now closed on every path.
TEST(Fuzz, RefusedNiftiHeadersLeaveNoFileOpen) {
  const fs::path dir = work_dir();
  write(small_volume(false).GetPointer(), dir / "v.nii");
  std::string bytes = slurp(dir / "v.nii");
  const float nan = std::numeric_limits<float>::quiet_NaN();
  std::memcpy(&bytes[80 + 4], &nan, 4);  // pixdim[2]
  write_text(dir / "nan.nii", bytes);
  write(small_volume(false).GetPointer(), dir / "v.nii.gz", true);
  const std::size_t before = open_file_descriptors();
  for (int i = 0; i < 20; ++i) {
    EXPECT_THROW(gdm::read_volume((dir / "nan.nii").string()), gdm::InvalidInput);
    EXPECT_NO_THROW(gdm::read_volume((dir / "v.nii.gz").string()));
  }
  EXPECT_EQ(open_file_descriptors(), before);
}

// fuzz_image_reader (test/fuzz/corpus/fuzz_image_reader/crash_nii_nan_srow):
// a NIfTI header whose sform (or qform) holds a NaN made ITK 5.2's
// NiftiImageIO run an SVD that vnl ends with abort(): the process died
// (SIGABRT) inside read_volume. Now refused before ITK reads the header.
// (ITK alone is not run on these files: it would abort this test.)
TEST(Fuzz, NiftiWithANonFiniteOrientationIsRefusedNotAborted) {
  const fs::path dir = work_dir();
  write(small_volume(false).GetPointer(), dir / "v.nii");
  const std::string good = slurp(dir / "v.nii");
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  std::int16_t code = 1;
  {
    std::string bytes = good;
    std::memcpy(&bytes[254], &code, 2);        // sform_code 1
    std::memcpy(&bytes[280 + 4], &nan, 4);     // srow_x[1]
    write_text(dir / "nan-srow.nii", bytes);
    expect_refused(dir / "nan-srow.nii", {"srow_x[1] is nan", "orientation and origin must be finite"});
  }
  {
    std::string bytes = good;
    std::int16_t zero = 0;
    std::memcpy(&bytes[252], &code, 2);        // qform_code 1
    std::memcpy(&bytes[254], &zero, 2);        // sform_code 0: the qform is used
    std::memcpy(&bytes[256 + 8], &inf, 4);     // quatern_d
    write_text(dir / "inf-quatern.nii", bytes);
    expect_refused(dir / "inf-quatern.nii", {"quatern_b/c/d[2] is inf", "orientation and origin must be finite"});
  }
  {
    // crash_nii_sizeof_hdr_476: the same with a sizeof_hdr that is neither 348
    // nor 540, which niftilib reads anyway (byte order from dim[0]).
    std::string bytes = good;
    const std::int32_t sizeof_hdr = 476;
    std::memcpy(&bytes[0], &sizeof_hdr, 4);
    std::memcpy(&bytes[254], &code, 2);
    std::memcpy(&bytes[280 + 8], &nan, 4);     // srow_x[2]
    write_text(dir / "odd-size.nii", bytes);
    expect_refused(dir / "odd-size.nii", {"srow_x[2] is nan", "orientation and origin must be finite"});
  }
  EXPECT_NO_THROW(gdm::read_volume((dir / "v.nii").string()));
}

// Every input of fuzz_image_reader's committed corpus (test/fuzz/corpus),
// the crashes it found included, as the fuzz target reads it: the first byte
// picks the extension, the rest is the file. Each gives a volume or a
// gdm::Error, never a signal (SIGFPE, abort) or another exception.
TEST(Fuzz, EveryCorpusInputIsReadOrRefused) {
  const fs::path dir = work_dir();
  const char* const extensions[] = {".mha", ".nrrd", ".nii", ".nii.gz", ".vtk"};
  int inputs = 0;
  for (const auto& entry : fs::directory_iterator(GDM_FUZZ_CORPUS_DIR)) {
    const std::string bytes = slurp(entry.path());
    if (bytes.empty()) continue;
    const fs::path file = dir / ("input" + std::string(extensions[static_cast<unsigned char>(bytes[0]) % 5]));
    write_text(file, bytes.substr(1));
    gdm::ReadOptions options;
    options.memory_limit = std::uint64_t{64} << 20;
    try {
      gdm::read_volume(file.string(), options);
    } catch (const gdm::Error&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << entry.path().filename() << ": not a gdm::Error: " << e.what();
    }
    ++inputs;
  }
  EXPECT_GE(inputs, 10);
}
