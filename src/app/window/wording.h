// Counts in the window's words: "1 handle", "2 handles", "1 vertex", "3 vertices".
#pragma once

#include <string>

namespace sculpt::app {

// n and the noun, singular for exactly one; plural defaults to singular + "s".
inline std::string countOf(size_t n, const std::string& singular, const std::string& plural = {}) {
    return std::to_string(n) + " " + (n == 1 ? singular : plural.empty() ? singular + "s" : plural);
}

// What stopped or refused an engine step, from OpReport::refusedBy, as the end of "where ..." / "... at once":
// "the lattice would fold", "the surface would cross itself", ...
inline std::string stopCauseWords(const std::string& refusedBy) {
    if (refusedBy == "lattice") return "the lattice would fold";
    if (refusedBy == "triangles") return "the surface would cross itself";
    if (refusedBy == "uncertified") return "the step could not be certified (no fold found)";
    if (refusedBy == "boundary") return "the lattice boundary would overlap itself";
    if (refusedBy == "symmetry") return "a point would meet its mirror image";
    return "the engine refused to go on";
}

}  // namespace sculpt::app
