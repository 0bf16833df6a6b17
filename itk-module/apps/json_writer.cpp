#include "json_writer.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace gdm_cli {

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\r': out += "\\r"; break;
      case '\t': out += "\\t"; break;
      case '\b': out += "\\b"; break;
      case '\f': out += "\\f"; break;
      default:
        if (u < 0x20) {
          char buffer[8];
          std::snprintf(buffer, sizeof buffer, "\\u%04x", u);
          out += buffer;
        } else {
          out += c;  // UTF-8 bytes pass through unchanged
        }
    }
  }
  return out + "\"";
}

std::string json_number(double value) {
  if (!std::isfinite(value)) return "null";
  char buffer[40];
  for (int precision = 6; precision <= 17; ++precision) {
    std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
    if (std::strtod(buffer, nullptr) == value) break;
  }
  return buffer;
}

std::string json_number(long long value) { return std::to_string(value); }

std::string JsonObject::str(int indent, int level) const {
  if (members_.empty()) return "{}";
  const std::string pad(static_cast<std::size_t>(indent * (level + 1)), ' ');
  const std::string end_pad(static_cast<std::size_t>(indent * level), ' ');
  std::string out = "{\n";
  for (std::size_t i = 0; i < members_.size(); ++i) {
    std::string value = members_[i].second;
    // Re-indent nested multi-line values.
    std::string shifted;
    for (const char c : value) {
      shifted += c;
      if (c == '\n') shifted += pad;
    }
    out += pad + json_string(members_[i].first) + ": " + shifted;
    out += i + 1 < members_.size() ? ",\n" : "\n";
  }
  return out + end_pad + "}";
}

}  // namespace gdm_cli
