// fuzz_pipeline: the input becomes a tiny volume (4 to 12 voxels per axis,
// values and spacing from the bytes, extremes included) and a few options set
// through gdm::pipeline_option_catalogue() (each entry's set() with a value
// decoded from the bytes: NaN, inf, huge and tiny included); then
// gdm::extract_surface with a 1 s time limit and at most 4000 faces.
// A gdm::Error is fine, and so is a result with a failure; a result without
// a failure must keep every guarantee (closed, 2-manifold, no
// self-intersection, positive volume): anything else aborts.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <vector>

#include "fuzz_util.h"
#include "gdm/errors.h"
#include "gdm/pipeline.h"

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

double spacing_of(std::uint8_t b) {
  static const double table[] = {1.0, 0.5, 2.0, 0.25, 3.0, 0.1, 10.0, 0.7, 1.3, 1e-3, 1e3, 1e-6, 1e6, 1e-30, 1e30,
                                 0.0, -1.0, kNaN, kInf, 1e-300, 1e300};
  constexpr std::size_t n = sizeof table / sizeof table[0];
  // Mostly ordinary spacings: the extremes are the last third.
  return table[b % n];
}

// An option's value: a table of telling values (NaN, infinities, huge, tiny,
// the range's ends) or raw bits.
double option_value(gdm_fuzz::Bytes& in, const gdm::OptionInfo& o) {
  const std::uint8_t s = in.byte();
  static const double table[] = {kNaN, kInf, -kInf, 0.0, -0.0, -1.0, 1.0, 2.0, 0.5, 1e308, -1e308, 1e-300,
                                  4.9e-324, 3.0, 4.0, 5.0, 10.0, 20.0, 100.0, 1e6, 1e9, 1e12, 2147483648.0,
                                  9.3e18, 1.9e19, 1e-3, 0.1, 45.0, 89.0};
  constexpr std::size_t n = sizeof table / sizeof table[0];
  if (s < n) return table[s];
  switch (s % 8) {
    case 0: return o.lo;
    case 1: return o.hi;
    case 2: return std::nextafter(o.lo, -kInf);
    case 3: return std::nextafter(o.hi, kInf);
    case 4: return static_cast<double>(in.f32());
    case 5: return in.f64();
    default: return o.lo + (std::isfinite(o.hi) ? o.hi - o.lo : 10.0) * (in.byte() / 255.0);
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  gdm_fuzz::Bytes in(data, size);
  gdm::Index3 dims;
  for (auto& d : dims) d = 4 + in.byte() % 9;
  gdm::Vec3 spacing;
  for (int a = 0; a < 3; ++a) spacing[a] = spacing_of(in.byte());
  const std::uint8_t mode = in.byte();
  const std::size_t n = static_cast<std::size_t>(dims[0]) * dims[1] * dims[2];
  std::vector<float> values(n, 0.0f);
  if (mode % 4 == 3) {
    for (auto& v : values) v = in.f32();  // raw floats: NaN and infinities included
  } else if (mode % 4 == 2) {
    for (auto& v : values) v = static_cast<float>(in.byte());  // raw bytes
  } else {
    // A blob (an ellipsoid around a centre) with noise: the model has something to find.
    const double cx = in.byte() % dims[0], cy = in.byte() % dims[1], cz = in.byte() % dims[2];
    const double r = 1.0 + in.byte() % 6;
    const int noise = in.byte() % 64;
    static const float scales[] = {1.0f, 1.0f, 1.0f, -1.0f, 1e-30f, 1e30f, 3e38f, 1e-40f};
    const float scale = scales[in.byte() % 8];
    std::size_t i = 0;
    for (int z = 0; z < dims[2]; ++z)
      for (int y = 0; y < dims[1]; ++y)
        for (int x = 0; x < dims[0]; ++x, ++i) {
          const double d2 = (x - cx) * (x - cx) + (y - cy) * (y - cy) + (z - cz) * (z - cz);
          const double base = d2 <= r * r ? 100.0 : 0.0;
          const double noisy = base + (noise ? static_cast<double>(in.byte() % (noise + 1)) : 0.0);
          values[i] = static_cast<float>(noisy) * scale;
        }
  }

  gdm::PipelineOptions o;
  o.deform.threads = 1;
  o.deform.global_refinements = in.byte() % 2;
  const std::uint8_t threshold_mode = in.byte();
  if (threshold_mode % 3 == 0) {
    o.threshold_otsu = false;
    const std::uint8_t t = in.byte();
    o.threshold = t < 200 ? t * 0.5 : option_value(in, gdm::OptionInfo{});
  }
  const auto& catalogue = gdm::pipeline_option_catalogue();
  const int count = in.byte() % 5;
  try {
    // A setter refuses (InvalidOption) a value its integer field cannot hold.
    for (int k = 0; k < count; ++k) {
      const auto& e = catalogue[in.byte() % catalogue.size()];
      e.set(o, option_value(in, e));
    }
  } catch (const gdm::InvalidOption&) {
    return 0;
  }
  // Bounded runs: 1 s, a few thousand faces, one thread (a value the bytes
  // made invalid is kept: validate() must refuse it).
  if (o.time_limit == 0.0 || o.time_limit > 1.0) o.time_limit = 1.0;
  if (o.deform.max_faces > 4000) o.deform.max_faces = 4000;
  if (o.deform.max_cycles > 2000) o.deform.max_cycles = 2000;
  o.deform.threads = 1;

  try {
    const gdm::Volume volume(dims, std::move(values), spacing);
    const gdm::PipelineResult r = gdm::extract_surface(volume, o);
    if (r.failure.empty()) {
      const auto& m = r.report;
      if (!m.closed || !m.two_manifold || m.self_intersections != 0 || !(m.volume > 0.0)) {
        std::fprintf(stderr, "fuzz_pipeline: a result without failure breaks a guarantee: %s\n",
                     gdm::to_string(m).c_str());
        std::abort();
      }
    }
  } catch (const gdm::Error&) {
  }
  return 0;
}
