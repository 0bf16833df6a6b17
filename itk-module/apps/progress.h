// Progress on stderr, one report per deformation cycle: updated in place on
// a terminal, plain lines otherwise (logs, CI), nothing with --quiet.
#pragma once

#include <chrono>
#include <cstddef>

namespace gdm_cli {

class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool quiet);
  // One deformation cycle done; `progress` is the filter's estimate in [0, 1).
  void cycle(std::size_t cycle, double progress);
  // Ends the in-place line on a terminal.
  void finish();

 private:
  bool quiet_;
  bool terminal_;
  bool open_line_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace gdm_cli
