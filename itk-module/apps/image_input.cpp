// The command line's reading: gdm::read_volume (gdm/image_io.h, the one
// reader of every front end) does the reading and every check; this maps its
// errors onto the command's exit codes and describes the input for the report.
#include "image_input.h"

#include "cli_errors.h"
#include "gdm/errors.h"
#include "gdm/image_io.h"

namespace gdm_cli {

gdm::Volume read_input(const std::string& path, const std::string& series_uid, std::uint64_t memory_limit,
                       InputInfo& info, std::ostream& log) {
  info.path = path;
  gdm::ReadOptions options;
  options.series_uid = series_uid;
  options.memory_limit = memory_limit;
  gdm::ImageInfo read;
  gdm::Volume volume;
  try {
    volume = gdm::read_volume(path, options, &read);
  } catch (const gdm::InvalidOption& e) {
    throw UsageError("--series " + series_uid + ": " + e.what());
  } catch (const gdm::Error& e) {
    std::string message = e.what();
    const std::string api = "ReadOptions::memory_limit";  // said with the command's flag
    const auto at = message.find(api);
    if (at != std::string::npos) message.replace(at, api.size(), "--memory-limit (GiB, 0 = no limit)");
    throw InputError(message);
  }
  if (read.series_count > 1 && series_uid.empty())
    log << "the folder holds " << read.series_count << " DICOM series; using the one with most slices ("
        << read.slices << "): " << read.series_uid << " (choose another with --series UID)\n";
  for (const auto& warning : read.warnings) log << "warning: " << warning << "\n";
  info.format = read.format;
  info.series_uid = read.series_uid;
  info.files = read.slices;
  info.series_count = read.series_count;
  info.pixel_type = read.pixel_type;
  info.size = read.dims;
  info.spacing = read.spacing;
  info.origin = read.origin;
  info.direction = read.direction;
  info.minimum = read.minimum;
  info.maximum = read.maximum;
  return volume;
}

}  // namespace gdm_cli
