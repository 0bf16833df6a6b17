// `gdm wrap`: the shrink-wrap of a mesh file (gdm::shrink_wrap, gdm/shrink_wrap.h)
// from the command line. No ITK here.
//
//   gdm wrap IN.(ply|obj|off|stl|vtk) -o OUT.(ply|obj|off|stl|vtk) --tolerance D
//            [--cell-size C] [--coverage-rounds N] [--quiet] [--report R.json]
//
// Exit codes as the rest of the CLI (cli_errors.h): 0 written, 2 bad usage,
// 3 unreadable input, 4 the wrap failed, 5 the mesh or report not written.
#pragma once

namespace gdm_cli {

// argv[1] is "wrap". Returns the exit code; prints errors as "gdm wrap: error: ...".
int wrap_command(int argc, char* argv[]);

}  // namespace gdm_cli
