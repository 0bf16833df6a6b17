// Generates data/phantom.mha, the CT-like volume gdm runs on when it is given
// no input. Deterministic: the same file on every machine (own random
// generator and Box-Muller transform, no std::normal_distribution).
//
//   gdm_generate_phantom <out.mha>
//
// 96 x 96 x 24 voxels of 0.5 x 0.5 x 2 mm (thick CT slices), short, in HU:
//   air -1000 around a soft-tissue cylinder (40 HU) that holds a bone-like
//   object (1000 HU): a crown (ellipsoid) on a neck with three diverging,
//   tapering roots (concave, branching, like the paper's tooth of section 6.3),
//   and a 2 mm bore through the crown's wall into it (a hole narrower than the
//   model's level of detail, which the topology term bridges, section 3.1.3).
// Every voxel is the mean of 4 x 4 x 8 samples inside it (partial-volume
// edges), plus Gaussian noise of 20 HU.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>

#include "itkImage.h"
#include "itkImageFileWriter.h"

namespace {

constexpr double kAir = -1000.0, kTissue = 40.0, kBone = 1000.0, kNoise = 20.0;
constexpr int kNx = 96, kNy = 96, kNz = 24;
constexpr double kSx = 0.5, kSy = 0.5, kSz = 2.0;

struct P {
  double x, y, z;
};

double sq(double v) { return v * v; }

// Inside a capsule from a (radius ra) to b (radius rb), radius linear along it.
bool in_tapered_capsule(const P& p, const P& a, const P& b, double ra, double rb) {
  const P ab{b.x - a.x, b.y - a.y, b.z - a.z};
  const double len2 = sq(ab.x) + sq(ab.y) + sq(ab.z);
  double t = ((p.x - a.x) * ab.x + (p.y - a.y) * ab.y + (p.z - a.z) * ab.z) / len2;
  t = std::clamp(t, 0.0, 1.0);
  const double r = ra + t * (rb - ra);
  return sq(p.x - a.x - t * ab.x) + sq(p.y - a.y - t * ab.y) + sq(p.z - a.z - t * ab.z) <= r * r;
}

bool in_object(const P& p) {
  const double cx = 24.0, cy = 24.0;
  // The bore: radius 1 mm along x from the crown's +x side, 6 mm deep.
  if (p.x >= 27.0 && sq(p.y - cy) + sq(p.z - 32.0) <= 1.0) return false;
  if (sq((p.x - cx) / 9.0) + sq((p.y - cy) / 8.0) + sq((p.z - 32.0) / 7.0) <= 1.0) return true;  // crown
  if (in_tapered_capsule(p, {cx, cy, 20.0}, {cx, cy, 30.0}, 5.0, 5.0)) return true;            // neck
  for (int k = 0; k < 3; ++k) {  // roots, 120 degrees apart
    const double a = (90.0 + 120.0 * k) * M_PI / 180.0;
    if (in_tapered_capsule(p, {cx, cy, 21.0}, {cx + 9.0 * std::cos(a), cy + 9.0 * std::sin(a), 5.0}, 3.0, 1.6))
      return true;
  }
  return false;
}

double intensity(const P& p) {
  if (sq(p.x - 24.0) + sq(p.y - 24.0) > 22.0 * 22.0) return kAir;
  return in_object(p) ? kBone : kTissue;
}

// splitmix64: a small, fully specified generator.
struct Random {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return (static_cast<double>(next() >> 11) + 0.5) / 9007199254740992.0; }  // (0, 1)
  double gaussian() {  // Box-Muller, one value per call
    const double u = uniform(), v = uniform();
    return std::sqrt(-2.0 * std::log(u)) * std::cos(2.0 * M_PI * v);
  }
};

}  // namespace

int main(int argc, char* argv[]) {
  if (argc != 2) {
    std::cerr << "Usage: " << argv[0] << " <out.mha>\n";
    return 2;
  }
  using ImageType = itk::Image<short, 3>;
  auto image = ImageType::New();
  ImageType::SizeType size{{kNx, kNy, kNz}};
  image->SetRegions(ImageType::RegionType(size));
  const double spacing[3] = {kSx, kSy, kSz};
  image->SetSpacing(spacing);
  const double origin[3] = {0.0, 0.0, 0.0};
  image->SetOrigin(origin);
  image->Allocate();

  Random random{20260101};
  constexpr int sx = 4, sy = 4, sz = 8;
  short* out = image->GetBufferPointer();
  for (int k = 0; k < kNz; ++k)
    for (int j = 0; j < kNy; ++j)
      for (int i = 0; i < kNx; ++i) {
        double sum = 0.0;
        for (int c = 0; c < sz; ++c)
          for (int b = 0; b < sy; ++b)
            for (int a = 0; a < sx; ++a)
              sum += intensity({(i - 0.5 + (a + 0.5) / sx) * kSx, (j - 0.5 + (b + 0.5) / sy) * kSy,
                                (k - 0.5 + (c + 0.5) / sz) * kSz});
        const double value = sum / (sx * sy * sz) + kNoise * random.gaussian();
        *out++ = static_cast<short>(std::lround(std::clamp(value, -1024.0, 3071.0)));
      }

  auto writer = itk::ImageFileWriter<ImageType>::New();
  writer->SetInput(image);
  writer->SetFileName(argv[1]);
  writer->SetUseCompression(true);
  try {
    writer->Update();
  } catch (const itk::ExceptionObject& e) {
    std::cerr << "cannot write " << argv[1] << ": " << e.GetDescription() << "\n";
    return 1;
  }
  return 0;
}
