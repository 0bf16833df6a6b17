#include "gdm/text.h"

#include <sstream>

namespace gdm {

std::string format_number(double v, int precision) {
  std::ostringstream s;
  s.precision(precision);
  s << v;
  return s.str();
}

}  // namespace gdm
