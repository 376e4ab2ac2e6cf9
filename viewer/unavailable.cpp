// Built instead of the viewer when CMake found no GLFW: everything else works, `aamap view` explains.
#include "core/error.h"
#include "viewer/viewer.h"

namespace aamap {

bool viewerBuilt() { return false; }

void runViewer(const ExperimentConfig&, const ViewerOptions&) {
    throw EnvironmentError(
        "aamap view is not available: this build has no GLFW 3 (CMake did not find it). "
        "Install it (Debian: apt-get install libglfw3-dev) and configure the build again");
}

}  // namespace aamap
