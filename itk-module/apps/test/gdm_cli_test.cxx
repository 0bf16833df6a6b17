// End-to-end tests of the gdm command: they run the built binary on volumes
// written here (the embedded phantom as MHA, NRRD, NIfTI and a DICOM series)
// and on the real scans of ../shared/data (skipped when absent), read the
// meshes back (ITK's mesh readers for .vtk/.obj/.off, parsers here for .ply
// and .stl) and check them with the core's mesh checks.
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "gtest/gtest.h"

#include "itkGDCMImageIO.h"
#include "itkImage.h"
#include "itkImageFileReader.h"
#include "itkImageFileWriter.h"
#include "itkImageRegionConstIteratorWithIndex.h"
#include "itkImageRegionIteratorWithIndex.h"
#include "itkImageSeriesWriter.h"
#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMetaDataObject.h"

#include "gdm/errors.h"
#include "gdm/mesh_checks.h"
#include "gdm/mesh_io.h"
#include "gdm/phantoms.h"
#include "gdm/seed.h"
#include "gdm/triangle_locator.h"
#include "json_writer.h"
#include "report.h"

namespace fs = std::filesystem;

namespace {

using ShortImage = itk::Image<short, 3>;

const std::string kGdm = GDM_EXECUTABLE;
const std::string kPhantom = GDM_PHANTOM;
const std::string kShared = GDM_SHARED_DIR;

// A fresh, empty folder for one test.
fs::path work_dir() {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  fs::path dir = fs::path(GDM_TEST_WORK_DIR) / (std::string(info->test_suite_name()) + "." + info->name());
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string quote(const std::string& s) {
  std::string out = "'";
  for (const char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

struct GdmRun {
  int code = -1;
  std::string out, err;
};

// Runs gdm with `args` in `dir`, stdout and stderr captured.
GdmRun run_gdm(const fs::path& dir, const std::vector<std::string>& args) {
  std::string command = "cd " + quote(dir.string()) + " && " + quote(kGdm);
  for (const auto& a : args) command += " " + quote(a);
  command += " >" + quote((dir / "stdout.txt").string()) + " 2>" + quote((dir / "stderr.txt").string());
  const int status = std::system(command.c_str());
  GdmRun run;
  run.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = slurp(dir / "stdout.txt");
  run.err = slurp(dir / "stderr.txt");
  fs::remove(dir / "stdout.txt");
  fs::remove(dir / "stderr.txt");
  return run;
}

// ---------------------------------------------------------------- meshes --

struct Mesh {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<std::uint32_t, 3>> faces;
  std::vector<int> generation;  // PLY only
};

template <typename T>
T get_le(std::istream& in) {
  unsigned char bytes[sizeof(T)];
  in.read(reinterpret_cast<char*>(bytes), sizeof(T));
  T value;
  std::memcpy(&value, bytes, sizeof(T));  // the test machines are little-endian
  return value;
}

Mesh read_ply(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string line;
  std::size_t vertices = 0, faces = 0;
  std::vector<std::string> vertex_properties;
  std::string element;
  bool binary = false;
  while (std::getline(in, line) && line != "end_header") {
    std::istringstream s(line);
    std::string word;
    s >> word;
    if (word == "format") binary = line.find("binary_little_endian") != std::string::npos;
    if (word == "element") {
      s >> element;
      (element == "vertex" ? vertices : faces) = 0;
      std::size_t n = 0;
      s >> n;
      (element == "vertex" ? vertices : faces) = n;
    }
    if (word == "property" && element == "vertex") {
      std::string type, name;
      s >> type >> name;
      vertex_properties.push_back(type + " " + name);
    }
  }
  EXPECT_TRUE(binary) << "the PLY file is not binary little-endian";
  const std::vector<std::string> expected = {"float x", "float y", "float z", "int generation"};
  EXPECT_EQ(vertex_properties, expected) << "PLY vertex properties";
  Mesh mesh;
  for (std::size_t i = 0; i < vertices && in; ++i) {
    std::array<double, 3> p{};
    for (double& x : p) x = get_le<float>(in);
    mesh.points.push_back(p);
    mesh.generation.push_back(get_le<std::int32_t>(in));
  }
  for (std::size_t f = 0; f < faces && in; ++f) {
    EXPECT_EQ(get_le<std::uint8_t>(in), 3);
    std::array<std::uint32_t, 3> face{};
    for (auto& v : face) v = static_cast<std::uint32_t>(get_le<std::int32_t>(in));
    mesh.faces.push_back(face);
  }
  EXPECT_TRUE(in.good()) << "the PLY file is truncated";
  in.peek();
  EXPECT_TRUE(in.eof()) << "the PLY file has trailing bytes";
  return mesh;
}

// Binary STL: a triangle soup; vertices are merged by their exact coordinates.
Mesh read_stl(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char header[80];
  in.read(header, 80);
  const auto n = get_le<std::uint32_t>(in);
  Mesh mesh;
  std::map<std::array<float, 3>, std::uint32_t> ids;
  for (std::uint32_t t = 0; t < n && in; ++t) {
    for (int k = 0; k < 3; ++k) get_le<float>(in);  // normal
    std::array<std::uint32_t, 3> face{};
    for (int k = 0; k < 3; ++k) {
      std::array<float, 3> p{};
      for (float& x : p) x = get_le<float>(in);
      const auto found = ids.emplace(p, static_cast<std::uint32_t>(mesh.points.size()));
      if (found.second) mesh.points.push_back({p[0], p[1], p[2]});
      face[k] = found.first->second;
    }
    get_le<std::uint16_t>(in);
    mesh.faces.push_back(face);
  }
  EXPECT_TRUE(in.good()) << "the STL file is truncated";
  return mesh;
}

// .vtk, .obj, .off with ITK's mesh readers.
Mesh read_with_itk(const fs::path& path) {
  using MeshType = itk::Mesh<double, 3, itk::DefaultStaticMeshTraits<double, 3, 3, double, double, double>>;
  auto reader = itk::MeshFileReader<MeshType>::New();
  reader->SetFileName(path.string());
  reader->Update();
  const MeshType* m = reader->GetOutput();
  Mesh mesh;
  std::map<MeshType::PointIdentifier, std::uint32_t> ids;
  for (auto it = m->GetPoints()->Begin(); it != m->GetPoints()->End(); ++it) {
    ids[it.Index()] = static_cast<std::uint32_t>(mesh.points.size());
    mesh.points.push_back({it.Value()[0], it.Value()[1], it.Value()[2]});
  }
  for (auto it = m->GetCells()->Begin(); it != m->GetCells()->End(); ++it) {
    if (it.Value()->GetNumberOfPoints() != 3) continue;
    std::array<std::uint32_t, 3> face{};
    int k = 0;
    for (auto p = it.Value()->PointIdsBegin(); p != it.Value()->PointIdsEnd(); ++p) face[k++] = ids.at(*p);
    mesh.faces.push_back(face);
  }
  return mesh;
}

Mesh read_mesh(const fs::path& path) {
  const std::string e = path.extension().string();
  if (e == ".ply") return read_ply(path);
  if (e == ".stl") return read_stl(path);
  return read_with_itk(path);
}

gdm::MeshReport measure(const Mesh& m) {
  gdm::Mesh mesh;
  std::vector<gdm::Mesh::VertexHandle> h;
  for (const auto& p : m.points) h.push_back(mesh.add_vertex(gdm::Mesh::Point(p[0], p[1], p[2])));
  for (const auto& f : m.faces) EXPECT_TRUE(mesh.add_face(h[f[0]], h[f[1]], h[f[2]]).is_valid());
  return gdm::measure(mesh);
}

// Every guarantee of a gdm model: closed, 2-manifold, one component, genus 0,
// no self-intersecting face pair.
void expect_valid_model(const gdm::MeshReport& r) {
  EXPECT_TRUE(r.closed) << gdm::to_string(r);
  EXPECT_TRUE(r.two_manifold) << gdm::to_string(r);
  EXPECT_EQ(r.components, 1) << gdm::to_string(r);
  EXPECT_EQ(r.genus, 0) << gdm::to_string(r);
  EXPECT_EQ(r.self_intersections, 0u) << gdm::to_string(r);
}

std::array<double, 6> bounds(const Mesh& m) {
  std::array<double, 6> b{1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
  for (const auto& p : m.points)
    for (int d = 0; d < 3; ++d) {
      b[d] = std::min(b[d], p[d]);
      b[d + 3] = std::max(b[d + 3], p[d]);
    }
  return b;
}

// Physical bounds of the voxel centres on the object side of T (bright object).
template <typename TImage>
std::array<double, 6> voxel_bounds(const TImage* image, double threshold, bool darker) {
  std::array<double, 6> b{1e300, 1e300, 1e300, -1e300, -1e300, -1e300};
  const auto region = image->GetLargestPossibleRegion();
  itk::ImageRegionConstIteratorWithIndex<TImage> it(image, region);
  for (it.GoToBegin(); !it.IsAtEnd(); ++it) {
    const double v = it.Get();
    if (darker ? !(v < threshold) : !(v > threshold)) continue;
    typename TImage::PointType p;
    image->TransformIndexToPhysicalPoint(it.GetIndex(), p);
    for (int d = 0; d < 3; ++d) {
      b[d] = std::min(b[d], p[d]);
      b[d + 3] = std::max(b[d + 3], p[d]);
    }
  }
  return b;
}

// A number after "key": in a JSON text (the report); NaN when absent.
double json_value(const std::string& json, const std::string& key) {
  const auto at = json.find("\"" + key + "\":");
  if (at == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + at + key.size() + 3, nullptr);
}

// -------------------------------------------------------- input formats --

// A DICOM series with full per-slice position tags and a rescale intercept.
void write_dicom_series(const ShortImage* image, const fs::path& folder, const std::string& series = "2",
                        unsigned int slices = 0) {
  fs::create_directories(folder);
  using Slice = itk::Image<short, 2>;
  auto io = itk::GDCMImageIO::New();
  io->KeepOriginalUIDOn();
  auto writer = itk::ImageSeriesWriter<ShortImage, Slice>::New();
  const auto size = image->GetLargestPossibleRegion().GetSize();
  const auto spacing = image->GetSpacing();
  const std::string root = "1.2.826.0.1.3680043.9.7433.1";
  std::vector<itk::MetaDataDictionary*> dictionaries;
  std::vector<std::unique_ptr<itk::MetaDataDictionary>> owned;
  std::vector<std::string> names;
  for (unsigned int k = 0; k < (slices ? slices : size[2]); ++k) {
    owned.push_back(std::make_unique<itk::MetaDataDictionary>());
    auto& d = *owned.back();
    ShortImage::PointType p;
    image->TransformIndexToPhysicalPoint({{0, 0, static_cast<long>(k)}}, p);
    std::ostringstream position, pixel_spacing;
    position.precision(10);
    position << p[0] << "\\" << p[1] << "\\" << p[2];
    pixel_spacing << spacing[1] << "\\" << spacing[0];
    itk::EncapsulateMetaData<std::string>(d, "0008|0060", "CT");
    itk::EncapsulateMetaData<std::string>(d, "0028|0004", "MONOCHROME2");
    itk::EncapsulateMetaData<std::string>(d, "0008|0016", "1.2.840.10008.5.1.4.1.1.2");
    itk::EncapsulateMetaData<std::string>(d, "0008|0018", root + ".3." + series + "." + std::to_string(k + 1));
    itk::EncapsulateMetaData<std::string>(d, "0020|000d", root + ".1");
    itk::EncapsulateMetaData<std::string>(d, "0020|000e", root + "." + series);
    itk::EncapsulateMetaData<std::string>(d, "0020|0052", root + ".4");
    itk::EncapsulateMetaData<std::string>(d, "0020|0013", std::to_string(k + 1));
    itk::EncapsulateMetaData<std::string>(d, "0020|0032", position.str());
    itk::EncapsulateMetaData<std::string>(d, "0020|0037", "1\\0\\0\\0\\1\\0");
    itk::EncapsulateMetaData<std::string>(d, "0028|0030", pixel_spacing.str());
    itk::EncapsulateMetaData<std::string>(d, "0018|0050", std::to_string(spacing[2]));
    itk::EncapsulateMetaData<std::string>(d, "0028|1052", "-1024");
    itk::EncapsulateMetaData<std::string>(d, "0028|1053", "1");
    dictionaries.push_back(&d);
    char name[32];
    std::snprintf(name, sizeof name, "s%s-%03u.dcm", series.c_str(), k + 1);
    names.push_back((folder / name).string());
  }
  ShortImage::Pointer input = const_cast<ShortImage*>(image);
  if (slices) {  // the first `slices` slices only
    auto part = ShortImage::New();
    auto region = image->GetLargestPossibleRegion();
    region.SetSize(2, slices);
    part->CopyInformation(image);
    part->SetRegions(region);
    part->Allocate();
    const std::size_t n = region.GetNumberOfPixels();
    std::copy(image->GetBufferPointer(), image->GetBufferPointer() + n, part->GetBufferPointer());
    input = part;
  }
  writer->SetInput(input);
  writer->SetImageIO(io);
  writer->SetFileNames(names);
  writer->SetMetaDataDictionaryArray(&dictionaries);
  writer->Update();
}

TEST(Formats, SameMeshFromMhaNrrdNiftiDicom) {
  const fs::path dir = work_dir();
  const auto phantom = itk::ReadImage<ShortImage>(kPhantom);
  ASSERT_NEAR(phantom->GetSpacing()[0], 0.5, 1e-12);
  ASSERT_NEAR(phantom->GetSpacing()[2], 2.0, 1e-12);
  // Move the phantom off the origin so that origins are checked too.
  auto image = ShortImage::New();
  image->Graft(phantom);
  const double origin[3] = {-12.25, 7.5, 103.0};
  image->SetOrigin(origin);

  itk::WriteImage(image, (dir / "phantom.mha").string());
  itk::WriteImage(image, (dir / "phantom.nrrd").string());
  itk::WriteImage(image, (dir / "phantom.nii.gz").string(), true);
  itk::WriteImage(image, (dir / "detached.mhd").string());
  itk::WriteImage(image, (dir / "detached.nhdr").string());
  itk::WriteImage(image, (dir / "legacy.vtk").string());
  write_dicom_series(image, dir / "dicom");

  // The DICOM series reads back with its spacing, origin and HU values.
  {
    GdmRun r = run_gdm(dir, {"dicom", "--threshold", "400", "-o", "dicom.off", "--report", "dicom.json", "--quiet"});
    ASSERT_EQ(r.code, 0) << r.err;
    const std::string json = slurp(dir / "dicom.json");
    const auto at = json.find("\"spacing_mm\"");
    ASSERT_NE(at, std::string::npos);
    EXPECT_EQ(json.substr(at, json.find(']', at) + 1 - at), "\"spacing_mm\": [0.5, 0.5, 2]") << "DICOM spacing read back";
    EXPECT_EQ(json_value(json, "value_min"), -1024.0);
  }

  std::map<std::string, Mesh> meshes;
  for (const std::string input :
       {"phantom.mha", "phantom.nrrd", "phantom.nii.gz", "dicom", "detached.mhd", "detached.nhdr", "legacy.vtk"}) {
    const std::string out = "mesh-" + std::to_string(meshes.size()) + ".off";
    GdmRun r = run_gdm(dir, {input, "--threshold", "400", "-o", out, "--quiet"});
    ASSERT_EQ(r.code, 0) << input << ": " << r.err;
    EXPECT_TRUE(r.out.empty()) << "--quiet printed: " << r.out;
    meshes[input] = read_mesh(dir / out);
  }
  const Mesh& reference = meshes["phantom.mha"];
  ASSERT_GT(reference.faces.size(), 1000u);
  for (const auto& [input, mesh] : meshes) {
    ASSERT_EQ(mesh.points.size(), reference.points.size()) << input;
    ASSERT_EQ(mesh.faces.size(), reference.faces.size()) << input;
    double worst = 0.0;
    for (std::size_t i = 0; i < mesh.points.size(); ++i)
      for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(mesh.points[i][d] - reference.points[i][d]));
    EXPECT_LE(worst, 1e-4) << input << ": largest coordinate difference to the MHA mesh, mm";
    EXPECT_EQ(mesh.faces, reference.faces) << input;
  }

  // The extent in mm: the mesh surface lies within one spacing of the outermost
  // voxel centres above T along every axis, give or take a hundredth of one:
  // the fit's noise-adaptive smoothing (surface_fit.h) may leave a vertex a
  // noise-level past the last crossing of the data (1.3 um on this phantom).
  const auto mesh_box = bounds(reference);
  const auto voxel_box = voxel_bounds(image.GetPointer(), 400.0, false);
  const auto spacing = image->GetSpacing();
  for (int d = 0; d < 3; ++d) {
    const double slack = 0.01 * spacing[d];
    EXPECT_LE(mesh_box[d], voxel_box[d] + 0.1 * spacing[d]) << "low bound, axis " << d;
    EXPECT_GE(mesh_box[d], voxel_box[d] - spacing[d] - slack) << "low bound, axis " << d;
    EXPECT_GE(mesh_box[d + 3], voxel_box[d + 3] - 0.1 * spacing[d]) << "high bound, axis " << d;
    EXPECT_LE(mesh_box[d + 3], voxel_box[d + 3] + spacing[d] + slack) << "high bound, axis " << d;
  }
  expect_valid_model(measure(reference));
}

// A folder with two series: gdm takes the one with most slices and says so,
// or the one named by --series.
TEST(Formats, DicomFolderWithTwoSeries) {
  const fs::path dir = work_dir();
  const auto phantom = itk::ReadImage<ShortImage>(kPhantom);
  write_dicom_series(phantom, dir / "two", "7", 20);
  write_dicom_series(phantom, dir / "two", "8", 0);
  const std::string root = "1.2.826.0.1.3680043.9.7433.1";
  GdmRun most = run_gdm(dir, {"two", "--threshold", "400", "--refinements", "0", "-o", "a.ply", "--report", "a.json"});
  ASSERT_EQ(most.code, 0) << most.err;
  EXPECT_NE(most.out.find("the folder holds 2 DICOM series; using the one with most slices (24)"), std::string::npos)
      << most.out;
  EXPECT_EQ(json_value(slurp(dir / "a.json"), "files"), 24.0);
  GdmRun chosen = run_gdm(dir, {"two", "--series", root + ".7", "--threshold", "400", "--refinements", "0", "-o",
                                "b.ply", "--report", "b.json", "--allow-border"});
  ASSERT_EQ(chosen.code, 0) << chosen.err;
  const std::string json = slurp(dir / "b.json");
  EXPECT_EQ(json_value(json, "files"), 20.0);
  EXPECT_NE(json.find("\"series_uid\": \"" + root + ".7"), std::string::npos) << json;
  EXPECT_NE(json.find("\"size\": [96, 96, 20]"), std::string::npos);
  // A single slice is a 2D image.
  GdmRun slice = run_gdm(dir, {(dir / "two" / "s8-001.dcm").string(), "-o", "d.ply"});
  EXPECT_EQ(slice.code, 3);
  EXPECT_NE(slice.err.find("is a 2D image; gdm needs a 3D volume (pass the folder of the DICOM series)"),
            std::string::npos) << slice.err;
  GdmRun unknown = run_gdm(dir, {"two", "--series", "1.2.3.4", "-o", "c.ply"});
  EXPECT_EQ(unknown.code, 2);
  EXPECT_NE(unknown.err.find("--series 1.2.3.4: no such series"), std::string::npos) << unknown.err;
  EXPECT_FALSE(fs::exists(dir / "c.ply"));
}

// A region of interest keeps physical positions, and --seed-index counts in
// the input's voxels: cropping around the object gives the same mesh.
TEST(Preprocess, RoiKeepsPhysicalPositions) {
  const fs::path dir = work_dir();
  GdmRun whole = run_gdm(dir, {"--seed-index", "48,48,16", "-o", "whole.off", "--quiet"});
  ASSERT_EQ(whole.code, 0) << whole.err;
  GdmRun cropped = run_gdm(dir, {"--roi", "8,8,0,88,88,23", "--seed-index", "48,48,16", "-o", "roi.off",
                                 "--report", "roi.json", "--quiet"});
  ASSERT_EQ(cropped.code, 0) << cropped.err;
  const Mesh a = read_mesh(dir / "whole.off");
  const Mesh b = read_mesh(dir / "roi.off");
  ASSERT_EQ(a.points.size(), b.points.size());
  double worst = 0.0;
  for (std::size_t i = 0; i < a.points.size(); ++i)
    for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(a.points[i][d] - b.points[i][d]));
  EXPECT_LE(worst, 1e-4);
  EXPECT_NE(slurp(dir / "roi.json").find("\"roi\": [8, 8, 0, 88, 88, 23]"), std::string::npos);
  // A box outside the volume is bad usage.
  GdmRun outside = run_gdm(dir, {"--roi", "0,0,0,200,10,10", "-o", "x.ply"});
  EXPECT_EQ(outside.code, 2);
  EXPECT_NE(outside.err.find("is not inside the volume (size 96 x 96 x 24 voxels"), std::string::npos) << outside.err;
  EXPECT_FALSE(fs::exists(dir / "x.ply"));
}

// ------------------------------------------------------- output formats --

TEST(Output, EveryFormatReadsBack) {
  const fs::path dir = work_dir();
  GdmRun r = run_gdm(dir, {"-o", "mesh.ply", "--report", "run.json", "--refinements", "0"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string json = slurp(dir / "run.json");
  const double vertices = json_value(json, "vertices");
  const double faces = json_value(json, "faces");
  const double max_generation = json_value(json, "max_generation");
  ASSERT_GT(faces, 100.0);
  EXPECT_NE(r.out.find("closed yes, manifold yes"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("cycle 1 "), std::string::npos) << "no progress line per cycle on stderr: " << r.err;

  const Mesh ply = read_mesh(dir / "mesh.ply");
  EXPECT_EQ(ply.points.size(), vertices);
  EXPECT_EQ(ply.faces.size(), faces);
  ASSERT_EQ(ply.generation.size(), ply.points.size());
  EXPECT_EQ(*std::max_element(ply.generation.begin(), ply.generation.end()), max_generation);
  EXPECT_EQ(*std::min_element(ply.generation.begin(), ply.generation.end()), 0) << "the seed's vertices are generation 0";
  EXPECT_GT(max_generation, 1.0);

  for (const std::string ext : {"obj", "stl", "off", "vtk"}) {
    GdmRun again = run_gdm(dir, {"-o", "mesh." + ext, "--refinements", "0", "--quiet"});
    ASSERT_EQ(again.code, 0) << ext << ": " << again.err;
    const Mesh mesh = read_mesh(dir / ("mesh." + ext));
    EXPECT_EQ(mesh.points.size(), vertices) << ext;
    EXPECT_EQ(mesh.faces.size(), faces) << ext;
    const gdm::MeshReport m = measure(mesh);
    EXPECT_TRUE(m.closed) << ext;
    EXPECT_TRUE(m.two_manifold) << ext;
    EXPECT_EQ(m.components, 1) << ext;
    EXPECT_GT(m.volume, 0.0) << ext << ": faces must be oriented outwards";
    EXPECT_NEAR(m.volume, json_value(json, "volume_mm3"), 1e-3 * m.volume) << ext;
  }
  // The VTK file carries the generation as point data.
  EXPECT_NE(slurp(dir / "mesh.vtk").find("SCALARS generation int 1"), std::string::npos);
  // Nothing but the outputs (no temporaries) is left.
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
    ++files;
  }
  EXPECT_EQ(files, 6u);
}

TEST(Output, ReportHoldsEveryParameter) {
  const fs::path dir = work_dir();
  GdmRun r = run_gdm(dir, {"--a2", "4.5", "--lod", "12", "--threads", "1", "--refinements", "0", "-o", "m.obj",
                        "--report", "r.json", "--quiet"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string json = slurp(dir / "r.json");
  EXPECT_EQ(json_value(json, "a2"), 4.5);
  EXPECT_EQ(json_value(json, "lod_face_area"), 12.0);
  EXPECT_EQ(json_value(json, "threads"), 1.0);
  EXPECT_EQ(json_value(json, "global_refinements"), 0.0);
  EXPECT_NE(json.find("\"status\": \"ok\""), std::string::npos);
  EXPECT_NE(json.find("\"source\": \"phantom default\""), std::string::npos);
  // Every option of --help is in the report's parameters.
  GdmRun help = run_gdm(dir, {"--help"});
  ASSERT_EQ(help.code, 0);
  std::istringstream lines(help.out);
  std::string line;
  int options = 0;
  while (std::getline(lines, line)) {
    if (line.rfind("  --", 0) != 0) continue;
    std::string name = line.substr(4, line.find_first_of(" \n", 4) - 4);
    if (name == "help" || name == "version") continue;
    std::replace(name.begin(), name.end(), '-', '_');  // the report spells options as the catalogue does
    ++options;
    EXPECT_NE(json.find("\"" + name + "\":"), std::string::npos) << name << " is not in the report";
    if (line.find(" N ") != std::string::npos || line.find("[") != std::string::npos) continue;
  }
  EXPECT_GE(options, 35);
  // Escaping.
  EXPECT_EQ(gdm_cli::json_string("a\"b\\c\n\x01"), "\"a\\\"b\\\\c\\n\\u0001\"");
  EXPECT_EQ(gdm_cli::json_number(0.1), "0.1");
  EXPECT_EQ(gdm_cli::json_number(std::nan("")), "null");
}

TEST(Output, HelpDocumentsOptionsAndExitCodes) {
  const fs::path dir = work_dir();
  GdmRun r = run_gdm(dir, {"--help"});
  ASSERT_EQ(r.code, 0);
  for (const char* s : {"--threshold", "--polarity", "--seed", "--seed-index", "--seed-radius", "--seed-mesh",
                        "--smooth", "--roi", "--series", "--mode", "--a0", "--a1", "--a2", "--lod-face-area", "(also --lod)",
                        "--global-refinements", "(also --refinements)",
                        "--max-cycles", "--threads", "--report", "--quiet", "Exit codes", "default: 10]",
                        "[mm; default: 0]", "--subvoxel-fit on|off", "--fit-passes N", "--fit-max-distance X", "--fit-smoothing X",
                        "--lod-tolerance X", "--lod-min-angle X", "--lod-rounds N", "--max-topology-ratio X",
                        "--refinement-travel X", "--float-exact-output on|off", "(also --float-exact)", "[voxels; default: 0]",
                        "[degrees; default: 15]", "[rounds; default: 6]"})
    EXPECT_NE(r.out.find(s), std::string::npos) << s;
}

// Progress: updated in place on a terminal (a pseudo-terminal from script(1)),
// plain lines otherwise, nothing with --quiet.
TEST(Output, ProgressOnATerminal) {
  if (std::system("command -v script >/dev/null 2>&1") != 0) GTEST_SKIP() << "script(1) is not installed";
  const fs::path dir = work_dir();
  const std::string log = (dir / "tty.txt").string();
  const std::string command = "cd " + quote(dir.string()) + " && script -qec " +
                              quote(quote(kGdm) + " --refinements 0 -o tty.ply") + " /dev/null > " + quote(log);
  const int status = std::system(command.c_str());
  const std::string text = slurp(log);
  if (status != 0 && text.find("input:") == std::string::npos)
    GTEST_SKIP() << "script(1) could not run gdm on a pseudo-terminal: " << text;
  ASSERT_EQ(status, 0) << text;
  const auto first = text.find("\rcycle     1 ");
  ASSERT_NE(first, std::string::npos) << text;
  EXPECT_EQ(text.find("cycle 1 stage"), std::string::npos) << "plain lines on a terminal";
  // The in-place line carries the cycle's faces and moving vertices: the seed
  // (an icosahedron subdivided once, 80 faces) moves in its first cycle.
  std::size_t cycle = 0, stage = 9, faces = 0, moving = 0;
  ASSERT_EQ(std::sscanf(text.c_str() + first, "\rcycle %zu stage %zu faces %zu moving %zu", &cycle, &stage, &faces,
                        &moving), 4)
      << text.substr(first, 80);
  EXPECT_EQ(cycle, 1u);
  EXPECT_EQ(stage, 0u);
  EXPECT_GE(faces, 80u);
  EXPECT_GT(moving, 0u);
  GdmRun quiet = run_gdm(dir, {"--refinements", "0", "-o", "q.ply", "--quiet"});
  ASSERT_EQ(quiet.code, 0);
  EXPECT_TRUE(quiet.err.empty()) << quiet.err;
  EXPECT_TRUE(quiet.out.empty()) << quiet.out;
}

void expect_failure(const fs::path& dir, std::vector<std::string> args, int code, const std::string& message);

// Progress when stderr is not a terminal: one plain line per cycle with the
// cycle's faces and moving vertices, consistent with the report.
TEST(Output, ProgressLinesPerCycle) {
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {"-o", "p.ply", "--report", "p.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string json = slurp(dir / "p.json");
  std::istringstream lines(r.err);
  std::string line;
  std::size_t expected = 1, last_faces = 0, moved_total = 0, last_stage = 0;
  while (std::getline(lines, line)) {
    std::size_t cycle = 0, stage = 0, faces = 0, moving = 0;
    int percent = -1;
    ASSERT_EQ(std::sscanf(line.c_str(), "cycle %zu stage %zu faces %zu moving %zu progress %d%%", &cycle, &stage,
                          &faces, &moving, &percent), 5)
        << "not a progress line: " << line;
    EXPECT_EQ(cycle, expected++) << line;
    EXPECT_GE(stage, last_stage) << line;
    EXPECT_EQ(faces % 2, 0u) << "a closed triangle mesh has an even face count: " << line;
    EXPECT_GE(faces, 80u) << line;
    EXPECT_GE(percent, 0);
    EXPECT_LT(percent, 100);
    last_faces = faces;
    last_stage = stage;
    moved_total += moving;
  }
  EXPECT_EQ(static_cast<double>(expected - 1), json_value(json, "cycles")) << "one line per cycle";
  EXPECT_EQ(static_cast<double>(last_stage), json_value(json, "global_refinements"));
  // Without the error-driven level of detail the final fit keeps the faces;
  // the sharp edges (sharp_edges) and the triangle-quality pass (min_angle)
  // add two per split, the quality pass removes two per collapse.
  EXPECT_EQ(static_cast<double>(last_faces) + 2.0 * json_value(json, "sharp_edge_splits") +
                2.0 * json_value(json, "quality_splits") - 2.0 * json_value(json, "quality_collapses"),
            json_value(json, "faces"));
  EXPECT_GT(moved_total, 0u);
}

// The report and the summary give the run's peak memory (the process's
// largest resident set): more than the volume it read, in MB.
TEST(Output, ReportsPeakMemory) {
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {"--refinements", "0", "-o", "m.ply", "--report", "m.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const double peak = json_value(slurp(dir / "m.json"), "peak_memory_mb");
  // The phantom's floats alone are 64^3 x 4 bytes = 1 MB.
  EXPECT_GT(peak, 1.0);
  EXPECT_LT(peak, 1.0e6);
  const auto at = r.out.find("peak memory ");
  ASSERT_NE(at, std::string::npos) << r.out;
  EXPECT_NEAR(std::strtod(r.out.c_str() + at + 12, nullptr), peak, 1.0) << r.out;
}

// The error-driven level of detail (--lod-tolerance): a closed manifold mesh
// with a different face count, the work reported; bad values of the new
// options are bad usage naming the option.
TEST(Model, ErrorDrivenLevelOfDetail) {
  const fs::path dir = work_dir();
  const GdmRun plain = run_gdm(dir, {"-o", "a.ply", "--report", "a.json"});
  ASSERT_EQ(plain.code, 0) << plain.err;
  const GdmRun lod = run_gdm(dir, {"--lod-tolerance", "0.1", "-o", "b.ply", "--report", "b.json"});
  ASSERT_EQ(lod.code, 0) << lod.err;
  const std::string a = slurp(dir / "a.json");
  const std::string b = slurp(dir / "b.json");
  EXPECT_EQ(json_value(b, "lod_tolerance"), 0.1);
  EXPECT_EQ(json_value(a, "lod_tolerance"), 0.0);
  EXPECT_EQ(json_value(a, "lod_splits"), 0.0);
  EXPECT_EQ(json_value(a, "lod_collapses"), 0.0);
  EXPECT_GT(json_value(a, "fit_moves"), 0.0) << "the sub-voxel fit is on by default";
  EXPECT_GT(json_value(b, "lod_collapses"), 0.0);
  EXPECT_NE(lod.out.find("lod collapses"), std::string::npos) << lod.out;
  EXPECT_EQ(plain.out.find("lod collapses"), std::string::npos) << plain.out;

  const Mesh mesh_a = read_mesh(dir / "a.ply");
  const Mesh mesh_b = read_mesh(dir / "b.ply");
  const gdm::MeshReport ra = measure(mesh_a);
  const gdm::MeshReport rb = measure(mesh_b);
  expect_valid_model(rb);
  EXPECT_NE(mesh_b.faces.size(), mesh_a.faces.size());
  EXPECT_EQ(static_cast<double>(mesh_b.faces.size()), json_value(b, "faces"));
  // Both describe the same object: within 1% of each other's volume.
  EXPECT_NEAR(rb.volume, ra.volume, 0.01 * ra.volume);
  std::cout << "default: " << mesh_a.faces.size() << " faces, " << ra.volume << " mm^3; --lod-tolerance 0.1: "
            << mesh_b.faces.size() << " faces, " << rb.volume << " mm^3" << std::endl;

  // The other new options reach the core and the report.
  const GdmRun options = run_gdm(dir, {"--refinements", "0", "--subvoxel-fit", "off", "--float-exact", "off",
                                       "--max-topology-ratio", "inf", "--refinement-travel", "2", "--fit-passes", "3",
                                       "--fit-max-distance", "0.5", "--fit-smoothing", "1.5", "--lod-min-angle", "10",
                                       "--lod-rounds", "2",
                                       "-o", "c.ply", "--report", "c.json", "--quiet"});
  ASSERT_EQ(options.code, 0) << options.err;
  const std::string c = slurp(dir / "c.json");
  EXPECT_EQ(json_value(c, "fit_moves"), 0.0) << "--subvoxel-fit off";
  EXPECT_NE(c.find("\"subvoxel_fit\": false"), std::string::npos);
  EXPECT_NE(c.find("\"float_exact_output\": false"), std::string::npos);
  EXPECT_NE(c.find("\"max_topology_ratio\": \"inf\""), std::string::npos);
  EXPECT_EQ(json_value(c, "refinement_travel"), 2.0);
  EXPECT_EQ(json_value(c, "fit_passes"), 3.0);
  EXPECT_EQ(json_value(c, "fit_max_distance"), 0.5);
  EXPECT_EQ(json_value(c, "fit_smoothing"), 1.5);
  EXPECT_EQ(json_value(c, "lod_min_angle"), 10.0);
  EXPECT_EQ(json_value(c, "lod_rounds"), 2.0);

  // Bad values: exit 2, the option named, no output.
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"--lod-tolerance", "-1"}, "--lod-tolerance: must be 0 (off) or in [0.01, 10], got -1"},
      {{"--lod-tolerance", "0.001"}, "--lod-tolerance: must be 0 (off) or in [0.01, 10]"},
      {{"--fit-passes", "0"}, "--fit-passes: must be in [1, 20], got 0"},
      {{"--fit-max-distance", "0"}, "--fit-max-distance: must be in (0, 4], got 0"},
      {{"--fit-smoothing", "-1"}, "--fit-smoothing: must be in [0, 5], got -1"},
      {{"--lod-min-angle", "60"}, "--lod-min-angle: must be in [0, 60), got 60"},
      {{"--lod-rounds", "51"}, "--lod-rounds: must be in [1, 50], got 51"},
      {{"--max-topology-ratio", "0"}, "--max-topology-ratio: must be > 0"},
      {{"--refinement-travel", "-2"}, "--refinement-travel: must be > 0"},
      {{"--subvoxel-fit", "maybe"}, "--subvoxel-fit: must be on or off, got maybe"},
      {{"--float-exact", "2"}, "--float-exact: must be on or off, got 2"},
  };
  for (const auto& [args, message] : bad) {
    const fs::path bad_dir = dir / ("bad-" + args[0].substr(2));
    fs::create_directories(bad_dir);
    expect_failure(bad_dir, args, 2, message);
  }
}

// The face budget (--faces N): the model has about N faces (within 5 %),
// every guarantee holds, the summary and the report say what was asked and
// obtained; an absurd budget is bad usage (exit 2) with a message.
TEST(Model, FaceBudget) {
  const fs::path dir = work_dir();
  for (const int n : {600, 2500}) {
    const std::string mesh = "b" + std::to_string(n) + ".ply", json = "b" + std::to_string(n) + ".json";
    const GdmRun r = run_gdm(dir, {"--faces", std::to_string(n), "-o", mesh, "--report", json});
    ASSERT_EQ(r.code, 0) << r.err;
    const Mesh m = read_mesh(dir / mesh);
    expect_valid_model(measure(m));
    EXPECT_NEAR(static_cast<double>(m.faces.size()), n, 0.05 * n);
    const std::string report = slurp(dir / json);
    EXPECT_EQ(json_value(report, "face_budget"), n);
    EXPECT_EQ(json_value(report, "budget_faces"), static_cast<double>(m.faces.size()));
    EXPECT_GT(json_value(report, "budget_collapses"), 0.0);
    EXPECT_NE(r.out.find("face budget: " + std::to_string(n) + " faces requested, " + std::to_string(m.faces.size()) +
                         " obtained"),
              std::string::npos)
        << r.out;
  }
  // Bad values: exit 2, a message, no output.
  const std::vector<std::pair<std::vector<std::string>, std::string>> bad = {
      {{"--faces", "10"}, "--faces: must be 0 (off) or in [20, 1e+09], got 10"},
      {{"--faces", "-5"}, "--faces: must be 0 (off) or in [20, 1e+09], got -5"},
      {{"--faces", "many"}, "--faces"},
      {{"--faces", "3000000"}, "face_budget 3000000 is above max_faces 2000000"},
      {{"--faces", "500", "--lod-tolerance", "0.1"}, "face_budget and lod_tolerance both choose the number of faces"},
  };
  int i = 0;
  for (const auto& [args, message] : bad) {
    const fs::path bad_dir = dir / ("bad-" + std::to_string(i++));
    fs::create_directories(bad_dir);
    expect_failure(bad_dir, args, 2, message);
  }
}

// A seed mesh file gives the same model as the same polyhedron built in.
TEST(Seed, SeedMeshFile) {
  const fs::path dir = work_dir();
  const gdm::Mesh ico = gdm::make_icosahedron(gdm::Vec3(22, 24, 32), 2.0);
  {
    std::ofstream obj(dir / "ico.obj");
    obj.precision(17);
    for (auto v : ico.vertices()) obj << "v " << ico.point(v)[0] << ' ' << ico.point(v)[1] << ' ' << ico.point(v)[2] << '\n';
    for (auto f : ico.faces()) {
      obj << 'f';
      for (auto v : ico.fv_range(f)) obj << ' ' << v.idx() + 1;
      obj << '\n';
    }
  }
  GdmRun from_file = run_gdm(dir, {"--seed-mesh", "ico.obj", "-o", "a.off", "--report", "a.json", "--quiet"});
  ASSERT_EQ(from_file.code, 0) << from_file.err;
  GdmRun built_in = run_gdm(dir, {"--seed", "22,24,32", "--seed-radius", "2", "--seed-level", "0", "-o", "b.off",
                                  "--report", "b.json", "--quiet"});
  ASSERT_EQ(built_in.code, 0) << built_in.err;
  const double a = json_value(slurp(dir / "a.json"), "volume_mm3");
  const double b = json_value(slurp(dir / "b.json"), "volume_mm3");
  EXPECT_NEAR(a, b, 0.01 * b);
  EXPECT_NE(slurp(dir / "a.json").find("\"source\": \"mesh\""), std::string::npos);
  const gdm::MeshReport m = measure(read_mesh(dir / "a.off"));
  EXPECT_TRUE(m.closed);
  EXPECT_TRUE(m.two_manifold);
  // A seed mesh reaching outside the volume is bad usage; an unreadable one bad input.
  std::ofstream(dir / "far.obj") << "v 0 0 -50\nv 10 0 -50\nv 0 10 -50\nv 0 0 -40\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 3 1 4\n";
  GdmRun far = run_gdm(dir, {"--seed-mesh", "far.obj", "-o", "far.ply"});
  EXPECT_EQ(far.code, 2);
  EXPECT_NE(far.err.find("is outside the volume"), std::string::npos) << far.err;
  GdmRun missing = run_gdm(dir, {"--seed-mesh", "none.vtk", "-o", "none.ply"});
  EXPECT_EQ(missing.code, 3);
  EXPECT_NE(missing.err.find("cannot read the seed mesh none.vtk"), std::string::npos) << missing.err;
}

// --------------------------------------------------------- real scans --

TEST(RealData, CtPhantomDicomSeries) {
  const fs::path series = kShared + "/data/ct-phantom-dicom/series";
  if (!fs::exists(series)) GTEST_SKIP() << "the DICOM series " << series << " is absent";
  const fs::path dir = work_dir();
  // A coarse level of detail and a cycle budget keep the test short (the
  // model does not converge within 2000 cycles on this scan; at 600 it encloses
  // 99% of the volume it has at 2000); the head phantom fills the scanned
  // slab, so its top and bottom touch the volume border.
  GdmRun r = run_gdm(dir, {series.string(), "--seed", "auto", "--threshold", "-400", "--smooth", "1", "--lod", "100",
                           "--refinements", "0", "--max-cycles", "600", "--allow-border", "-o", "ct.ply", "--report",
                           "ct.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  std::cout << r.out;
  const std::string json = slurp(dir / "ct.json");
  EXPECT_NEAR(json_value(json, "value_min"), -1024.0, 1e-9) << "rescale intercept applied (HU)";
  const auto at = json.find("\"spacing_mm\"");
  ASSERT_NE(at, std::string::npos);
  std::array<double, 3> spacing{};
  std::sscanf(json.c_str() + at, "\"spacing_mm\": [%lf, %lf, %lf]", &spacing[0], &spacing[1], &spacing[2]);
  EXPECT_NEAR(spacing[0], 0.451, 0.001);
  EXPECT_NEAR(spacing[1], 0.451, 0.001);
  EXPECT_NEAR(spacing[2], 5.0, 1e-3);

  const Mesh mesh = read_mesh(dir / "ct.ply");
  const gdm::MeshReport m = measure(mesh);
  EXPECT_TRUE(m.closed);
  EXPECT_TRUE(m.two_manifold);
  EXPECT_EQ(m.components, 1);
  // The extent in mm fits the 512 x 512 x 28 grid at 0.451 x 0.451 x 5 mm: the
  // phantom spans the whole slab in z (27 slice gaps = 135 mm, far more than a
  // misread 1 mm slice spacing could give) and is about 150 mm wide.
  const auto b = bounds(mesh);
  EXPECT_NEAR(b[5] - b[2], 27 * 5.0, 5.0);
  EXPECT_GT(b[3] - b[0], 100.0);
  EXPECT_LT(b[3] - b[0], 512 * 0.4512);
  EXPECT_GT(b[4] - b[1], 100.0);
  EXPECT_LT(b[4] - b[1], 512 * 0.4512);
}

// A growing model's vertices do not pile up (deformer.cpp,
// piles_onto_a_neighbour): on this part of the CT head phantom's 5 mm
// slices the image draws the vertices the local resampling makes at a
// spike's tip to one point; before the rule, 24 edges of the model (fit and
// triangle quality off, so the cycles' own edges are what is read back)
// were shorter than a tenth of a voxel, the shortest 0.0000, and the
// smallest angle 0 degrees.
TEST(RealData, CtVerticesDoNotPileUp) {
  const fs::path series = kShared + "/data/ct-phantom-dicom/series";
  if (!fs::exists(series)) GTEST_SKIP() << "the DICOM series " << series << " is absent";
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {series.string(), "--roi", "148,234,0,268,354,12", "--threshold", "-375", "--subvoxel-fit",
                                 "off", "--min-angle", "0", "-o", "crop.ply", "--report", "crop.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const Mesh mesh = read_mesh(dir / "crop.ply");
  const gdm::MeshReport m = measure(mesh);
  EXPECT_TRUE(m.closed);
  EXPECT_TRUE(m.two_manifold);
  EXPECT_EQ(m.self_intersections, 0u);
  const double voxel = 0.451171875;  // the smallest spacing
  double shortest = std::numeric_limits<double>::infinity();
  std::size_t short_edges = 0;
  for (const auto& f : mesh.faces)
    for (int k = 0; k < 3; ++k) {  // each edge twice (once from each of its faces): counted in halves
      const auto& a = mesh.points[f[static_cast<std::size_t>(k)]];
      const auto& b = mesh.points[f[static_cast<std::size_t>((k + 1) % 3)]];
      const double length = std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]) / voxel;
      shortest = std::min(shortest, length);
      short_edges += length < 0.1;
    }
  std::printf("%zu faces, shortest edge %.4f voxel\n", mesh.faces.size(), shortest);
  EXPECT_EQ(short_edges / 2, 0u) << "shortest " << shortest << " voxel";
  EXPECT_GT(m.min_angle_deg, 0.5);
}

// A real scan at the defaults: no angle below the default bound of 10
// degrees, and a valid model; `file` skips the test when absent.
void expect_no_angle_below_the_bound_at_the_defaults(const fs::path& file) {
  if (!fs::exists(file)) GTEST_SKIP() << "the scan " << file << " is absent";
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {file.string(), "-o", "model.ply", "--report", "model.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string json = slurp(dir / "model.json");
  EXPECT_EQ(json_value(json, "faces_below_min_angle"), 0.0);
  EXPECT_GT(json_value(json, "quality_moves"), 0.0);
  const gdm::MeshReport m = measure(read_mesh(dir / "model.ply"));
  expect_valid_model(m);
  EXPECT_GE(m.min_angle_deg, 10.0);
}

// The CT head phantom at the defaults. One needle (9.5 degrees) was left on
// the crest of a thin fin, where the faces' normals cancel and the
// relaxation finds no tangent plane, until the quality pass slid the corners
// of the faces it left along their edges; with the curvature correction one
// (9.97 degrees) at a crumpled apex, until the pass's last nudge (issue 16).
// The whole model at the defaults takes about a minute (Release, 2 cores):
// skipped in the sanitizer build.
TEST(RealData, CtHeadAtTheDefaultsHasNoAngleBelowTheBound) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer build: the CT head at the defaults is left to the Release run";
#endif
  expect_no_angle_below_the_bound_at_the_defaults(kShared + "/data/ct-phantom-dicom/series");
}

// The T1 MRI head at the defaults: two faces were left below 10 degrees
// (9.80 the smallest) until the quality pass's last nudge (issue 16, stop
// 59). About 35 s (Release, 2 cores): skipped in the sanitizer build.
TEST(RealData, T1HeadAtTheDefaultsHasNoAngleBelowTheBound) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer build: the T1 head at the defaults is left to the Release run";
#endif
  expect_no_angle_below_the_bound_at_the_defaults(kShared + "/data/mri-head-t1/chris_t1.nii.gz");
}

// The README's command for the T1 head from the object's voxels, as written
// (a binary PLY: float coordinates). Its model had a strip of faces folded
// flat sixteen times between two points (each vertex split off a long edge
// moved onto the point where the vertex two before it sat, a neighbour's
// neighbour): no float can separate layers 1e-9 mm apart, 23 vertices kept
// double coordinates and the PLY held 1,239 crossing face pairs (stop 65).
// About 35 s (Release, 2 cores): skipped in the sanitizer build.
TEST(RealData, T1HeadFromItsVoxelsWritesAPlyThatKeepsTheGuarantees) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer build: the T1 head is left to the Release run";
#endif
  const fs::path file = kShared + "/data/mri-head-t1/chris_t1.nii.gz";
  if (!fs::exists(file)) GTEST_SKIP() << "the scan " << file << " is absent";
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {file.string(), "--voxel-seed", "-o", "head.ply", "--report", "head.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(json_value(slurp(dir / "head.json"), "float_refused"), 0.0);
  const gdm::MeshReport m = measure(read_mesh(dir / "head.ply"));
  expect_valid_model(m);
  EXPECT_GE(m.min_angle_deg, 10.0);
}

// Two scans whose object the scan cuts (the EPI head at its top and bottom
// slices, neghip's blobs at the x sides), at the defaults: no flag needed,
// the summary and the report say the border was allowed and why.
// The whole tooth (T 115, a seed in the dentin) ends a voxel short of the
// scan's last slice: its region lies on the border's second layer, which the
// model reaches within a voxel, so it counts as cut too. No angle below the
// default bound of 10 degrees (on the EPI head one needle was left at 9.65
// degrees before the quality pass's pairs of collapses, issue 16).
TEST(RealData, ObjectsTheScanCutsWorkAtTheDefaults) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> scans = {
      {"mri-epi/mha.mha", {}}, {"neghip/neghip.mhd", {}}, {"tooth/tooth.mhd", {"--threshold", "115", "--seed", "56,56,70"}}};
  for (const auto& [name, options] : scans) {
    const fs::path file = kShared + "/data/" + name;
    if (!fs::exists(file)) GTEST_SKIP() << "the scan " << file << " is absent";
    const fs::path dir = work_dir();
    std::vector<std::string> args = {file.string(), "-o", "out.ply", "--report", "out.json"};
    args.insert(args.end(), options.begin(), options.end());
    const GdmRun r = run_gdm(dir, args);
    ASSERT_EQ(r.code, 0) << name << ": " << r.err;
    EXPECT_NE(r.out.find("the object is cut by the scan"), std::string::npos) << r.out;
    const std::string json = slurp(dir / "out.json");
    EXPECT_NE(json.find("\"cut_by_scan\": true"), std::string::npos) << json;
    EXPECT_LT(json_value(json, "border_fraction"), 0.25);
    EXPECT_GT(json_value(json, "border_vertices"), 0.0);
    const gdm::MeshReport m = measure(read_mesh(dir / "out.ply"));
    EXPECT_TRUE(m.closed) << name;
    EXPECT_TRUE(m.two_manifold) << name;
    EXPECT_EQ(m.genus, 0) << name;
    EXPECT_EQ(m.self_intersections, 0u) << name;
    EXPECT_GE(m.min_angle_deg, 10.0) << name;
    EXPECT_EQ(json_value(json, "faces_below_min_angle"), 0.0) << name;
  }
}

// Seams (where a growing model's fronts met, self_contact.h) on more than 1 %
// of the model's area get the summary's hint to start from the object's
// voxels (and "seams_worth_a_voxel_seed": true in the report), less get
// neither; started from its voxels, a model has no hint. Neghip's blobs and
// the EPI head leave seams at the defaults (82 and 2,145 mm^2 when this was
// written, 1.4 and 2.7 % of their areas; 0 from their voxels): at least one
// of them must get the hint, or the test says nothing.
TEST(RealData, SeamsGetTheHintToStartFromTheVoxels) {
  int hinted = 0;
  for (const std::string name : {"neghip/neghip.mhd", "mri-epi/mha.mha"}) {
    const fs::path file = kShared + "/data/" + name;
    if (!fs::exists(file)) GTEST_SKIP() << "the scan " << file << " is absent";
    const fs::path dir = work_dir();
    const GdmRun grown = run_gdm(dir, {file.string(), "-o", "grown.ply", "--report", "grown.json"});
    ASSERT_EQ(grown.code, 0) << name << ": " << grown.err;
    const std::string json = slurp(dir / "grown.json");
    const bool worth = json_value(json, "seam_area_mm2") > 0.01 * measure(read_mesh(dir / "grown.ply")).area;
    hinted += worth ? 1 : 0;
    EXPECT_EQ(grown.out.find(gdm_cli::kVoxelSeedHint) != std::string::npos, worth) << name << ": " << grown.out;
    EXPECT_NE(json.find(std::string("\"seams_worth_a_voxel_seed\": ") + (worth ? "true" : "false")), std::string::npos)
        << name;
    const GdmRun voxels = run_gdm(dir, {file.string(), "--voxel-seed", "-o", "voxels.ply", "--report", "voxels.json"});
    ASSERT_EQ(voxels.code, 0) << name << ": " << voxels.err;
    EXPECT_EQ(voxels.out.find("hint: --voxel-seed"), std::string::npos) << name << ": " << voxels.out;
    EXPECT_NE(slurp(dir / "voxels.json").find("\"seams_worth_a_voxel_seed\": false"), std::string::npos) << name;
    if (worth)  // the hint's promise, where the cavity fill left no handle open (it caps them by default)
      EXPECT_LT(json_value(slurp(dir / "voxels.json"), "seam_area_mm2"), 0.01 * measure(read_mesh(dir / "voxels.ply")).area)
          << name;
  }
  EXPECT_GE(hinted, 1) << "neither scan's grown model left seams on over 1 % of its area";
}

TEST(RealData, ToothPulp) {
  const std::string file = kShared + "/data/tooth/tooth.mhd";
  if (!fs::exists(file)) GTEST_SKIP() << "the tooth " << file << " is absent";
  const fs::path dir = work_dir();
  constexpr double kThreshold = 115.0;

  // The pulp: the 6-connected voxels below T flood-filled from the seed voxel.
  using ImageType = itk::Image<unsigned char, 3>;
  const auto image = itk::ReadImage<ImageType>(file);
  const auto size = image->GetLargestPossibleRegion().GetSize();
  const unsigned char* v = image->GetBufferPointer();
  const gdm::Volume volume({static_cast<int>(size[0]), static_cast<int>(size[1]), static_cast<int>(size[2])},
                           std::vector<float>(v, v + size[0] * size[1] * size[2]));
  const std::vector<char> pulp = gdm::phantoms::region_below(volume, {50, 47, 95}, kThreshold);
  const auto count = static_cast<std::size_t>(std::count(pulp.begin(), pulp.end(), 1));
  const auto s = image->GetSpacing();
  const double voxels_mm3 = static_cast<double>(count) * s[0] * s[1] * s[2];

  // Level of detail 4 voxel^2: the root canals are 2 to 4 voxels wide. At the
  // paper's 10 voxel^2 the model bridges their narrow parts (-12 % of the
  // flood fill); at 4, -3.5 % (15962 mm^3). The error-driven level of detail
  // (--lod-tolerance 0.1) on top keeps that accuracy with fewer than a third
  // of the faces (measured: 2418 instead of 8248). (--refine-channels follows
  // the canals at any level of detail: +0.5 %, see the gap tests.)
  std::size_t faces[2] = {0, 0};
  for (const bool error_driven : {false, true}) {
    std::vector<std::string> args = {file, "--threshold", "115", "--polarity", "dark", "--seed-index", "50,47,95",
                                     "--lod", "4", "-o", "pulp.ply", "--report", "pulp.json"};
    if (error_driven) args.insert(args.end(), {"--lod-tolerance", "0.1"});
    const GdmRun r = run_gdm(dir, args);
    ASSERT_EQ(r.code, 0) << r.err;
    std::cout << r.out;
    const Mesh mesh = read_mesh(dir / "pulp.ply");
    const gdm::MeshReport m = measure(mesh);
    EXPECT_TRUE(m.closed);
    EXPECT_TRUE(m.two_manifold);
    EXPECT_EQ(m.components, 1);
    EXPECT_EQ(m.self_intersections, 0u);
    faces[error_driven] = mesh.faces.size();
    const double ratio = m.volume / voxels_mm3;
    std::cout << "tooth pulp" << (error_driven ? " with --lod-tolerance 0.1" : "") << ": " << mesh.faces.size()
              << " faces, model volume " << m.volume << " mm^3, flood-filled pulp " << count
              << " voxels = " << voxels_mm3 << " mm^3, ratio " << ratio << " (" << 100.0 * (ratio - 1.0) << " %)"
              << std::endl;
    EXPECT_NEAR(ratio, 1.0, 0.05);
  }
  EXPECT_LT(2 * faces[1], faces[0]) << "the error-driven level of detail coarsens where the surface is flat";
}

// ------------------------------------------------------------ bad input --

// Runs gdm expecting `code` and `message` on stderr, and no output file.
void expect_failure(const fs::path& dir, std::vector<std::string> args, int code, const std::string& message) {
  args.insert(args.end(), {"-o", "out.ply", "--report", "out.json"});
  const GdmRun r = run_gdm(dir, args);
  EXPECT_EQ(r.code, code) << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << "stderr: " << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.ply"));
  EXPECT_FALSE(fs::exists(dir / "out.json"));
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

TEST(BadInput, MissingFile) { expect_failure(work_dir(), {"no-such-scan.nii.gz"}, 3, "no such file or folder: no-such-scan.nii.gz"); }

TEST(BadInput, FolderWithoutDicom) {
  const fs::path dir = work_dir();
  fs::create_directories(dir / "empty");
  std::ofstream(dir / "empty" / "notes.txt") << "not a DICOM file\n";
  expect_failure(dir, {"empty"}, 3, "no DICOM series in the folder empty");
}

TEST(BadInput, TwoDimensionalImage) {
  const fs::path dir = work_dir();
  using Image2 = itk::Image<unsigned char, 2>;
  auto image = Image2::New();
  image->SetRegions(Image2::RegionType(Image2::SizeType{{16, 16}}));
  image->Allocate();
  image->FillBuffer(7);
  image->SetPixel({{4, 4}}, 200);
  itk::WriteImage(image, (dir / "slice.mha").string());
  expect_failure(dir, {"slice.mha"}, 3, "slice.mha is a 2D image");
}

TEST(BadInput, CorruptMhaHeader) {
  const fs::path dir = work_dir();
  std::ofstream(dir / "broken.mha") << "ObjectType = Image\nNDims = 3\nDimSize = 10 ten 10\nElementType = MET_BANANA\n"
                                     << "ElementDataFile = LOCAL\n\x01\x02\x03";
  expect_failure(dir, {"broken.mha"}, 3, "broken.mha");
}

TEST(BadInput, SeedOutsideTheVolume) {
  expect_failure(work_dir(), {"--seed", "1000,0,0"}, 2, "the seed centre (1000, 0, 0) mm is outside the volume");
}

TEST(BadInput, SeedIndexOutsideTheVolume) {
  expect_failure(work_dir(), {"--seed-index", "10,10,99"}, 2, "the seed index 10,10,99 is outside the volume");
}

TEST(BadInput, UnknownOption) { expect_failure(work_dir(), {"--frobnicate"}, 2, "unknown option '--frobnicate'"); }

TEST(BadInput, NegativeSigma) { expect_failure(work_dir(), {"--smooth", "-1"}, 2, "--smooth: must be in [0, 1000], got -1"); }

TEST(BadInput, ThresholdOutsideTheRange) {
  expect_failure(work_dir(), {"--threshold", "5000"}, 2, "the threshold 5000 is outside the value range");
}

TEST(BadInput, UnknownOutputExtension) {
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {"-o", "mesh.xyz"});
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("unknown mesh extension"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "mesh.xyz"));
}

TEST(BadInput, UnwritableOutput) {
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {"-o", "no-such-folder/mesh.ply", "--refinements", "0", "--quiet"});
  EXPECT_EQ(r.code, 5) << r.err;
  EXPECT_NE(r.err.find("cannot write no-such-folder/mesh.ply"), std::string::npos) << r.err;
}

// The wrong polarity: the "object" is the air and tissue around the phantom,
// which fills the volume, so the model leaks to the border: exit 4, a hint,
// no mesh; the report says why.
TEST(ModelFailure, LeakToTheBorder) {
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {"--polarity", "dark", "--refinements", "0", "-o", "out.ply", "--report", "out.json", "--quiet"});
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("reached the volume border"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--polarity"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.ply"));
  const std::string json = slurp(dir / "out.json");
  EXPECT_EQ(json_value(json, "exit_code"), 4.0);
  EXPECT_GT(json_value(json, "border_vertices"), 0.0);
  // It stops within a few cycles of the first contact: with the border
  // allowed, the same leak has not converged after ten times as many cycles.
  const int stopped = static_cast<int>(json_value(json, "cycles"));
  const GdmRun all = run_gdm(dir, {"--polarity", "dark", "--refinements", "0", "--allow-border", "--max-cycles",
                                   std::to_string(10 * stopped), "--report", "all.json", "--quiet"});
  EXPECT_EQ(all.code, 0) << all.err;
  EXPECT_NE(slurp(dir / "all.json").find("\"reached the maximum number of cycles\""), std::string::npos)
      << "the leak stopped after " << stopped << " cycles; converging took fewer than ten times as many";
}

// A phantom (unit spacing, origin 0) as a float MetaImage.
void write_phantom(const gdm::Volume& v, const fs::path& file) {
  using FloatImage = itk::Image<float, 3>;
  auto image = FloatImage::New();
  const auto& n = v.dims();
  image->SetRegions(FloatImage::RegionType(
      FloatImage::SizeType{{static_cast<itk::SizeValueType>(n[0]), static_cast<itk::SizeValueType>(n[1]),
                            static_cast<itk::SizeValueType>(n[2])}}));
  image->Allocate();
  std::copy(v.values().begin(), v.values().end(), image->GetBufferPointer());
  itk::WriteImage(image, file.string());
}

// The paper's opened bottle (a dark cavity in a bright wall with an opening
// 6 voxels across, dark outside): exit 4 (a leak) without --gap; with --gap 8
// the opening is bridged, and the summary and the report say what the gap did.
TEST(Model, GapBridgesTheOpeningOfABottle) {
  const fs::path dir = work_dir();
  namespace ph = gdm::phantoms;
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const gdm::Vec3 c = grid.center();
  const ph::Sdf shell = ph::difference(ph::sphere(c, 14.0), ph::sphere(c, 12.0));
  const ph::Sdf hole = [c](const gdm::Vec3& p) { return std::max(std::hypot(p.y() - c.y(), p.z() - c.z()) - 3.0, c.x() - p.x()); };
  const gdm::Volume bottle = ph::voxelize(grid, ph::difference(shell, hole), 50.0, 150.0);
  write_phantom(bottle, dir / "bottle.mha");
  const std::string seed = std::to_string(c.x()) + "," + std::to_string(c.y()) + "," + std::to_string(c.z());
  const std::vector<std::string> common = {"bottle.mha", "--threshold", "125", "--polarity", "dark", "--seed", seed};
  std::vector<std::string> leak = common, bridged = common;
  leak.insert(leak.end(), {"-o", "leak.ply", "--quiet"});
  bridged.insert(bridged.end(), {"--gap", "8", "-o", "bottle.ply", "--report", "bottle.json"});
  const GdmRun l = run_gdm(dir, leak);
  EXPECT_EQ(l.code, 4) << l.err;
  EXPECT_FALSE(fs::exists(dir / "leak.ply"));
  const GdmRun b = run_gdm(dir, bridged);
  ASSERT_EQ(b.code, 0) << b.err;
  EXPECT_NE(b.out.find("gap: "), std::string::npos) << b.out;
  const std::string json = slurp(dir / "bottle.json");
  EXPECT_GT(json_value(json, "gap_closed_voxels"), 0.0);
  EXPECT_GT(json_value(json, "bridge_vertices"), 0.0);
  EXPECT_EQ(json_value(json, "gap"), 8.0);
  const Mesh mesh = read_mesh(dir / "bottle.ply");
  expect_valid_model(measure(mesh));
  double farthest = 0.0;
  for (const auto& p : mesh.points) farthest = std::max(farthest, std::hypot(p[0] - c.x(), p[1] - c.y(), p[2] - c.z()));
  EXPECT_LT(farthest, 13.0) << "the cap strays into the opening";
}

// A bright hollow sphere (radii 9 to 14 voxels) grown from a seed in its
// wall: by default the cavity is filled and the model is the outer sphere;
// the summary and the report say so. With --fill-cavities off the model
// lines the cavity, and the summary reports where it meets itself.
TEST(Model, AHollowShellGivesItsOuterSurface) {
  const fs::path dir = work_dir();
  namespace ph = gdm::phantoms;
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const gdm::Vec3 c = grid.center();
  const gdm::Volume shell = ph::voxelize(grid, ph::difference(ph::sphere(c, 14.0), ph::sphere(c, 9.0)), 50.0, 150.0);
  write_phantom(shell, dir / "shell.mha");
  const std::string seed = std::to_string(c.x() + 11.5) + "," + std::to_string(c.y()) + "," + std::to_string(c.z());
  const std::vector<std::string> common = {"shell.mha", "--threshold", "125", "--seed", seed, "--seed-radius", "1.5"};
  std::vector<std::string> solid = common, lined = common;
  solid.insert(solid.end(), {"-o", "solid.ply", "--report", "solid.json"});
  lined.insert(lined.end(), {"--fill-cavities", "off", "-o", "lined.ply", "--report", "lined.json"});
  const GdmRun s = run_gdm(dir, solid);
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_NE(s.out.find("cavities: 1 enclosed region of background filled"), std::string::npos) << s.out;
  EXPECT_EQ(s.out.find("meets itself"), std::string::npos) << s.out;
  const std::string json = slurp(dir / "solid.json");
  EXPECT_EQ(json_value(json, "cavities"), 1.0);
  EXPECT_GT(json_value(json, "cavity_volume_mm3"), 2500.0);  // 4/3 pi 9^3 = 3,054 mm^3
  double nearest = 1e9;
  for (const auto& p : read_mesh(dir / "solid.ply").points)
    nearest = std::min(nearest, std::hypot(p[0] - c.x(), p[1] - c.y(), p[2] - c.z()));
  EXPECT_GT(nearest, 13.0) << "a vertex lies inside the shell's wall or cavity";
  const GdmRun l = run_gdm(dir, lined);
  ASSERT_EQ(l.code, 0) << l.err;
  EXPECT_EQ(l.out.find("cavities:"), std::string::npos) << l.out;
  EXPECT_EQ(json_value(slurp(dir / "lined.json"), "cavities"), 0.0);
}

// A bright torus (tube of radius 5 around a circle of radius 12) grown from a
// seed in its tube: by default the hole is capped by a membrane at its
// narrowest place, the model is genus 0 and meets itself nowhere, and the
// summary and the report say where the cap is. With --cap-handles off the
// model goes round the tube from both sides and the summary reports where
// its fronts meet.
TEST(Model, ATorusIsCappedAcrossItsHole) {
  const fs::path dir = work_dir();
  namespace ph = gdm::phantoms;
  const ph::Tori shape = ph::tori(1);  // the shared torus: R 12, r 5 in 44 x 44 x 22
  const gdm::Vec3 c = shape.centres.front();
  write_phantom(ph::voxelize(shape.grid, shape.sdf, 50.0, 150.0), dir / "torus.mha");
  const std::string seed = std::to_string(c.x()) + "," + std::to_string(c.y() - 12.0) + "," + std::to_string(c.z());
  const std::vector<std::string> common = {"torus.mha", "--threshold", "125", "--seed", seed, "--seed-radius", "1.5"};
  std::vector<std::string> capped = common, open = common;
  capped.insert(capped.end(), {"-o", "capped.ply", "--report", "capped.json"});
  open.insert(open.end(), {"--cap-handles", "off", "-o", "open.ply", "--report", "open.json"});
  const GdmRun s = run_gdm(dir, capped);
  ASSERT_EQ(s.code, 0) << s.err;
  EXPECT_NE(s.out.find("handles: 1 capped by a membrane across the hole"), std::string::npos) << s.out;
  EXPECT_EQ(s.out.find("meets itself"), std::string::npos) << s.out;
  const std::string json = slurp(dir / "capped.json");
  EXPECT_EQ(json_value(json, "handles"), 1.0);
  EXPECT_EQ(json_value(json, "cavities"), 0.0);
  EXPECT_NE(json.find("\"kind\": \"handle\""), std::string::npos) << json;
  expect_valid_model(measure(read_mesh(dir / "capped.ply")));
  const GdmRun o = run_gdm(dir, open);
  ASSERT_EQ(o.code, 0) << o.err;
  EXPECT_EQ(o.out.find("handles:"), std::string::npos) << o.out;
  EXPECT_NE(o.out.find("meets itself"), std::string::npos) << o.out;
  EXPECT_EQ(json_value(slurp(dir / "open.json"), "handles"), 0.0);
}

// --topology exact (issue 15): a hollow shell's cavity becomes a second,
// inward component and a torus's hole a tube (genus 1); the summary and the
// report say so, and the mesh read back has that genus and those components.
TEST(Model, TopologyExactFollowsTheData) {
  const fs::path dir = work_dir();
  namespace ph = gdm::phantoms;
  ph::Grid grid;
  grid.dims = {40, 40, 40};
  const gdm::Vec3 c = grid.center();
  write_phantom(ph::with_gaussian_noise(
                    ph::voxelize(grid, ph::difference(ph::sphere(c, 14.0), ph::sphere(c, 11.0)), 50.0, 150.0), 7.5, 15u),
                dir / "hollow.mha");
  const std::string seed = std::to_string(c.x() + 12.5) + "," + std::to_string(c.y()) + "," + std::to_string(c.z());
  const GdmRun h = run_gdm(dir, {"hollow.mha", "--threshold", "125", "--seed", seed, "--seed-radius", "1.2", "--topology",
                                 "exact", "-o", "hollow.ply", "--report", "hollow.json"});
  ASSERT_EQ(h.code, 0) << h.err;
  EXPECT_NE(h.out.find("topology exact: 1 enclosed cavity as its own closed component"), std::string::npos) << h.out;
  const std::string hj = slurp(dir / "hollow.json");
  EXPECT_EQ(json_value(hj, "cavity_components"), 1.0);
  EXPECT_EQ(json_value(hj, "components"), 2.0);
  const gdm::MeshReport hm = measure(read_mesh(dir / "hollow.ply"));
  EXPECT_EQ(hm.components, 2);
  EXPECT_EQ(hm.genus, 0);
  EXPECT_EQ(hm.self_intersections, 0u);
  EXPECT_TRUE(hm.closed && hm.two_manifold);

  const ph::Tori torus = ph::tori(1);  // the shared torus
  const gdm::Vec3 t = torus.centres.front();
  write_phantom(ph::with_gaussian_noise(ph::voxelize(torus.grid, torus.sdf, 50.0, 150.0), 7.5, 16u),
                dir / "torus_exact.mha");
  const std::string tseed = std::to_string(t.x()) + "," + std::to_string(t.y() - 12.0) + "," + std::to_string(t.z());
  const GdmRun r = run_gdm(dir, {"torus_exact.mha", "--threshold", "125", "--seed", tseed, "--seed-radius", "1.5",
                                 "--topology", "exact", "-o", "torus_exact.ply", "--report", "torus_exact.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("1 of 1 handle(s) opened into a tube through the hole (genus +1)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("genus 1, components 1"), std::string::npos) << r.out;
  const std::string tj = slurp(dir / "torus_exact.json");
  EXPECT_EQ(json_value(tj, "handles_opened"), 1.0);
  EXPECT_EQ(json_value(tj, "genus"), 1.0);
  const gdm::MeshReport tm = measure(read_mesh(dir / "torus_exact.ply"));
  EXPECT_EQ(tm.genus, 1);
  EXPECT_EQ(tm.components, 1);
  EXPECT_EQ(tm.self_intersections, 0u);
  EXPECT_TRUE(tm.closed && tm.two_manifold);
}

// ------------------------------------------------------------- phantom --

TEST(Phantom, GeneratorReproducesTheCommittedFile) {
  const fs::path dir = work_dir();
  const std::string command = quote(GDM_PHANTOM_GENERATOR) + " " + quote((dir / "phantom.mha").string());
  ASSERT_EQ(std::system(command.c_str()), 0);
  const auto fresh = itk::ReadImage<ShortImage>((dir / "phantom.mha").string());
  const auto committed = itk::ReadImage<ShortImage>(kPhantom);
  ASSERT_EQ(fresh->GetLargestPossibleRegion(), committed->GetLargestPossibleRegion());
  EXPECT_EQ(fresh->GetSpacing(), committed->GetSpacing());
  const std::size_t n = committed->GetLargestPossibleRegion().GetNumberOfPixels();
  EXPECT_EQ(std::memcmp(fresh->GetBufferPointer(), committed->GetBufferPointer(), n * sizeof(short)), 0);
  EXPECT_LT(fs::file_size(kPhantom), 2u * 1024 * 1024);
}

TEST(Phantom, AutoSeedInsideAConcaveObject) {
  // Without input gdm runs on the phantom with --seed auto: the seed is the
  // deepest object voxel, and the model reaches all three roots.
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {"-o", "p.off", "--report", "p.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string json = slurp(dir / "p.json");
  EXPECT_GT(json_value(json, "depth_mm"), 3.0);
  const Mesh mesh = read_mesh(dir / "p.off");
  const auto b = bounds(mesh);
  // Roots end at z = 5 mm with radius 1.6 (data/generate_phantom.cxx); the crown's top is at z = 39.
  EXPECT_LT(b[2], 5.0);
  EXPECT_NEAR(b[5], 39.0, 2.0);
  // Each root tip (9 mm from the axis at 90, 210, 330 degrees) has a vertex near it.
  for (int k = 0; k < 3; ++k) {
    const double a = (90.0 + 120.0 * k) * M_PI / 180.0;
    const std::array<double, 3> tip{24.0 + 9.0 * std::cos(a), 24.0 + 9.0 * std::sin(a), 5.0};
    double nearest = 1e300;
    for (const auto& p : mesh.points)
      nearest = std::min(nearest, std::hypot(p[0] - tip[0], p[1] - tip[1], p[2] - tip[2]));
    EXPECT_LT(nearest, 2.5) << "root " << k;
  }
}

// ------------------------------------------------------------------ wrap --

// A geodesic sphere of radius 10 mm around (5, -3, 40) with its top cap
// (centroids above z = 40 + 8 mm) cut off: an open mesh.
gdm::Mesh open_sphere() {
  gdm::Mesh mesh = gdm::make_geodesic_sphere(gdm::Vec3(5.0, -3.0, 40.0), 10.0, 3);
  mesh.request_face_status();
  mesh.request_edge_status();
  mesh.request_vertex_status();
  for (auto f : mesh.faces()) {
    gdm::Vec3 c = gdm::Vec3::Zero();
    for (auto v : mesh.fv_range(f)) c += gdm::to_eigen(mesh.point(v)) / 3.0;
    if (c.z() > 48.0) mesh.delete_face(f, true);
  }
  mesh.garbage_collection();
  return mesh;
}

TEST(Wrap, OpenSphereBecomesClosed) {
  const fs::path dir = work_dir();
  const gdm::Mesh input = open_sphere();
  ASSERT_FALSE(gdm::measure(input).closed);
  gdm::write_mesh(input, (dir / "open.obj").string());
  const double tolerance = 1.5;
  const GdmRun r = run_gdm(dir, {"wrap", "open.obj", "-o", "wrap.ply", "--tolerance", "1.5", "--cell-size", "0.5",
                                 "--quiet", "--report", "wrap.json"});
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("closed yes, 2-manifold yes, genus 0, self-intersections 0"), std::string::npos) << r.out;
  EXPECT_NE(slurp(dir / "wrap.json").find("\"farthest_input_distance_mm\""), std::string::npos);
  const gdm::Mesh wrap = gdm::read_mesh((dir / "wrap.ply").string());
  const gdm::MeshReport m = gdm::measure(wrap);
  EXPECT_TRUE(m.closed);
  EXPECT_TRUE(m.two_manifold);
  EXPECT_EQ(m.genus, 0);
  EXPECT_EQ(m.self_intersections, 0u);
  std::vector<gdm::Triangle> faces;
  for (auto f : wrap.faces()) {
    gdm::Triangle t;
    int k = 0;
    for (auto v : wrap.fv_range(f)) t[k++] = gdm::to_eigen(wrap.point(v));
    faces.push_back(t);
  }
  const gdm::TriangleLocator to_wrap(faces);
  double farthest = 0.0;
  for (auto v : input.vertices()) farthest = std::max(farthest, to_wrap.distance(gdm::to_eigen(input.point(v))));
  EXPECT_LE(farthest, tolerance);
}

TEST(Wrap, BadToleranceExitsTwo) {
  const fs::path dir = work_dir();
  gdm::write_mesh(open_sphere(), (dir / "open.ply").string());
  for (const char* t : {"-1", "0", "abc", "nan"}) {
    const GdmRun r = run_gdm(dir, {"wrap", "open.ply", "-o", "wrap.ply", "--tolerance", t});
    EXPECT_EQ(r.code, 2) << t << ": " << r.err;
    EXPECT_NE(r.err.find("--tolerance"), std::string::npos) << r.err;
  }
  const GdmRun no_tolerance = run_gdm(dir, {"wrap", "open.ply", "-o", "wrap.ply"});
  EXPECT_EQ(no_tolerance.code, 2) << no_tolerance.err;
  const GdmRun coarse = run_gdm(dir, {"wrap", "open.ply", "-o", "wrap.ply", "--tolerance", "1", "--cell-size", "2"});
  EXPECT_EQ(coarse.code, 2) << coarse.err;
  EXPECT_FALSE(fs::exists(dir / "wrap.ply"));
}

// A wrap far beyond the limits (cells of 1 um around a 20 mm sphere: 3e13
// cells) is refused before any work: exit 2, the estimate and a cell size that
// fits in the message, no output; --estimate prints the estimate; the limits
// can be lifted (0) or set, and bad limits are usage errors.
TEST(Wrap, TooCostlyIsRefusedWithTheEstimate) {
  const fs::path dir = work_dir();
  gdm::write_mesh(open_sphere(), (dir / "open.ply").string());
  const GdmRun r = run_gdm(dir, {"wrap", "open.ply", "-o", "wrap.ply", "--tolerance", "0.003", "--cell-size", "0.001"});
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("gdm wrap: error: the wrap would take about "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("distance grid, about "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("above the time limit of 180 s and the memory limit of 2 GiB; refused before starting"),
            std::string::npos) << r.err;
  EXPECT_NE(r.err.find("Raise --cell-size ("), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--time-limit S, --memory-limit GB"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("usage:"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "wrap.ply"));
  // The memory limit alone: 0.1 mm cells (a 250^3 grid, about 60 MiB and more for the faces) under 0.01 GiB.
  const GdmRun memory = run_gdm(dir, {"wrap", "open.ply", "-o", "wrap.ply", "--tolerance", "0.3", "--cell-size", "0.1",
                                      "--memory-limit", "0.01", "--time-limit", "0"});
  EXPECT_EQ(memory.code, 2) << memory.err;
  EXPECT_NE(memory.err.find("above the memory limit of 0.01 GiB"), std::string::npos) << memory.err;
  // --estimate: the estimate only, also beyond the limits.
  const GdmRun estimate = run_gdm(dir, {"wrap", "open.ply", "--tolerance", "0.003", "--cell-size", "0.001", "--estimate"});
  EXPECT_EQ(estimate.code, 0) << estimate.err;
  EXPECT_NE(estimate.out.find("triangles): about "), std::string::npos) << estimate.out;
  for (const char* bad : {"-1", "abc", "inf"}) {
    const GdmRun b = run_gdm(dir, {"wrap", "open.ply", "-o", "wrap.ply", "--tolerance", "1", "--time-limit", bad});
    EXPECT_EQ(b.code, 2) << bad << ": " << b.err;
    EXPECT_NE(b.err.find("--time-limit"), std::string::npos) << b.err;
  }
  EXPECT_FALSE(fs::exists(dir / "wrap.ply"));
}

TEST(Wrap, MissingOrEmptyInputExitsThree) {
  const fs::path dir = work_dir();
  const GdmRun missing = run_gdm(dir, {"wrap", "nothing_here.obj", "-o", "wrap.ply", "--tolerance", "1"});
  EXPECT_EQ(missing.code, 3) << missing.err;
  EXPECT_NE(missing.err.find("nothing_here.obj"), std::string::npos) << missing.err;
  std::ofstream(dir / "empty.obj").close();
  const GdmRun empty = run_gdm(dir, {"wrap", "empty.obj", "-o", "wrap.ply", "--tolerance", "1"});
  EXPECT_EQ(empty.code, 3) << empty.err;
  EXPECT_NE(empty.err.find("empty.obj"), std::string::npos) << empty.err;
  EXPECT_NE(empty.err.find("empty"), std::string::npos) << empty.err;
  std::ofstream(dir / "points.off") << "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n";
  const GdmRun points = run_gdm(dir, {"wrap", "points.off", "-o", "wrap.ply", "--tolerance", "1"});
  EXPECT_EQ(points.code, 3) << points.err;
  EXPECT_NE(points.err.find("no faces"), std::string::npos) << points.err;
  EXPECT_FALSE(fs::exists(dir / "wrap.ply"));
}

}  // namespace

// ------------------------------------------------- hostile input (issue 13) --

// A small blob volume written here, with any spacing.
void write_blob(const fs::path& path, const std::array<double, 3>& spacing) {
  auto image = ShortImage::New();
  ShortImage::RegionType region;
  region.SetSize({{32, 32, 32}});
  image->SetRegions(region);
  image->Allocate();
  const double s[3] = {spacing[0], spacing[1], spacing[2]};
  image->SetSpacing(s);
  itk::ImageRegionIteratorWithIndex<ShortImage> it(image, region);
  for (it.GoToBegin(); !it.IsAtEnd(); ++it) {
    const auto i = it.GetIndex();
    const double r = std::hypot(i[0] - 15.5, i[1] - 15.5, i[2] - 15.5);
    it.Set(r < 9.0 ? 1000 : 0);
  }
  itk::WriteImage(image, path.string());
}

// Runs gdm with exactly `args`, expecting `code` and `message` on stderr and no temporary file left.
void expect_refused(const fs::path& dir, const std::vector<std::string>& args, int code, const std::string& message) {
  const GdmRun r = run_gdm(dir, args);
  EXPECT_EQ(r.code, code) << r.err;
  EXPECT_NE(r.err.find(message), std::string::npos) << "stderr: " << r.err;
  EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

// Item 2: no output may overwrite the input or the other output; the input is untouched.
TEST(Hostile, OutputsNeverOverwriteTheInput) {
  const fs::path dir = work_dir();
  write_blob(dir / "in.vtk", {1, 1, 1});
  const std::string before = slurp(dir / "in.vtk");
  expect_refused(dir, {"in.vtk", "-o", "in.vtk"}, 2, "--output in.vtk is the input");
  expect_refused(dir, {"in.vtk", "-o", "m.ply", "--report", "in.vtk"}, 2, "--report in.vtk is the input");
  expect_refused(dir, {"in.vtk", "-o", "x.vtk", "--report", "x.vtk"}, 2, "--report and --output name the same file");
  expect_refused(dir, {"in.vtk", "-o", "./in.vtk"}, 2, "is the input");
  EXPECT_EQ(slurp(dir / "in.vtk"), before);
  EXPECT_FALSE(fs::exists(dir / "m.ply"));
  EXPECT_FALSE(fs::exists(dir / "x.vtk"));
}

// Items 7 and 9: values that would run a no-op or an undefined cast are refused at once.
TEST(Hostile, AbsurdValuesAreRefusedBeforeTheRun) {
  const fs::path dir = work_dir();
  expect_failure(dir, {"--a0", "0"}, 2, "--a0: must be > 0");
  expect_failure(dir, {"--a0", "inf"}, 2, "--a0: must be > 0");
  expect_failure(dir, {"--a2", "1e309"}, 2, "--a2");
  expect_failure(dir, {"--seed-level", "5"}, 2, "--seed-level: must be in [0, 4], got 5");
  expect_failure(dir, {"--seed-index", "1e20,0,0"}, 2, "--seed-index: needs integer voxel indices (at most 1e9)");
  expect_failure(dir, {"--roi", "0,0,0,1e20,5,5"}, 2, "--roi: needs non-negative integer voxel indices");
  expect_failure(dir, {"--seed-radius", "1e-300"}, 2, "--seed-radius: 1e-300 mm is below 0.75 voxel");
  expect_refused(dir, {"-o", "no-such-folder/m.ply"}, 5, "the folder no-such-folder of the output does not exist");
}

// Item 8: extreme anisotropy would need billions of faces: refused up front, naming the spacing.
TEST(Hostile, ExtremeAnisotropyIsRefusedUpFront) {
  const fs::path dir = work_dir();
  write_blob(dir / "thin.mha", {0.001, 1.0, 1000.0});
  const auto start = std::chrono::steady_clock::now();
  expect_refused(dir, {"thin.mha", "--threshold", "500", "-o", "m.ply"}, 2, "--lod-face-area: 10 voxel^2");
  const GdmRun r = run_gdm(dir, {"thin.mha", "--threshold", "500", "-o", "m.ply"});
  EXPECT_NE(r.err.find("resample the volume (spacing 0.001 x 1 x 1000 mm)"), std::string::npos) << r.err;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 20.0);
  EXPECT_FALSE(fs::exists(dir / "m.ply"));
}

// Item 6: a seed mesh that intersects itself, or is flat, is refused before it is used.
TEST(Hostile, BadSeedMeshesAreRefused) {
  const fs::path dir = work_dir();
  write_blob(dir / "in.mha", {1, 1, 1});
  // Two overlapping octahedra in one file: closed and manifold, but self-intersecting.
  std::ofstream twin(dir / "twin.off");
  twin << "OFF\n12 16 0\n";
  for (const double cx : {15.5, 16.5})
    twin << cx + 2 << " 15.5 15.5\n" << cx - 2 << " 15.5 15.5\n" << cx << " 17.5 15.5\n" << cx << " 13.5 15.5\n"
         << cx << " 15.5 17.5\n" << cx << " 15.5 13.5\n";
  for (const int o : {0, 6}) {
    const int f[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
    for (const auto& t : f) twin << "3 " << t[0] + o << " " << t[1] + o << " " << t[2] + o << "\n";
  }
  twin.close();
  expect_refused(dir, {"in.mha", "--threshold", "500", "--seed-mesh", "twin.off", "-o", "m.ply"}, 2,
                 "the seed mesh intersects itself");
  std::ofstream empty(dir / "empty.obj");
  empty.close();
  const GdmRun r = run_gdm(dir, {"in.mha", "--threshold", "500", "--seed-mesh", "empty.obj", "-o", "m.ply"});
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find("cannot read the seed mesh empty.obj"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "m.ply"));
}

// The leak of ModelFailure.LeakToTheBorder is said within a few cycles of the first contact.
TEST(Hostile, LeakStopsAtTheFirstContact) {
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {"--polarity", "dark", "-o", "out.ply", "--report", "out.json", "--quiet"});
  EXPECT_EQ(r.code, 4) << r.err;
  const std::string json = slurp(dir / "out.json");
  EXPECT_NE(json.find("\"stop_reason\": \"reached the volume border\""), std::string::npos) << json;
  EXPECT_LT(json_value(json, "cycles"), 60.0);
}

// Starts `program args...` in `dir` with stdout to a pipe (returned in `out_fd`)
// and stderr to dir/stderr.txt.
pid_t spawn(const fs::path& dir, const std::string& program, const std::vector<std::string>& args, int& out_fd) {
  int fds[2];
  if (::pipe(fds) != 0) return -1;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::close(fds[0]);
    ::dup2(fds[1], 1);
    const int err = ::open((dir / "stderr.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (err >= 0) ::dup2(err, 2);
    if (::chdir(dir.c_str()) != 0) ::_exit(126);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(program.c_str()));
    for (const auto& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(program.c_str(), argv.data());
    ::_exit(127);
  }
  ::close(fds[1]);
  out_fd = fds[0];
  return pid;
}

// Every file of `dir` but stderr.txt, by name.
std::vector<std::string> files_in(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().filename() != "stderr.txt") names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// Item 10: SIGTERM, SIGINT (Ctrl-C) or SIGHUP while the mesh is being written
// removes its temporary file (and the report written just before it); the
// process still ends by that signal. gdm_interrupt_helper stops inside the
// write body of gdm::write_file_atomically, as gdm's own last step.
TEST(Hostile, InterruptedWriteLeavesNoFile) {
  const fs::path dir = work_dir();
  for (const int sig : {SIGTERM, SIGINT, SIGHUP})
    for (const bool with_report : {false, true}) {
      SCOPED_TRACE("signal " + std::to_string(sig) + (with_report ? " with a report" : ""));
      std::vector<std::string> args = {"out.ply"};
      if (with_report) args.push_back("out.json");
      int out = -1;
      const pid_t pid = spawn(dir, GDM_INTERRUPT_HELPER, args, out);
      ASSERT_GT(pid, 0);
      char line[8] = {};
      ASSERT_EQ(::read(out, line, 7), 7) << "the helper did not start writing: " << slurp(dir / "stderr.txt");
      ::close(out);
      EXPECT_EQ(std::string(line, 7), "writing");
      const std::string temporary = "out.ply.tmp-" + std::to_string(pid);
      EXPECT_TRUE(fs::exists(dir / temporary)) << "the write is in flight";
      EXPECT_EQ(fs::exists(dir / "out.json"), with_report);
      ASSERT_EQ(::kill(pid, sig), 0);
      int status = 0;
      ASSERT_EQ(::waitpid(pid, &status, 0), pid);
      EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == sig) << "status " << status;
      EXPECT_EQ(files_in(dir), std::vector<std::string>{}) << "left behind";
    }
}

// Item 10: the report is written first, then the mesh; a failed report write
// leaves no mesh (exit 5), and a failed mesh write removes the report (exit 5).
// The unwritable path is a folder where the file should go (root can write anywhere else).
TEST(Hostile, FailedReportOrMeshWriteLeavesNeither) {
  const fs::path dir = work_dir();
  fs::create_directory(dir / "report.json");
  GdmRun r = run_gdm(dir, {"--refinements", "0", "--quiet", "-o", "out.ply", "--report", "report.json"});
  EXPECT_EQ(r.code, 5) << r.err;
  EXPECT_NE(r.err.find("report.json"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.ply")) << "a failed report write left the mesh";
  EXPECT_TRUE(fs::is_directory(dir / "report.json"));
  fs::remove(dir / "report.json");
  EXPECT_EQ(files_in(dir), std::vector<std::string>{});

  fs::create_directory(dir / "out.ply");
  r = run_gdm(dir, {"--refinements", "0", "--quiet", "-o", "out.ply", "--report", "report.json"});
  EXPECT_EQ(r.code, 5) << r.err;
  EXPECT_NE(r.err.find("out.ply"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "report.json")) << "a failed mesh write left the report";
  EXPECT_TRUE(fs::is_directory(dir / "out.ply"));
  fs::remove(dir / "out.ply");
  EXPECT_EQ(files_in(dir), std::vector<std::string>{});
}

// A float MetaImage of the blob of write_blob with the given inside and outside values.
void write_float_blob(const fs::path& path, float inside, float outside, bool one_voxel_outside = false) {
  using FloatImage = itk::Image<float, 3>;
  auto image = FloatImage::New();
  FloatImage::RegionType region;
  region.SetSize({{32, 32, 32}});
  image->SetRegions(region);
  image->Allocate();
  itk::ImageRegionIteratorWithIndex<FloatImage> it(image, region);
  for (it.GoToBegin(); !it.IsAtEnd(); ++it) {
    const auto i = it.GetIndex();
    const bool in = one_voxel_outside ? !(i[0] == 0 && i[1] == 0 && i[2] == 0)
                                      : std::hypot(i[0] - 15.5, i[1] - 15.5, i[2] - 15.5) < 9.0;
    it.Set(in ? inside : outside);
  }
  itk::WriteImage(image, path.string());
}

// Item 9: values near FLT_MAX (Otsu's float bins overflowed to an infinite
// threshold): a sane model (exit 0) or a refusal naming the problem (exit 3), never exit 1.
TEST(Hostile, ValuesNearFloatMaxNeverExitOne) {
  const fs::path dir = work_dir();
  write_float_blob(dir / "huge.mha", 3e38f, -3e38f);
  const GdmRun r = run_gdm(dir, {"huge.mha", "-o", "huge.ply", "--report", "huge.json", "--quiet"});
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string json = slurp(dir / "huge.json");
  const double t = json_value(json, "value");
  EXPECT_TRUE(std::isfinite(t)) << json;
  EXPECT_GT(t, -3e38);
  EXPECT_LT(t, 3e38);
  EXPECT_GT(json_value(json, "fit_moves"), 0.0) << "the sub-voxel fit ran (its samples stay finite)";
  const gdm::MeshReport m = measure(read_mesh(dir / "huge.ply"));
  EXPECT_TRUE(m.closed);
  EXPECT_EQ(m.self_intersections, 0u);
  // The same blob as short values 1000 and 0 gives the same model.
  write_blob(dir / "blob.mha", {1, 1, 1});
  ASSERT_EQ(run_gdm(dir, {"blob.mha", "-o", "blob.ply", "--quiet"}).code, 0);
  const gdm::MeshReport reference = measure(read_mesh(dir / "blob.ply"));
  EXPECT_NEAR(m.volume / reference.volume, 1.0, 0.02) << m.volume << " mm^3 against " << reference.volume;

  // 1e38 everywhere but one voxel: Otsu puts that voxel alone below T, the
  // object is the whole volume and touches the border: the leak message
  // (exit 4); with --allow-border, the box of the volume (exit 0).
  write_float_blob(dir / "flat.mha", 1e38f, 0.0f, true);
  const GdmRun flat = run_gdm(dir, {"flat.mha", "-o", "flat.ply", "--quiet"});
  EXPECT_EQ(flat.code, 4) << flat.err;
  EXPECT_NE(flat.err.find("gdm: error: the model reached the volume border"), std::string::npos) << flat.err;
  EXPECT_FALSE(fs::exists(dir / "flat.ply"));
  const GdmRun allowed = run_gdm(dir, {"flat.mha", "-o", "flat.ply", "--allow-border", "--quiet"});
  ASSERT_EQ(allowed.code, 0) << allowed.err;
  const gdm::MeshReport box = measure(read_mesh(dir / "flat.ply"));
  EXPECT_TRUE(box.closed);
  EXPECT_EQ(box.self_intersections, 0u);
  EXPECT_GT(box.volume, 0.9 * 31.0 * 31.0 * 31.0) << "nearly the whole 31 mm cube";
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

// Item 9: a FIFO would block the open forever, a folder has nothing to read:
// as --seed-mesh or as gdm wrap's input, refused at once with exit 3.
TEST(Hostile, FifoOrFolderMeshIsRefusedAtOnce) {
  const fs::path dir = work_dir();
  ASSERT_EQ(::mkfifo((dir / "pipe.obj").c_str(), 0600), 0);
  fs::create_directory(dir / "folder.off");
  const auto start = std::chrono::steady_clock::now();
  for (const std::string mesh : {"pipe.obj", "folder.off"}) {
    const std::string what = mesh == "pipe.obj" ? "a FIFO (named pipe)" : "a folder";
    GdmRun r = run_gdm(dir, {"--seed-mesh", mesh, "-o", "m.ply", "--quiet"});
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("cannot read the seed mesh " + mesh), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not a regular file: it is " + what), std::string::npos) << r.err;
    r = run_gdm(dir, {"wrap", mesh, "-o", "w.ply", "--tolerance", "1"});
    EXPECT_EQ(r.code, 3) << r.err;
    EXPECT_NE(r.err.find("not a regular file: it is " + what), std::string::npos) << r.err;
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 30.0);
  EXPECT_FALSE(fs::exists(dir / "m.ply"));
  EXPECT_FALSE(fs::exists(dir / "w.ply"));
}

// Item 9: a legacy VTK image whose header claims 1e11 points (data for a
// few): exit 3 naming the problem, before any large allocation, with or
// without the memory limit.
TEST(Hostile, VtkImageClaimingHugePointCount) {
  const fs::path dir = work_dir();
  std::ofstream(dir / "huge.vtk", std::ios::binary)
      << "# vtk DataFile Version 3.0\nhostile\nBINARY\nDATASET STRUCTURED_POINTS\nDIMENSIONS 10000 10000 1000\n"
      << "SPACING 1 1 1\nORIGIN 0 0 0\nPOINT_DATA 100000000000\nSCALARS s short 1\nLOOKUP_TABLE default\n"
      << std::string(4096, '\x01');
  expect_failure(dir, {"huge.vtk"}, 3, "huge.vtk: the header claims 100000000000 voxels");
  expect_failure(dir, {"huge.vtk", "--memory-limit", "0"}, 3, "huge.vtk: the header claims 100000000000 voxels");
  std::ofstream(dir / "points.vtk", std::ios::binary)
      << "# vtk DataFile Version 3.0\nhostile\nASCII\nDATASET POLYDATA\nPOINTS 100000000000 float\n0 0 0\n";
  expect_failure(dir, {"points.vtk"}, 3, "points.vtk");
}

// Resource guards: --memory-limit (GiB of float voxels) refuses a larger volume
// before it is read, with exit 3 naming the limit; 0 lifts it.
TEST(Hostile, MemoryLimitRefusesLargeVolumes) {
  const fs::path dir = work_dir();
  write_blob(dir / "in.mha", {1, 1, 1});  // 32^3 voxels = 128 KiB as float
  expect_failure(dir, {"in.mha", "--threshold", "500", "--memory-limit", "0.0001"}, 3, "more than the memory limit");
  const GdmRun r = run_gdm(dir, {"in.mha", "--threshold", "500", "--memory-limit", "0.0001", "-o", "m.ply"});
  EXPECT_NE(r.err.find("--memory-limit"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("ReadOptions"), std::string::npos) << r.err;
  expect_failure(dir, {"--memory-limit", "-1"}, 2, "--memory-limit: must be in [0, 1e6]");
  expect_failure(dir, {"--memory-limit", "nan"}, 2, "--memory-limit");
  const GdmRun ok = run_gdm(dir, {"in.mha", "--threshold", "500", "--memory-limit", "0", "--refinements", "0",
                                  "-o", "m.ply", "--report", "m.json", "--quiet"});
  EXPECT_EQ(ok.code, 0) << ok.err;
  EXPECT_EQ(json_value(slurp(dir / "m.json"), "memory_limit"), 0.0);
}

// Resource guards: --time-limit ends a run that takes longer, exit 4 saying it
// ran out of time, no mesh.
TEST(Hostile, TimeLimitEndsTheRun) {
  const fs::path dir = work_dir();
  const GdmRun r = run_gdm(dir, {"--time-limit", "0.001", "-o", "out.ply"});
  EXPECT_EQ(r.code, 4) << r.err;
  EXPECT_NE(r.err.find("ran out of time (time_limit 0.001 s)"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.ply"));
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp-"), std::string::npos) << entry.path();
}

// gdm wrap as gdm: no output may overwrite its input (exit 2, the input
// untouched), and the report goes with its mesh (a failed mesh write, exit 5,
// leaves no report).
TEST(Hostile, WrapOutputsNeverOverwriteTheInput) {
  const fs::path dir = work_dir();
  gdm::write_mesh(gdm::make_geodesic_sphere(gdm::Vec3(0, 0, 0), 5.0, 1), (dir / "in.obj").string());
  const std::string before = slurp(dir / "in.obj");
  expect_refused(dir, {"wrap", "in.obj", "-o", "in.obj", "--tolerance", "1"}, 2, "--output in.obj is the input");
  expect_refused(dir, {"wrap", "in.obj", "-o", "w.ply", "--report", "./in.obj", "--tolerance", "1"}, 2,
                 "--report ./in.obj is the input");
  expect_refused(dir, {"wrap", "in.obj", "-o", "w.vtk", "--report", "w.vtk", "--tolerance", "1"}, 2,
                 "--report and --output name the same file");
  EXPECT_EQ(slurp(dir / "in.obj"), before);
  fs::create_directory(dir / "w.ply");
  expect_refused(dir, {"wrap", "in.obj", "-o", "w.ply", "--report", "w.json", "--tolerance", "1", "--quiet"}, 5,
                 "w.ply");
  EXPECT_FALSE(fs::exists(dir / "w.json")) << "a failed mesh write left the report";
  fs::remove(dir / "w.ply");
  fs::create_directory(dir / "w.json");
  expect_refused(dir, {"wrap", "in.obj", "-o", "w.ply", "--report", "w.json", "--tolerance", "1", "--quiet"}, 5,
                 "w.json");
  EXPECT_FALSE(fs::exists(dir / "w.ply")) << "a failed report write left the mesh";
}
