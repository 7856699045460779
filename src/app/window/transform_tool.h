// The lattice tool's modal transforms, as Blender has them: G moves, R rotates and S scales the selected
// control points about their median point, following the mouse. X, Y or Z locks a world axis (the same key
// again unlocks it); a typed value replaces the mouse (G Z 0.5 Enter moves 0.5 world units along Z, R Z 90
// Enter turns 90 degrees about +Z, S 2 Enter doubles the distances to the pivot; Backspace edits, '-' negates).
// Enter or a left click confirms: one undo step. Esc or a right click cancels: the session takes the drag back
// and nothing is recorded.
//
// The engine does the moving: an interactive control-point drag (Session::stroke().beginControl), each update the
// offsets since the start (Session::stroke().updateControlPerPoint: rotation and scale move every point
// differently), tested for injectivity and stopped at the last injective position like a mouse drag. The
// engine moves each point straight from where it is, so a large change of angle or factor (a typed value) is
// sent as steps along the rotation or scale (at most 10 degrees, or a factor of 1.25, each): a straight line
// between two rotations 90 degrees apart squashes the lattice half way, which the conic injectivity test
// refuses although both ends are rigid.
//
// Mouse: a move follows the cursor in the plane through the pivot facing the eye, or along the locked axis
// (the point of the axis nearest the cursor's ray); a rotation follows the cursor's angle about the pivot on
// the screen (about the view axis, or the locked axis turned the way the cursor turns); a scale is the
// cursor's distance from the pivot over its distance at the start.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "app/window/input_events.h"
#include "core/mesh_types.h"
#include "render/scene.h"

namespace sculpt::app {

struct AppState;

enum class TransformKind { Move, Rotate, Scale };

struct TransformState {
    bool active = false;
    TransformKind kind = TransformKind::Move;
    int axis = -1;             // -1 free; 0, 1, 2: locked to world X, Y, Z
    std::string digits;        // the typed value without its sign, e.g. "0.5"; empty: the mouse decides
    bool negate = false;       // '-' typed: the value (typed or the mouse's) is negated
    std::vector<int> points;   // the control points that move (selected, not pinned), sorted
    Positions starts;          // their positions when it began, #points x 3
    Eigen::Vector3d pivot = Eigen::Vector3d::Zero();     // their median point
    Eigen::Vector3d viewAxis = Eigen::Vector3d::UnitZ(); // towards the eye when it began
    double startX = 0.0, startY = 0.0;     // the cursor when it began, framebuffer pixels
    double cursorX = 0.0, cursorY = 0.0;   // the cursor now
    double screenAngle = 0.0;  // Rotate: the cursor's turn about the pivot since the start, radians, CCW on screen
    std::string readout;       // "Move Z: 0.5", the head of the status line
    bool stopped = false;      // the last update stopped short (refused further by the engine)
    std::string stopCause;     //   OpReport::refusedBy of that stop ("lattice", "triangles", ...)
    std::string stopWords;     //   and what the engine found there (OpReport::failureWords)
    // What was last asked of the session: Move an offset, Rotate an angle (radians) about `axis` (-1: the view
    // axis), Scale a factor along `axis` (-1: all three).
    struct Pose {
        int axis = -1;
        double value = 0.0;
        Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    };
    Pose applied;
};

// G / R / S in the lattice tool: starts a transform of the selection at the cursor. False (the status line
// says why) when nothing can move: no selection, all of it pinned, or a drag already running.
bool beginTransform(AppState& state, TransformKind kind, double cursorX, double cursorY);
// Every key while a transform runs goes here (presses and repeats): axis keys, the typed value, Enter, Esc.
// Other keys are swallowed, so no shortcut acts in the middle of a transform.
void transformKey(AppState& state, const KeyEvent& event);
void transformMouseMove(AppState& state, double x, double y);
// Ends it: confirm keeps what it applied as one history entry; cancel takes it back exactly.
void confirmTransform(AppState& state);
void cancelTransform(AppState& state);

// The locked axis through the pivot, for the renderer's overlay (nothing while free or idle).
void appendTransformGuides(const AppState& state, render::ConstraintView& view);
// Dear ImGui, over the 3D view: a dashed line from the pivot to the cursor while rotating or scaling.
void drawTransformOverlay(const AppState& state);

}  // namespace sculpt::app
