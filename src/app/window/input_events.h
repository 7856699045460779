// Plain input events of the sculpting window, independent of GLFW (house style 10): the GLFW layer
// (glfw_main.cpp) converts its callbacks into these, and tests feed synthetic ones to the same SculptApp code.
//
// Coordinates are framebuffer pixels with the origin at the top-left corner (GLFW's window coordinates times
// the content scale), so picking and drawing agree on HiDPI screens.
#pragma once

namespace sculpt::app {

struct Modifiers {
    bool shift = false;
    bool control = false;
    bool alt = false;
    bool super = false;  // the Cmd / Windows key; treated like control for shortcuts
};

enum class MouseButton { Left, Right, Middle };
enum class ButtonAction { Press, Release };
enum class KeyAction { Press, Repeat, Release };

struct MouseButtonEvent {
    MouseButton button = MouseButton::Left;
    ButtonAction action = ButtonAction::Press;
    double x = 0.0, y = 0.0;  // cursor position, framebuffer pixels
    Modifiers modifiers;
};

struct MouseMoveEvent {
    double x = 0.0, y = 0.0;  // framebuffer pixels
    Modifiers modifiers;
};

struct ScrollEvent {
    double dx = 0.0, dy = 0.0;  // wheel notches (positive dy: away from the user = zoom in)
};

// Only the keys the app binds; everything else arrives as Other. Digits, Period and Minus are the main
// keyboard's, Numpad* the keypad's (Blender's view keys; typed values take both).
enum class Key {
    A, F, G, L, N, O, P, Q, R, S, X, Y, Z, Tab, Delete, Backspace, Enter, Escape, Home,
    Digit0, Digit1, Digit2, Digit3, Digit4, Digit5, Digit6, Digit7, Digit8, Digit9, Period, Minus,
    Numpad0, Numpad1, Numpad2, Numpad3, Numpad4, Numpad5, Numpad6, Numpad7, Numpad8, Numpad9, NumpadDecimal,
    NumpadMinus, Other
};

// 0-9 for a digit key of either the main keyboard or the keypad, -1 for any other key.
inline int digitOf(Key key) {
    if (key >= Key::Digit0 && key <= Key::Digit9) return static_cast<int>(key) - static_cast<int>(Key::Digit0);
    if (key >= Key::Numpad0 && key <= Key::Numpad9) return static_cast<int>(key) - static_cast<int>(Key::Numpad0);
    return -1;
}

struct KeyEvent {
    Key key = Key::Other;
    KeyAction action = KeyAction::Press;
    Modifiers modifiers;
};

struct FramebufferSizeEvent {
    int width = 0, height = 0;  // 0 x 0 while the window is minimised
};

// Whether the UI (Dear ImGui's io.WantCaptureMouse / WantCaptureKeyboard) claims the input: every app checks
// these before using input itself. Passed explicitly so tests can exercise both.
struct CaptureFlags {
    bool mouse = false;
    bool keyboard = false;
};

}  // namespace sculpt::app
