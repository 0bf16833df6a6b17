// The embedded phantom (data/phantom.mha) that gdm runs on without an input.
#pragma once

#include <string>
#include <vector>

namespace gdm_cli {

// Its threshold (HU): between the soft tissue (40 HU) and the object (1000 HU).
constexpr double kPhantomThreshold = 400.0;

// The folders searched, in order: $GDM_DATA_DIR, <executable>/../share/gdm
// (installed), <executable>/data (build tree), the source tree's data/.
std::vector<std::string> phantom_candidates();

// The first candidate that exists; "" when none.
std::string find_phantom();

}  // namespace gdm_cli
