#include "app/window/transform_tool.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>
#include <imgui.h>

#include "app/window/app_state.h"
#include "app/window/panels.h"
#include "app/window/picking.h"
#include "app/window/tool_commands.h"
#include "app/window/wording.h"

namespace sculpt::app {
namespace {

constexpr double kPi = 3.14159265358979323846;
const char* const kAxisNames[3] = {"X", "Y", "Z"};

Eigen::Vector3d toEigen(const glm::dvec3& v) { return {v.x, v.y, v.z}; }

std::string number(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.4g", value == 0.0 ? 0.0 : value);  // no "-0"
    return text;
}

// An offset's components as the readout shows them, "0.1, 0, 0.3": a component below 1e-9 of the offset's length
// is rounding left by projecting the cursor onto the view plane (a free move in a front view gave
// "0.1, -4.441e-16, 0.3") and shows as 0.
std::string components(const Eigen::Vector3d& offset) {
    const double noise = 1e-9 * offset.norm();
    const auto shown = [&](double value) { return number(std::abs(value) <= noise ? 0.0 : value); };
    return shown(offset.x()) + ", " + shown(offset.y()) + ", " + shown(offset.z());
}

// Where the cursor's ray meets the plane through the pivot facing the eye (as it was at the start).
bool cursorOnViewPlane(const AppState& state, double x, double y, Eigen::Vector3d& point) {
    const TransformState& t = state.transform;
    Ray ray;
    return rayThroughPixel(state.camera, state.framebufferWidth, state.framebufferHeight, x, y, ray) &&
           intersectPlane(ray, t.pivot, t.viewAxis, point);
}

// The parameter along the locked axis (pivot + s * axis) of the axis point nearest the cursor's ray; false
// when the axis points at the eye (no direction on the screen to follow).
bool cursorAlongAxis(const AppState& state, double x, double y, double& s) {
    const TransformState& t = state.transform;
    Ray ray;
    if (!rayThroughPixel(state.camera, state.framebufferWidth, state.framebufferHeight, x, y, ray)) return false;
    const Eigen::Vector3d a = Eigen::Vector3d::Unit(t.axis), w = t.pivot - ray.origin;
    const double b = a.dot(ray.direction), denominator = 1.0 - b * b;
    if (denominator < 1e-6) return false;
    s = (b * ray.direction.dot(w) - a.dot(w)) / denominator;
    return std::isfinite(s);
}

bool pivotPixel(const AppState& state, double& x, double& y) {
    return projectToPixel(state.camera, state.framebufferWidth, state.framebufferHeight, state.transform.pivot, x, y);
}

// The cursor's angle about the pivot on the screen, counter-clockwise (pixels have y down).
double cursorAngle(const AppState& state, double x, double y) {
    double px = 0.0, py = 0.0;
    if (!pivotPixel(state, px, py)) return 0.0;
    return std::atan2(-(y - py), x - px);
}

// The typed value, or NaN while nothing is typed.
double typedValue(const TransformState& t) {
    if (t.digits.empty()) return NAN;
    const double value = std::strtod(t.digits.c_str(), nullptr);
    return t.negate ? -value : value;
}

std::string typedText(const TransformState& t) { return std::string("[") + (t.negate ? "-" : "") + t.digits + "|]"; }
// The typed value in words: "45 deg", "-0.5".
std::string typedValueText(const TransformState& t) {
    return (t.negate ? "-" : "") + t.digits + (t.kind == TransformKind::Rotate ? " deg" : "");
}

using Pose = TransformState::Pose;

// The pose the cursor and the typed value ask for.
Pose requestedPose(const AppState& state) {
    const TransformState& t = state.transform;
    Pose pose;
    pose.axis = t.axis;
    const double typed = typedValue(t);
    const bool typing = !t.digits.empty();
    const double sign = t.negate ? -1.0 : 1.0;
    switch (t.kind) {
        case TransformKind::Move:
            if (typing) {
                // note: as in Blender, a typed value without an axis goes along X.
                pose.offset = typed * Eigen::Vector3d::Unit(std::max(t.axis, 0));
            } else if (t.axis >= 0) {
                double s0 = 0.0, s1 = 0.0;
                if (cursorAlongAxis(state, t.startX, t.startY, s0) && cursorAlongAxis(state, t.cursorX, t.cursorY, s1))
                    pose.offset = sign * (s1 - s0) * Eigen::Vector3d::Unit(t.axis);
            } else {
                Eigen::Vector3d a, b;
                if (cursorOnViewPlane(state, t.startX, t.startY, a) && cursorOnViewPlane(state, t.cursorX, t.cursorY, b))
                    pose.offset = sign * (b - a);
            }
            break;
        case TransformKind::Rotate:
            if (typing) {
                pose.value = typed * kPi / 180.0;  // right-handed about the axis
            } else {
                // Turned the way the cursor turns on the screen: a locked axis may point away from the eye.
                const bool away = t.axis >= 0 && Eigen::Vector3d::Unit(t.axis).dot(t.viewAxis) < 0.0;
                pose.value = sign * t.screenAngle * (away ? -1.0 : 1.0);
            }
            break;
        case TransformKind::Scale:
            pose.value = 1.0;
            if (typing) {
                pose.value = typed;
            } else {
                double px = 0.0, py = 0.0;
                if (pivotPixel(state, px, py)) {
                    const double from = std::max(std::hypot(t.startX - px, t.startY - py), 1.0);
                    pose.value = sign * std::hypot(t.cursorX - px, t.cursorY - py) / from;
                }
            }
            break;
    }
    return pose;
}

// "Move Y", "Rotate (view axis)", "Scale": the head of the readout.
std::string headOf(const TransformState& t) {
    const std::string axisName = t.axis >= 0 ? std::string(" ") + kAxisNames[t.axis] : std::string();
    switch (t.kind) {
        case TransformKind::Move: return "Move" + (t.axis < 0 && !t.digits.empty() ? std::string(" X") : axisName);
        case TransformKind::Rotate: return "Rotate" + (t.axis >= 0 ? axisName : std::string(" (view axis)"));
        case TransformKind::Scale: return "Scale" + axisName;
    }
    return {};
}

// A pose's value as the readout shows it: "0.5", "0.1, 0, 0.3 (length 0.316)", "40 deg", "1.14".
std::string valueOf(const TransformState& t, const Pose& pose) {
    switch (t.kind) {
        case TransformKind::Move: {
            const int axis = t.axis >= 0 ? t.axis : -1;
            if (axis >= 0) return number(pose.offset[axis]);
            return components(pose.offset) + " (length " + number(pose.offset.norm()) + ")";
        }
        case TransformKind::Rotate: return number(pose.value * 180.0 / kPi) + " deg";
        case TransformKind::Scale: return number(pose.value);
    }
    return {};
}

// A pose in words, for the history and the status line: "along Y by 0.5", "by (0.1, 0, 0.3)", "about Z by 40 deg",
// "about the view axis by 40 deg", "along X by 1.14", "by 1.14".
std::string poseWords(const TransformState& t, const Pose& pose) {
    const std::string along = pose.axis >= 0 ? std::string("along ") + kAxisNames[pose.axis] + " " : std::string();
    switch (t.kind) {
        case TransformKind::Move:
            if (pose.axis >= 0) return along + "by " + number(pose.offset[pose.axis]);
            return "by (" + components(pose.offset) + ")";
        case TransformKind::Rotate:
            return std::string("about ") + (pose.axis >= 0 ? kAxisNames[pose.axis] : "the view axis") + " by " +
                   number(pose.value * 180.0 / kPi) + " deg";
        case TransformKind::Scale: return along + "by " + number(pose.value);
    }
    return {};
}

bool sameGeometry(const TransformState& t, const Pose& a, const Pose& b) {
    if (t.kind == TransformKind::Move) return a.offset == b.offset;
    return a.value == b.value && (a.axis == b.axis || a.value == (t.kind == TransformKind::Rotate ? 0.0 : 1.0));
}

// Each moving point's offset from its start in this pose.
Eigen::MatrixX3d offsetsOf(const TransformState& t, const Pose& pose) {
    const Eigen::Index count = t.starts.rows();
    Eigen::MatrixX3d offsets(count, 3);
    if (t.kind == TransformKind::Move) {
        offsets.rowwise() = pose.offset.transpose();
        return offsets;
    }
    const Eigen::Vector3d axis = pose.axis >= 0 ? Eigen::Vector3d::Unit(pose.axis) : t.viewAxis;
    const Eigen::Matrix3d rotation = Eigen::AngleAxisd(pose.value, axis).toRotationMatrix();
    for (Eigen::Index r = 0; r < count; ++r) {
        const Eigen::Vector3d p = t.starts.row(r).transpose(), d = p - t.pivot;
        Eigen::Vector3d moved;
        if (t.kind == TransformKind::Rotate) moved = rotation * d - d;
        else if (pose.axis >= 0) moved = (pose.value - 1.0) * d[pose.axis] * axis;
        else moved = (pose.value - 1.0) * d;
        offsets.row(r) = moved.transpose();
    }
    return offsets;
}

// The poses to send on the way from `from` to `to` (the last is `to`): rotations in steps of at most
// 10 degrees and scales by factors of at most 1.25 (through the identity when the axis changes); moves and
// scales through zero or a sign change in one straight step.
std::vector<Pose> pathBetween(TransformKind kind, const Pose& from, const Pose& to) {
    if (kind == TransformKind::Move) return {to};
    const double identity = kind == TransformKind::Rotate ? 0.0 : 1.0;
    if (from.axis != to.axis && from.value != identity) {
        Pose rest = from;
        rest.value = identity;
        std::vector<Pose> path = pathBetween(kind, from, rest);
        rest.axis = to.axis;
        for (const Pose& pose : pathBetween(kind, rest, to)) path.push_back(pose);
        return path;
    }
    const bool geometric = kind == TransformKind::Scale && from.value > 0.0 && to.value > 0.0;
    const double span = geometric ? std::abs(std::log(to.value / from.value)) / std::log(1.25)
                      : kind == TransformKind::Rotate ? std::abs(to.value - from.value) / (10.0 * kPi / 180.0) : 1.0;
    const int steps = std::clamp(static_cast<int>(std::ceil(span)), 1, 64);
    std::vector<Pose> path;
    for (int k = 1; k <= steps; ++k) {
        Pose pose = to;
        const double s = static_cast<double>(k) / steps;
        if (k < steps)
            pose.value = geometric ? from.value * std::pow(to.value / from.value, s) : from.value + s * (to.value - from.value);
        path.push_back(pose);
    }
    return path;
}

// The pose a fraction f of the way from `from` to `to` (a step of pathBetween: both on one axis, or `from` the
// identity).
Pose blend(TransformKind kind, const Pose& from, const Pose& to, double f) {
    Pose pose = to;
    if (kind == TransformKind::Move) pose.offset = from.offset + f * (to.offset - from.offset);
    else pose.value = from.value + f * (to.value - from.value);
    return pose;
}

// What stopped the transform, in words: stopCauseWords, and where crossing triangles stopped it, where and which
// parts in the engine's words: "the surface would cross itself near (0.1, 0.2, 0.3)", "the surface would cross
// itself: part 1 (80 triangles) and part 2 (80 triangles) would cross (of the mesh's 2 parts) near (...)". The
// engine's own "the surface would pass through itself" is not said a second time. Where vertices resting outside
// the lattice's box (a brush stroke pulled them out of it) were left behind by the moving cage, which tears the
// surface there, they are named with the way out, as the end of the drag that pulled them out named them.
std::string stopWhy(const AppState& state, const TransformState& t) {
    const std::string cause = stopCauseWords(t.stopCause);
    if (t.stopCause != "triangles") return cause;
    const std::string same = "the surface would pass through itself";
    std::string why = t.stopWords.empty() ? cause
                      : t.stopWords.rfind(same, 0) == 0 ? cause + t.stopWords.substr(same.size())
                                                        : cause + ": " + t.stopWords;
    if (const int left = state.session.verticesLeftOutsideCage(); left > 0)
        why += "; " + countOf(static_cast<size_t>(left), "vertex", "vertices") + " outside the lattice's box " + (left == 1 ? "stays" : "stay") +
               " where " + (left == 1 ? "it is" : "they are") + " (Lattice set-up with more padding takes them in)";
    return why;
}

// Sends one pose to the session; the report is the status line's.
Status sendPose(AppState& state, const Pose& pose, core::OpReport& report) {
    Status s = state.session.stroke().updateControlPerPoint(offsetsOf(state.transform, pose), report);
    if (!s) return s;
    if (report.status == core::OpStatus::Applied) noteSessionMoved(state);
    state.hasReport = true;
    state.lastReport = report;
    state.stats.solveMs = report.wallMs;
    return s;
}

// Asks the session for the transform as it now stands, along the path from the pose applied, and keeps in
// t.applied the pose the lattice really is in: a step that would fold stops where the session stopped it (a move
// or scale moves each point linearly with its value, so the stop is the pose a fraction of the step on; a
// rotation's straight step is not a rotation, so the points are put on the rotation of that angle, or back on
// the step's start where that would fold). What is shown is what Enter keeps.
void applyTransform(AppState& state) {
    TransformState& t = state.transform;
    const Pose wanted = requestedPose(state);
    std::string note;
    Status s = Status::success();
    if (!std::isfinite(wanted.value) || !wanted.offset.allFinite()) {
        s = Status::error("the typed value is not a number");
    } else if (t.kind == TransformKind::Scale && !t.digits.empty() && wanted.value == 0.0) {
        // note: "0" on the way to "0.5" would flatten the points (and stop them there); it waits for more digits.
        note = "  (0 would flatten the points: type on)";
    } else {
        t.stopped = false;
        t.stopCause.clear();
        t.stopWords.clear();
        Pose reached = t.applied;
        for (const Pose& pose : pathBetween(t.kind, t.applied, wanted)) {
            core::OpReport report;
            s = sendPose(state, pose, report);
            if (!s) break;
            if (report.fractionApplied >= 1.0 || report.status == core::OpStatus::NoOp) {
                reached = pose;
                continue;
            }
            t.stopped = true;
            t.stopCause = report.refusedBy;
            t.stopWords = report.failureWords;
            const double f = std::max(0.0, report.fractionApplied);
            const Pose partial = blend(t.kind, reached, pose, f);
            if (t.kind != TransformKind::Rotate || f == 0.0) {
                reached = partial;
            } else {
                core::OpReport onRotation;
                if (Status r = sendPose(state, partial, onRotation); r && onRotation.fractionApplied >= 1.0) {
                    reached = partial;
                } else {
                    core::OpReport back;
                    if (Status b = sendPose(state, reached, back); !b) s = b;
                }
            }
            break;
        }
        if (s) t.applied = reached;
    }
    const Pose identity{t.axis, t.kind == TransformKind::Scale ? 1.0 : 0.0, Eigen::Vector3d::Zero()};
    const bool showsReached = t.digits.empty() && !t.negate;  // the readout shows the pose reached, not a typed value
    t.readout = headOf(t) + ": " + (showsReached ? valueOf(t, t.applied) : typedText(t) + (t.kind == TransformKind::Rotate ? " deg" : ""));
    if (s && t.stopped)
        note = sameGeometry(t, t.applied, identity)
                   ? "  (refused at once: " + stopWhy(state, t) + "; nothing moved)"
                   // (the value reached, unless the readout shows it already: not said twice)
                   : "  (stopped " + (showsReached ? std::string("there") : "at " + valueOf(t, t.applied)) + " where " + stopWhy(state, t) + ")";
    std::string text = t.readout + (s ? note : "  (" + s.message + ")");
    text += "   X Y Z: axis, type a value, Enter or click: confirm, Esc or right-click: cancel";
    setStatus(state, text, !s);
    state.gpu.fields = true;
}

}  // namespace

bool beginTransform(AppState& state, TransformKind kind, double cursorX, double cursorY) {
    if (state.drag.active || state.transform.active || state.session.mesh().empty()) return false;
    clampLatticeSelection(state);
    const core::Lattice& lattice = state.session.lattice();
    std::vector<int> movable;
    for (int id : state.tools.lattice.points)
        if (!lattice.pinned[static_cast<size_t>(id)]) movable.push_back(id);
    if (movable.empty()) {
        setStatus(state, state.tools.lattice.points.empty()
                             ? "Select control points first (click, Shift+click, a box or A), then G, R or S."
                             : "The selected control points are pinned; press P to unpin them.",
                  true);
        return false;
    }
    if (Status s = state.session.stroke().beginControl(movable); !s) {
        setStatus(state, "Cannot move the control points: " + s.message, true);
        return false;
    }
    TransformState t;
    t.active = true;
    t.kind = kind;
    t.points = movable;
    t.starts.resize(static_cast<Eigen::Index>(movable.size()), 3);
    for (size_t r = 0; r < movable.size(); ++r) {
        t.starts.row(static_cast<Eigen::Index>(r)) = lattice.controlPoint(movable[r]).transpose();
        t.pivot += lattice.controlPoint(movable[r]) / static_cast<double>(movable.size());
    }
    t.viewAxis = toEigen(state.camera.towardEye());
    t.startX = t.cursorX = cursorX;
    t.startY = t.cursorY = cursorY;
    t.applied.value = kind == TransformKind::Scale ? 1.0 : 0.0;
    state.transform = std::move(t);
    state.drag = DragState{};
    state.drag.active = true;
    state.drag.kind = DragKind::Transform;
    state.tools.hint.clear();
    applyTransform(state);  // nothing moves yet (NoOp); puts the readout up
    return true;
}

void transformMouseMove(AppState& state, double x, double y) {
    TransformState& t = state.transform;
    if (!t.active) return;
    if (t.kind == TransformKind::Rotate) {
        // Accumulated turn, so that more than half a turn keeps its sign.
        t.screenAngle += std::remainder(cursorAngle(state, x, y) - cursorAngle(state, t.cursorX, t.cursorY), 2.0 * kPi);
    }
    t.cursorX = x;
    t.cursorY = y;
    applyTransform(state);
}

void transformKey(AppState& state, const KeyEvent& event) {
    TransformState& t = state.transform;
    if (!t.active || event.action == KeyAction::Release) return;
    if (event.modifiers.control || event.modifiers.super) return;  // shortcuts wait until it ends
    const bool press = event.action == KeyAction::Press;
    const int digit = digitOf(event.key);
    if (digit >= 0) {
        t.digits += static_cast<char>('0' + digit);
    } else if ((event.key == Key::Period || event.key == Key::NumpadDecimal)) {
        if (t.digits.find('.') == std::string::npos) t.digits += t.digits.empty() ? "0." : ".";
    } else if ((event.key == Key::Minus || event.key == Key::NumpadMinus) && press) {
        t.negate = !t.negate;
    } else if (event.key == Key::Backspace) {
        if (!t.digits.empty()) t.digits.pop_back();
        else t.negate = false;
    } else if ((event.key == Key::X || event.key == Key::Y || event.key == Key::Z) && press) {
        const int axis = event.key == Key::X ? 0 : event.key == Key::Y ? 1 : 2;
        t.axis = t.axis == axis ? -1 : axis;  // the same key again: free (Blender toggles through global)
    } else if (event.key == Key::Enter && press) {
        confirmTransform(state);
        return;
    } else if (event.key == Key::Escape && press) {
        cancelTransform(state);
        return;
    } else {
        return;  // swallowed
    }
    applyTransform(state);
}

void confirmTransform(AppState& state) {
    TransformState& t = state.transform;
    if (!t.active) return;
    const std::string verb = t.kind == TransformKind::Move ? "move" : t.kind == TransformKind::Rotate ? "rotate" : "scale";
    const std::string words = poseWords(t, t.applied);
    const std::string points = countOf(t.points.size(), "control point");
    const bool stopped = t.stopped;
    const std::string why = stopped ? stopWhy(state, t) : std::string();
    const std::string typed = t.digits.empty() ? std::string() : typedValueText(t);
    if (Status named = state.session.stroke().setLabel(verb + " " + points + " " + words); !named)
        setStatus(state, "Cannot name the history entry: " + named.message, true);
    // note: the journal, not the history's size: after an undo a new entry replaces the redo branch.
    const size_t before = state.session.history().journal().size();
    state.session.stroke().end();
    const bool recorded = state.session.history().journal().size() > before;
    state.transform = TransformState{};
    state.drag = DragState{};
    state.gpu.fields = true;
    std::string text;
    if (recorded) {
        text = std::string(verb == "move" ? "Moved " : verb == "rotate" ? "Rotated " : "Scaled ") + points + " " + words;
        if (stopped) text += " (stopped there: further, " + why + (typed.empty() ? std::string() : "; " + typed + " was typed") + ")";
        text += ": one undo step.";
    } else {
        text = stopped ? "Nothing moved: at once, " + why + "." : "Nothing moved.";
    }
    setStatus(state, text, false);
}

void cancelTransform(AppState& state) {
    if (!state.transform.active) return;
    core::OpReport report;
    const Status s = state.session.stroke().cancel(report);
    if (s && report.status == core::OpStatus::Applied) noteSessionMoved(state);
    state.transform = TransformState{};
    state.drag = DragState{};
    state.gpu.fields = true;
    if (!s) setStatus(state, "Cannot cancel the transform: " + s.message, true);
    else setStatus(state, "Transform cancelled: the control points are back where they were.", false);
}

void appendTransformGuides(const AppState& state, render::ConstraintView& view) {
    const TransformState& t = state.transform;
    if (!t.active || t.axis < 0) return;
    // Long enough to cross the view; the projection clips it at the near and far planes.
    const Eigen::Vector3d reach = 8.0 * state.camera.sceneRadius * Eigen::Vector3d::Unit(t.axis);
    view.axisLines.push_back({t.pivot - reach, t.pivot + reach, t.axis});
}

void drawTransformOverlay(const AppState& state) {
    const TransformState& t = state.transform;
    if (!t.active || t.kind == TransformKind::Move) return;
    double px = 0.0, py = 0.0;
    if (!pivotPixel(state, px, py)) return;
    const ImVec2 a = framebufferToUi(state, px, py), b = framebufferToUi(state, t.cursorX, t.cursorY);
    ImDrawList* draw = ImGui::GetForegroundDrawList();
    // Dashed, as Blender draws it: 6-pixel dashes.
    const float length = std::hypot(b.x - a.x, b.y - a.y);
    const int dashes = std::max(1, static_cast<int>(length / 12.0f));
    for (int i = 0; i < dashes; ++i) {
        const float s0 = static_cast<float>(i) / dashes, s1 = (i + 0.5f) / dashes;
        draw->AddLine(ImVec2(a.x + (b.x - a.x) * s0, a.y + (b.y - a.y) * s0),
                      ImVec2(a.x + (b.x - a.x) * s1, a.y + (b.y - a.y) * s1), IM_COL32(20, 20, 20, 220), 1.5f);
    }
    draw->AddCircleFilled(a, 3.0f, IM_COL32(255, 255, 255, 230));
}

}  // namespace sculpt::app
