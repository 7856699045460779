// Dear ImGui context set-up shared by the window and the tests: theme and font.
#pragma once

namespace sculpt::app {

// Creates the ImGui context (no .ini file) with the app's dark theme and DejaVu Sans at 15 * scale pixels
// when the font file is installed (ImGui's built-in font otherwise). scale: content scale (2 on HiDPI).
void createUiContext(float scale);
void destroyUiContext();

}  // namespace sculpt::app
