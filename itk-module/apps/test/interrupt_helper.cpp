// gdm_interrupt_helper OUT [REPORT]: the gdm command's last step, stopped in
// the middle. With REPORT, writes it and guards it (gdm::RemoveOnInterrupt)
// as gdm does; then writes OUT through gdm::write_file_atomically, whose body
// writes 1 MiB, says "writing" on stdout and blocks until a signal ends the
// process. The handler is installed lazily by the writer (no explicit call):
// Hostile.InterruptedWriteLeavesNoFile signals it and looks for leftovers.
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <ostream>
#include <string>

#include "gdm/mesh_io.h"

int main(int argc, char* argv[]) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: gdm_interrupt_helper OUT [REPORT]\n");
    return 2;
  }
  // As on a terminal: a script's background job starts with SIGINT ignored.
  for (const int sig : {SIGINT, SIGTERM, SIGHUP}) ::signal(sig, SIG_DFL);
  const std::string out = argv[1];
  const std::string report = argc == 3 ? argv[2] : "";
  if (!report.empty()) gdm::write_file_atomically(report, false, [](std::ostream& o) { o << "{\"status\": \"ok\"}\n"; });
  gdm::RemoveOnInterrupt guard(report);
  gdm::write_file_atomically(out, true, [](std::ostream& o) {
    o << std::string(1 << 20, '\0') << std::flush;
    static const char line[] = "writing\n";
    if (::write(1, line, sizeof line - 1) < 0) ::_exit(3);
    for (;;) ::pause();
  });
  return 1;  // not reached
}
