// The only ITK translation unit of the test tool: writes a gdm::Volume as a
// volume file (MetaImage, NRRD, NIfTI: chosen by the extension).
#include <itkImage.h>
#include <itkImageFileWriter.h>

#include "gdm/volume.h"

void write_volume(const gdm::Volume& volume, const std::string& path) {
  using Image = itk::Image<float, 3>;
  auto image = Image::New();
  Image::SizeType size;
  Image::SpacingType spacing;
  Image::PointType origin;
  Image::DirectionType direction;
  for (int i = 0; i < 3; ++i) {
    size[i] = static_cast<itk::SizeValueType>(volume.dims()[i]);
    spacing[i] = volume.spacing()[i];
    origin[i] = volume.origin()[i];
    for (int j = 0; j < 3; ++j) direction[i][j] = volume.direction()(i, j);
  }
  image->SetRegions(size);
  image->SetSpacing(spacing);
  image->SetOrigin(origin);
  image->SetDirection(direction);
  image->Allocate();
  std::copy(volume.values().begin(), volume.values().end(), image->GetBufferPointer());
  auto writer = itk::ImageFileWriter<Image>::New();
  writer->SetFileName(path);
  writer->SetInput(image);
  writer->Update();
}
