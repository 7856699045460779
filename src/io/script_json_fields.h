// The JSON fields that several script ops (and a recording's "applied" steps) share, read and written the same
// way everywhere: the brush, a lattice's settings, constraints, lists, a lattice tool and its net edits.
// Internal to io (script_json.cpp reads, script_json_write.cpp writes, script_ops.cpp's entries use both). A read
// that fails throws json_fields::FieldError naming the field path and what was expected.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/deform/refinement.h"
#include "core/session/operation.h"
#include "core/volume/lattice_edit.h"
#include "io/json_fields.h"

namespace sculpt::io::script_fields {

using nlohmann::json;

// Reading (script_json.cpp).

// The brush fields of a drag or drag_vertex op (or of a recorded operation's "brush"): "radius" (world units,
// 0 = none), "strength" in (0, 1], "falloff" ("smooth", "medium", "sharp"), "symmetry" ("x", "yz", ...).
core::BrushSettings parseBrush(const json& j, const std::string& path);
// A lattice's settings: a box lattice ("resolution", "degree", "padding", "pin_layers", "region") or a lattice of
// any shape ("kind", lattice_json.h) with its "pin_layers".
core::LatticeSettings parseLattice(const json& j, const std::string& path);
// [{"source": [x,y,z], "target": [x,y,z]}, ...], non-empty unless allowEmpty.
std::vector<core::PointConstraint> parseConstraints(const json& list, const std::string& path, bool allowEmpty);
std::vector<int> intList(const json& list, const std::string& path);
std::vector<double> numberList(const json& list, const std::string& path);
Eigen::MatrixX3d vectorRows(const json& list, const std::string& path);  // [[x,y,z], ...]
// A fraction of the bounding-box diagonal: finite and > 0.
double tolerance(const json& value, const std::string& path);
// The fields of set_refinement (Session::refinement().set); absent ones keep their defaults.
core::RefinementSettings parseRefinementSettings(const json& j, const std::string& path);
// The lattice tool of an add_lattice / edit_lattice op: "lattice" (lattice_json.h) or "file" (a library file,
// relative to the script's folder), then optionally "place" (the positioning command, Coquillart 1990, 3.2).
// An edit_lattice op (`edit`) may give neither (its "edits" then apply to the tool's current net: the tool's net
// stays null) and gives no name unless it has "name" (the tool keeps its own).
core::LatticeTool parseTool(const json& j, const std::string& path, bool edit);
// edit_lattice's "edits" (core/volume/lattice_edit.h): {"move": {"points": [slot, ...], "offset": [x,y,z]}},
// {"merge": [slot, slot, ...]}, {"refine": {"axis": a}}, {"insert": {"axis": a, "at": u, "times": m}},
// {"remove": {"axis": a, "index": i}}.
std::vector<core::NetEdit> parseEdits(const json& j, const std::string& path);

// Writing (script_json_write.cpp): what the readers above read back bit for bit (doubles in the shortest form
// that reads back to the same bits).

// Whether a brush is used: a radius, symmetry, or strength below 1 (else a drag writes no brush fields).
bool brushUsed(const core::BrushSettings& brush);
// The brush's fields, only when it is used.
void addBrushJson(json& j, const core::BrushSettings& brush);
json latticeJson(const core::LatticeSettings& settings);
json constraintsJson(const std::vector<core::PointConstraint>& list);
json rowsJson(const Eigen::MatrixX3d& rows);
json editsJson(const std::vector<core::NetEdit>& edits);

}  // namespace sculpt::io::script_fields
