// fuzz_image_reader: the input's first byte chooses the extension (.mha,
// .nrrd, .nii, .nii.gz, .vtk), the rest is the file; gdm::read_volume reads it
// as gdm configures ITK, with a 64 MiB limit. A volume or a gdm::Error /
// std::exception is fine; a crash, a sanitizer report, a hang (-timeout) or a
// large allocation (-rss_limit_mb / -malloc_limit_mb) is a finding.
#include <cstddef>
#include <cstdint>
#include <exception>

#include "fuzz_util.h"
#include "gdm/errors.h"
#include "gdm/image_io.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static const char* const extensions[] = {".mha", ".nrrd", ".nii", ".nii.gz", ".vtk"};
  const std::string path = gdm_fuzz::write_temp(data + 1, size - 1, extensions[data[0] % 5]);
  gdm::ReadOptions options;
  options.memory_limit = std::uint64_t{64} << 20;
  try {
    gdm::ImageInfo info;
    const gdm::Volume v = gdm::read_volume(path, options, &info);
    if (v.voxel_count() * 4 > options.memory_limit) __builtin_trap();  // the limit was not kept
  } catch (const gdm::Error&) {
  } catch (const std::exception&) {
  }
  return 0;
}
