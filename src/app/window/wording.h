// Counts and commands in the window's words: "1 handle", "2 handles", "1 vertex", "3 vertices", "Undo".
#pragma once

#include <string>
#include <utility>

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

// OpReport::injectivity of an applied command, for the status line: "injective" is the check's verdict, said as
// what it means to the user ("checked: nothing folds or crosses"; without the triangle check only folds are
// tested); other verdicts ("not checked", "as recorded") are already words.
inline std::string checkWords(const std::string& injectivity, bool trianglesChecked) {
    if (injectivity == "injective") return trianglesChecked ? "checked: nothing folds or crosses" : "checked: nothing folds";
    if (injectivity == "not checked") return "not checked for folds";
    return injectivity;
}

// An engine command's report name (OpReport::op: the script op's name) in the window's words: "Undo",
// "Lattice set-up", "Control point move". A name it does not know is returned as it is.
inline std::string commandWords(const std::string& op) {
    static const std::pair<const char*, const char*> words[] = {
        {"drag", "Drag"}, {"drag_vertex", "Drag"}, {"move_control_point", "Control point move"}, {"undo", "Undo"},
        {"redo", "Redo"}, {"cancel_drag", "Cancelled drag"}, {"setup_lattice", "Lattice set-up"},
        {"add_lattice", "Adding the lattice"}, {"edit_lattice", "Lattice edit"}, {"remove_lattice", "Removing the lattice"},
        {"freeze", "Freezing the lattice"}, {"unfreeze", "Unfreezing"}, {"refine", "Refinement"},
        {"setup_tspline", "T-spline set-up"}, {"subdivide_cells", "Cell subdivision"}, {"set_weights", "Weights"},
        {"hammer", "Hammer"}, {"crimp", "Crimp"}, {"replay", "Replay"},
        {"set_pins", "Pinning"}, {"group", "Grouping"}, {"set_refinement", "Refinement setting"}, {"screenshot", "Screenshot"}};
    for (const auto& [name, text] : words)
        if (op == name) return text;
    return op;
}

}  // namespace sculpt::app
