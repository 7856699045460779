// The interactive window: GLFW 3.3 core-profile context, Dear ImGui (Debian's prebuilt glfw + opengl3
// backends) and the loop that turns GLFW callbacks into SculptApp's plain events.
#pragma once

#include <string>

namespace sculpt::app {

// Opens meshPath in a window and runs until it is closed. Returns the process exit code: 0, kExitBadInput
// for an unreadable mesh, 2 when no window can be opened (no display: the message points to --headless).
//
// Hidden automation for CI and benchmarks (environment variables):
//   SCULPT_WINDOW_FRAMES=N       close after N frames
//   SCULPT_WINDOW_SCREENSHOT=P   with FRAMES: write the last frame (scene + UI) to PNG file P
//   SCULPT_WINDOW_MSAA=N         samples per pixel (default: 4, none on a software rasterizer)
//   SCULPT_WINDOW_AUTODRAG=1     feed a synthetic drag (press on the centre, move up and back) through the
//                                same event path and print the frame rate while dragging
int runWindow(const std::string& meshPath);

}  // namespace sculpt::app
