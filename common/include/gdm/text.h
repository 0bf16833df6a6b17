// Numbers in messages and log lines, written one way everywhere.
#pragma once

#include <string>

namespace gdm {

// `v` with `precision` significant digits ("0.1", "1e+06", "inf", "nan").
std::string format_number(double v, int precision = 6);

}  // namespace gdm
