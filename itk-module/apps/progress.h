// Progress on stderr, one report per deformation cycle: updated in place on
// a terminal, plain lines otherwise (logs, CI), nothing with --quiet.
#pragma once

#include <chrono>
#include <cstddef>

namespace gdm_cli {

// The figures of one deformation cycle (the filter's Current* getters).
struct CycleFigures {
  std::size_t cycle = 0;     // 1-based
  std::size_t stage = 0;     // global refinements done so far
  std::size_t vertices = 0;
  std::size_t faces = 0;
  std::size_t moving = 0;    // vertices that moved in the cycle
  double progress = 0.0;     // the filter's estimate in [0, 1)
};

class ProgressPrinter {
 public:
  explicit ProgressPrinter(bool quiet);
  // One deformation cycle done.
  void cycle(const CycleFigures& c);
  // Ends the in-place line on a terminal.
  void finish();

 private:
  bool quiet_;
  bool terminal_;
  bool open_line_ = false;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace gdm_cli
