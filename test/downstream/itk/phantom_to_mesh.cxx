// reader -> smoothing -> GeometricallyDeformedModelImageToMeshFilter -> mesh writer,
// the seed placed by gdm's automatic seed (gdm::find_auto_seed, gdm::pipeline).
//   phantom_to_mesh <image> <mesh.vtk> [threshold = 400]
// exit 0 when the written mesh is closed (V - E + F = 2 for a genus-0 surface: V - F/2 = 2).
#include <cstdlib>
#include <iostream>

#include "itkGDMVolumeConversion.h"  // first: ITK's Eigen before the gdm headers
#include "itkGeometricallyDeformedModelImageToMeshFilter.h"
#include "itkImageFileReader.h"
#include "itkMesh.h"
#include "itkMeshFileReader.h"
#include "itkMeshFileWriter.h"
#include "itkSmoothingRecursiveGaussianImageFilter.h"

#include "gdm/seeding.h"

int main(int argc, char* argv[]) {
  if (argc < 3) {
    std::cerr << "Usage: " << argv[0] << " <image> <mesh.vtk> [threshold]" << std::endl;
    return EXIT_FAILURE;
  }
  const double threshold = argc > 3 ? std::atof(argv[3]) : 400.0;
  using ImageType = itk::Image<float, 3>;
  using MeshType = itk::Mesh<float, 3>;
  try {
    auto reader = itk::ImageFileReader<ImageType>::New();
    reader->SetFileName(argv[1]);

    auto smoothing = itk::SmoothingRecursiveGaussianImageFilter<ImageType, ImageType>::New();
    smoothing->SetInput(reader->GetOutput());
    smoothing->SetSigma(0.5);
    smoothing->Update();

    const gdm::AutoSeed seed = gdm::find_auto_seed(
        itk::GDMConversion::VolumeFromImage(smoothing->GetOutput()), threshold, gdm::Polarity::object_brighter);

    using FilterType = itk::GeometricallyDeformedModelImageToMeshFilter<ImageType, MeshType>;
    auto filter = FilterType::New();
    filter->SetInput(smoothing->GetOutput());
    filter->SetThreshold(threshold);
    FilterType::PointType centre;
    for (unsigned int d = 0; d < 3; ++d) centre[d] = seed.center[d];
    filter->SetSeedCenter(centre);
    filter->SetSeedRadius(seed.radius);

    auto writer = itk::MeshFileWriter<MeshType>::New();
    writer->SetInput(filter->GetOutput());
    writer->SetFileName(argv[2]);
    writer->Update();

    auto check = itk::MeshFileReader<MeshType>::New();
    check->SetFileName(argv[2]);
    check->Update();
    const auto points = check->GetOutput()->GetNumberOfPoints();
    const auto cells = check->GetOutput()->GetNumberOfCells();
    std::cout << "seed (" << seed.center.transpose() << ") radius " << seed.radius << " mm; "
              << filter->GetNumberOfCycles() << " cycles; " << argv[2] << ": " << points << " points, " << cells
              << " triangles" << std::endl;
    const bool ok = cells > 0 && static_cast<long>(points) - static_cast<long>(cells) / 2 == 2;
    std::cout << (ok ? "OK" : "FAILED") << std::endl;
    return ok ? EXIT_SUCCESS : EXIT_FAILURE;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << std::endl;
    return EXIT_FAILURE;
  }
}
