// Writes the seed corpus of fuzz_image_reader: a small valid volume in every
// format the target chooses (.mha, .nrrd, .nii, .nii.gz, .vtk), written by
// ITK's own writers, each file prefixed by the byte that makes the target
// pick its extension. Usage: fuzz_make_image_corpus <folder>
#include "itkImage.h"
#include "itkImageFileWriter.h"

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <folder>\n", argv[0]);
    return 2;
  }
  const std::string out = argv[1];
  using Image = itk::Image<unsigned char, 3>;
  auto image = Image::New();
  image->SetRegions(Image::RegionType(Image::SizeType{{5, 4, 3}}));
  image->Allocate();
  unsigned char* p = image->GetBufferPointer();
  for (int i = 0; i < 60; ++i) p[i] = static_cast<unsigned char>((i * 37) % 200);
  Image::SpacingType spacing;
  spacing[0] = 0.5;
  spacing[1] = 1.0;
  spacing[2] = 2.0;
  image->SetSpacing(spacing);
  const char* const extensions[] = {".mha", ".nrrd", ".nii", ".nii.gz", ".vtk"};
  for (int k = 0; k < 5; ++k) {
    const std::string tmp = out + "/tmp" + extensions[k];
    auto writer = itk::ImageFileWriter<Image>::New();
    writer->SetFileName(tmp);
    writer->SetInput(image);
    writer->Update();
    std::ifstream in(tmp, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    in.close();
    std::remove(tmp.c_str());
    std::string name = extensions[k] + 1;
    for (auto& c : name)
      if (c == '.') c = '_';
    std::ofstream f(out + "/valid_" + name, std::ios::binary);
    f.put(static_cast<char>(k));
    f << bytes;
  }
  return 0;
}
