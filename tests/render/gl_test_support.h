// Shared pieces of the GL tests: one offscreen renderer per test process, golden-image comparison.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "render/offscreen_renderer.h"

namespace sculpt::test {

// The process-wide renderer (backend from SCULPT_GL_BACKEND: osmesa (default), egl or auto), made current.
// REQUIREs that it could be created, so a machine without GL fails loudly, naming the reason.
render::OffscreenRenderer& glTestRenderer();

// Folder for test output (actual and diff images of failed comparisons); created on first use.
std::string glTestOutputDir();

// Compares `actual` with tests/golden/<name>.png (see the thresholds in gl_test_support.cpp). On a
// mismatch writes <output>/<name>_actual.png and <name>_diff.png and fails, saying where they are.
// With SCULPT_UPDATE_GOLDEN=1 in the environment writes the golden instead (and warns).
void checkGolden(const render::Rgba8Image& actual, const std::string& name);

// Largest per-channel difference between two pixels at (x, y), or 255 if the sizes differ.
int pixelDifference(const render::Rgba8Image& a, const render::Rgba8Image& b, int x, int y);

// Fraction of the pixels that differ by more than the golden tolerance (gl_test_support.cpp), counting only
// pixels where `ignore` (one byte per pixel, rows top-down; empty: none ignored) is 0; 1 if the sizes differ.
double differingFraction(const render::Rgba8Image& a, const render::Rgba8Image& b,
                         const std::vector<std::uint8_t>& ignore = {});
// The golden threshold on that fraction (the same one checkGolden applies).
double goldenMaxDifferingFraction();

}  // namespace sculpt::test
