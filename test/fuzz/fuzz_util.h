// Shared helpers of the fuzz targets (test/fuzz): the input written to a
// temporary file with a chosen extension, and a reader of bytes that never
// runs out (missing bytes read as 0).
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

namespace gdm_fuzz {

// This process's temporary folder (removed at exit).
inline const std::filesystem::path& temp_dir() {
  static const std::filesystem::path dir = [] {
    const char* env = std::getenv("TMPDIR");
    std::filesystem::path d = std::filesystem::path(env && *env ? env : "/tmp") /
                              ("gdm_fuzz_" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    std::atexit([] {
      std::error_code ignored;
      std::filesystem::remove_all(temp_dir(), ignored);
    });
    return d;
  }();
  return dir;
}

// Writes `size` bytes to <temp>/input<ext> and returns the path.
inline std::string write_temp(const std::uint8_t* data, std::size_t size, const std::string& ext) {
  const std::string path = (temp_dir() / ("input" + ext)).string();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

// Reads the input front to back; past its end every byte is 0.
class Bytes {
 public:
  Bytes(const std::uint8_t* data, std::size_t size) : data_(data), size_(size) {}
  std::uint8_t byte() { return pos_ < size_ ? data_[pos_++] : 0; }
  std::uint32_t u32() {
    std::uint32_t v = 0;
    for (int i = 0; i < 4; ++i) v |= static_cast<std::uint32_t>(byte()) << (8 * i);
    return v;
  }
  float f32() {
    const std::uint32_t u = u32();
    float f;
    std::memcpy(&f, &u, sizeof f);
    return f;
  }
  double f64() {
    std::uint64_t u = u32();
    u |= static_cast<std::uint64_t>(u32()) << 32;
    double d;
    std::memcpy(&d, &u, sizeof d);
    return d;
  }
  std::size_t left() const { return pos_ < size_ ? size_ - pos_ : 0; }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t pos_ = 0;
};

}  // namespace gdm_fuzz
