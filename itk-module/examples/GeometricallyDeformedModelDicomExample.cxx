// Example pipeline: a DICOM series (read by gdm::read_volume) -> Gaussian smoothing -> in-plane
// shrinking -> GeometricallyDeformedModelImageToMeshFilter -> mesh file.
//
//   GeometricallyDeformedModelDicomExample <dicom folder> <output mesh (.vtk, .obj, ...)>
//       [threshold = -400] [sigma mm = 1.0] [in-plane shrink = 4]
//       [seed x y z (mm) radius (mm); default: the volume's centre, radius 10]
//
// The object is brighter than the threshold (e.g. a head in air at -400 HU).
#include <chrono>
#include <cstdlib>
#include <iostream>

#include "itkGeometricallyDeformedModelImageToMeshFilter.h"
#include "itkMesh.h"
#include "itkMeshFileWriter.h"
#include "itkShrinkImageFilter.h"
#include "itkSmoothingRecursiveGaussianImageFilter.h"

#include "gdm/image_io.h"  // gdm::read_volume: the series with most slices, its geometry checked

int
main(int argc, char * argv[])
{
  if (argc < 3)
  {
    std::cerr << "Usage: " << argv[0]
              << " <dicom folder> <output mesh> [threshold] [sigma mm] [in-plane shrink] [seed x y z radius]"
              << std::endl;
    return EXIT_FAILURE;
  }
  const double       threshold = argc > 3 ? std::atof(argv[3]) : -400.0;
  const double       sigma = argc > 4 ? std::atof(argv[4]) : 1.0;
  const unsigned int shrink = argc > 5 ? static_cast<unsigned int>(std::atoi(argv[5])) : 4;

  using PixelType = float;
  using ImageType = itk::Image<PixelType, 3>;
  using MeshType = itk::Mesh<float, 3>;

  try
  {
    // gdm::read_volume picks the series with most slices, refuses duplicated,
    // missing or tilted slices and takes the slice spacing from the positions.
    gdm::ImageInfo    info;
    const gdm::Volume volume = gdm::read_volume(argv[1], {}, &info);
    for (const auto & warning : info.warnings)
    {
      std::cerr << "warning: " << warning << std::endl;
    }
    auto                    input = ImageType::New();
    ImageType::SizeType     size;
    ImageType::SpacingType  spacing;
    ImageType::PointType    origin;
    ImageType::DirectionType direction;
    for (unsigned int d = 0; d < 3; ++d)
    {
      size[d] = info.dims[d];
      spacing[d] = info.spacing[d];
      origin[d] = info.origin[d];
      for (unsigned int c = 0; c < 3; ++c)
      {
        direction[d][c] = info.direction[3 * d + c];
      }
    }
    input->SetRegions(ImageType::RegionType(size));
    input->SetSpacing(spacing);
    input->SetOrigin(origin);
    input->SetDirection(direction);
    input->Allocate();
    std::copy(volume.values().begin(), volume.values().end(), input->GetBufferPointer());
    std::cout << info.format << " " << info.series_uid << ": " << info.slices << " files, size "
              << input->GetLargestPossibleRegion().GetSize() << ", spacing " << input->GetSpacing() << ", origin "
              << input->GetOrigin() << std::endl;

    using SmoothingType = itk::SmoothingRecursiveGaussianImageFilter<ImageType, ImageType>;
    auto smoothing = SmoothingType::New();
    smoothing->SetInput(input);
    smoothing->SetSigma(sigma);

    using ShrinkType = itk::ShrinkImageFilter<ImageType, ImageType>;
    auto                      shrinker = ShrinkType::New();
    ShrinkType::ShrinkFactorsType factors;
    factors[0] = factors[1] = std::max(1u, shrink);
    factors[2] = 1;
    shrinker->SetInput(smoothing->GetOutput());
    shrinker->SetShrinkFactors(factors);
    shrinker->Update();

    using FilterType = itk::GeometricallyDeformedModelImageToMeshFilter<ImageType, MeshType>;
    auto filter = FilterType::New();
    filter->SetInput(shrinker->GetOutput());
    filter->SetThreshold(threshold);
    filter->SetPolarity(FilterType::PolarityEnum::ObjectBrighter);
    FilterType::PointType seed;
    double                radius = 10.0;
    if (argc > 9)
    {
      for (unsigned int d = 0; d < 3; ++d)
      {
        seed[d] = std::atof(argv[6 + d]);
      }
      radius = std::atof(argv[9]);
    }
    else
    {
      const ImageType *               shrunk = shrinker->GetOutput();
      itk::ContinuousIndex<double, 3> middle;
      for (unsigned int d = 0; d < 3; ++d)
      {
        middle[d] = shrunk->GetLargestPossibleRegion().GetIndex()[d] +
                    (shrunk->GetLargestPossibleRegion().GetSize()[d] - 1) / 2.0;
      }
      shrunk->TransformContinuousIndexToPhysicalPoint(middle, seed);
    }
    filter->SetSeedCenter(seed);
    filter->SetSeedRadius(radius);
    int lastPercent = -1;
    filter->AddObserver(itk::ProgressEvent(), [&](const itk::EventObject &) {
      const int percent = static_cast<int>(100.0f * filter->GetProgress());
      if (percent / 10 != lastPercent / 10)
      {
        std::cout << "  progress " << percent << "%" << std::endl;
      }
      lastPercent = percent;
    });

    const auto start = std::chrono::steady_clock::now();
    filter->Update();
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "GDM: threshold " << threshold << ", seed " << seed << " radius " << radius << ": "
              << filter->GetOutput()->GetNumberOfPoints() << " points, " << filter->GetOutput()->GetNumberOfCells()
              << " triangles, " << filter->GetNumberOfCycles() << " cycles (" << filter->GetStopReason() << "), "
              << seconds << " s" << std::endl;

    using WriterType = itk::MeshFileWriter<MeshType>;
    auto writer = WriterType::New();
    writer->SetInput(filter->GetOutput());
    writer->SetFileName(argv[2]);
    writer->Update();
    std::cout << "wrote " << argv[2] << std::endl;
  }
  catch (const itk::ExceptionObject & error)
  {
    std::cerr << "Error: " << error << std::endl;
    return EXIT_FAILURE;
  }
  catch (const gdm::Error & error)
  {
    std::cerr << "Error: " << error.what() << std::endl;
    return EXIT_FAILURE;
  }
  return EXIT_SUCCESS;
}
