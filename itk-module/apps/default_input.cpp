#include "default_input.h"

#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>

namespace gdm_cli {
namespace {

std::string executable_dir() {
  char buffer[4096];
  const ssize_t n = ::readlink("/proc/self/exe", buffer, sizeof buffer - 1);
  if (n <= 0) return {};
  std::string path(buffer, static_cast<std::size_t>(n));
  const auto slash = path.find_last_of('/');
  return slash == std::string::npos ? std::string() : path.substr(0, slash);
}

}  // namespace

std::vector<std::string> phantom_candidates() {
  std::vector<std::string> out;
  if (const char* env = std::getenv("GDM_DATA_DIR")) out.push_back(std::string(env) + "/phantom.mha");
  const std::string exe = executable_dir();
  if (!exe.empty()) {
    out.push_back(exe + "/../share/gdm/phantom.mha");
    out.push_back(exe + "/data/phantom.mha");
  }
#ifdef GDM_SOURCE_DATA_DIR
  out.push_back(std::string(GDM_SOURCE_DATA_DIR) + "/phantom.mha");
#endif
  return out;
}

std::string find_phantom() {
  for (const auto& path : phantom_candidates()) {
    struct stat s {};
    if (::stat(path.c_str(), &s) == 0 && S_ISREG(s.st_mode)) return path;
  }
  return {};
}

}  // namespace gdm_cli
