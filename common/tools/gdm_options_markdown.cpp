// Prints docs/options.md from the catalogue of options:
//   build/common/gdm_options_markdown > docs/options.md
#include <iostream>

#include "gdm/pipeline.h"

int main() {
  std::cout << gdm::options_markdown();
  return 0;
}
