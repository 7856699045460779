// How long the randomized tests run. CI's sanitizer stage (ASan + UBSan makes every iteration about 8x slower)
// sets SCULPT_TEST_SCALE=0.25: the long property tests then run a quarter of their iterations, still over the
// same kinds of cases, so memory errors are caught in every path while the stage fits CI's time. The normal
// stage and a plain `ctest` run everything.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdlib>

namespace sculpt::test {

// n iterations, times SCULPT_TEST_SCALE (a number in (0, 1]; unset, empty or invalid: 1), never below minimum.
inline int scaledCount(int n, int minimum) {
    const char* text = std::getenv("SCULPT_TEST_SCALE");
    double scale = 1.0;
    if (text != nullptr && *text != '\0') {
        char* end = nullptr;
        const double value = std::strtod(text, &end);
        if (end != text && *end == '\0' && value > 0.0 && value <= 1.0) scale = value;
    }
    return std::max(minimum, static_cast<int>(std::lround(n * scale)));
}

}  // namespace sculpt::test
