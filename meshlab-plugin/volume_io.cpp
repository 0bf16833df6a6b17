// Volume files for the plugin: gdm::read_volume (gdm/image_io.h), the reader
// shared with the gdm command line, plus the plugin's own messages.
#include <sstream>
#include <stdexcept>
#include <sys/stat.h>

#include "gdm/image_io.h"
#include "volume_io.h"

namespace gdm_meshlab {

gdm::Volume read_volume(const std::string& path, std::string* description) {
  if (path.empty()) throw std::runtime_error("no volume file chosen: choose it with the ... button beside Volume file (MeshLab 2020.09 "
                             "ignores a path typed into that field; in a script, parameter volume_file)");
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw std::runtime_error("the volume file '" + path + "' does not exist");
  gdm::ImageInfo info;
  gdm::Volume volume = gdm::read_volume(path, {}, &info);
  if (description) {
    std::ostringstream s;
    if (info.format == "DICOM series") {
      s << "read DICOM series " << info.series_uid << " (" << info.slices << " slices";
      if (info.series_count > 1) s << "; the one with most slices, " << info.series_count - 1 << " other series ignored";
      s << ")";
    } else {
      s << "read file";
    }
    s << " '" << path << "': " << volume.dims()[0] << " x " << volume.dims()[1] << " x " << volume.dims()[2]
      << " voxels, spacing " << volume.spacing().x() << " x " << volume.spacing().y() << " x "
      << volume.spacing().z() << " mm, values [" << volume.min_value() << ", " << volume.max_value() << "]";
    for (const auto& warning : info.warnings) s << "; warning: " << warning;
    *description = s.str();
  }
  return volume;
}

}  // namespace gdm_meshlab
