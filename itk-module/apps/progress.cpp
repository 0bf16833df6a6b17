#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace gdm_cli {

ProgressPrinter::ProgressPrinter(bool quiet)
    : quiet_(quiet), terminal_(::isatty(STDERR_FILENO) == 1), start_(std::chrono::steady_clock::now()) {}

void ProgressPrinter::cycle(const CycleFigures& c) {
  if (quiet_) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const int percent = static_cast<int>(100.0 * c.progress);
  if (terminal_) {
    std::fprintf(stderr, "\rcycle %5zu  stage %zu  faces %8zu  moving %7zu  %3d%%  %7.1f s ", c.cycle, c.stage,
                 c.faces, c.moving, percent, seconds);
    open_line_ = true;
  } else {
    std::fprintf(stderr, "cycle %zu stage %zu faces %zu moving %zu progress %d%% time %.2f s\n", c.cycle, c.stage,
                 c.faces, c.moving, percent, seconds);
  }
  std::fflush(stderr);
}

void ProgressPrinter::finish() {
  if (open_line_) std::fputc('\n', stderr);
  open_line_ = false;
}

}  // namespace gdm_cli
