#include "progress.h"

#include <unistd.h>

#include <cstdio>

namespace gdm_cli {

ProgressPrinter::ProgressPrinter(bool quiet)
    : quiet_(quiet), terminal_(::isatty(STDERR_FILENO) == 1), start_(std::chrono::steady_clock::now()) {}

void ProgressPrinter::cycle(std::size_t cycle, double progress) {
  if (quiet_) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (terminal_) {
    std::fprintf(stderr, "\rcycle %5zu  %3d%%  %7.1f s ", cycle, static_cast<int>(100.0 * progress), seconds);
    open_line_ = true;
  } else {
    std::fprintf(stderr, "cycle %zu progress %d%% time %.2f s\n", cycle, static_cast<int>(100.0 * progress), seconds);
  }
  std::fflush(stderr);
}

void ProgressPrinter::finish() {
  if (open_line_) std::fputc('\n', stderr);
  open_line_ = false;
}

}  // namespace gdm_cli
