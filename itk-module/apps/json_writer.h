// A minimal JSON writer for the run report: escaped strings, numbers that
// read back exactly, and objects built key by key (insertion order kept).
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace gdm_cli {

// "text" with quotes, backslashes and control characters escaped (RFC 8259).
std::string json_string(const std::string& text);

// The shortest decimal that reads back to the same double; null for NaN/inf.
std::string json_number(double value);
std::string json_number(long long value);
inline std::string json_number(int value) { return json_number(static_cast<long long>(value)); }
inline std::string json_number(std::size_t value) { return json_number(static_cast<long long>(value)); }
inline std::string json_bool(bool value) { return value ? "true" : "false"; }

template <std::size_t N>
std::string json_array(const std::array<double, N>& values) {
  std::string out = "[";
  for (std::size_t i = 0; i < N; ++i) out += (i ? ", " : "") + json_number(values[i]);
  return out + "]";
}

// An object whose members are already-encoded JSON values.
class JsonObject {
 public:
  JsonObject& add(const std::string& key, const std::string& encoded_value) {
    members_.emplace_back(key, encoded_value);
    return *this;
  }
  // Nested objects are indented by `indent` spaces per level.
  std::string str(int indent = 2, int level = 0) const;

 private:
  std::vector<std::pair<std::string, std::string>> members_;
};

}  // namespace gdm_cli
