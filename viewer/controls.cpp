// The viewer's bindings as text: shared by `aamap view --help` and every build (with or without GLFW).
#include "viewer/viewer.h"

namespace aamap {

const char* viewerControls() {
    return R"(Controls (the window title is the status line: Snapshot pass times, parameters, trace, error):
  1 snapshot   2 |Laplacian|   3 aamap   4 rays per pixel   5 render   6 error map vs the reference
  T            trace the current view selectively (the render fills in tile by tile)
  C            cancel the trace (moving the camera cancels it too)
  mouse left   drag: orbit around the scene      mouse right  drag: look around (fly)
  wheel        dolly towards / away from the pivot
  arrows       orbit                              W A S D      fly forward, left, back, right
  Q E          fly down, up                       R            back to the config's view
  B / Shift+B  blur radius +1 / -1                F / Shift+F  noise floor x1.25 / /1.25
  ] / [        spacing x2 / /2                    = / -        threshold +0.5 / -0.5
  . / ,        n +1 / -1 (n x n rays per pixel at most)
  G            strategy: the next one that uses the aamap
  H            print these controls              Esc          quit
Camera moves and Snapshot parameters re-run the Snapshot and the aamap at once; the trace runs only
on T. The error map needs the reference: traced at the current view after the render (reference
type uniform), read from the file (type file, only at the config's view), else unavailable.)";
}

}  // namespace aamap
