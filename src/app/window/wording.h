// Counts in the window's words: "1 handle", "2 handles", "1 vertex", "3 vertices".
#pragma once

#include <string>

namespace sculpt::app {

// n and the noun, singular for exactly one; plural defaults to singular + "s".
inline std::string countOf(size_t n, const std::string& singular, const std::string& plural = {}) {
    return std::to_string(n) + " " + (n == 1 ? singular : plural.empty() ? singular + "s" : plural);
}

}  // namespace sculpt::app
