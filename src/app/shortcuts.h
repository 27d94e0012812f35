// The app's keyboard shortcuts: one table that drives both the key handling and the Help
// window, so the two cannot disagree.
//
// Key codes are GLFW's (GLFW_KEY_*: printable keys are their upper-case ASCII code), which is
// also how the ImGui GLFW backend indexes ImGuiIO::KeysDown; the headless driver of the tests
// presses the same codes. GL-free.
#pragma once

#include <span>
#include <string>

namespace snert::app {

namespace key {
inline constexpr int Space = 32, Slash = 47;
inline constexpr int Digit1 = 49, Digit2 = 50, Digit3 = 51, Digit4 = 52;
inline constexpr int B = 66, C = 67, E = 69, F = 70, H = 72, L = 76, O = 79, Q = 81, R = 82, S = 83,
                     W = 87;
inline constexpr int V = 86;
inline constexpr int Escape = 256, Enter = 257, Tab = 258, Right = 262, Left = 263, Down = 264,
                     Up = 265, PageUp = 266, PageDown = 267, Home = 268, End = 269, F1 = 290,
                     F12 = 301;
} // namespace key

enum class Action {
    PlayPause,
    StepBack,
    StepForward,
    FirstIteration,
    LastIteration,
    RunToConvergence,
    ResetCamera,
    ViewFront,
    ViewSide,
    ViewTop,
    ViewIso,
    ShadingFlat,
    ShadingSmooth,
    ShadingQuality,
    ToggleWireframe,
    OpenFile,
    Screenshot,
    ExportMeshes,
    ToggleSidePanel,
    ToggleBottomPanel,
    ToggleSliceView,
    NextSlice,
    PreviousSlice,
    Help,
    Quit,
};

struct Shortcut {
    Action action;
    int key;                 // key code (see above)
    bool ctrl = false;       // with Ctrl held
    const char* keys;        // as the Help window and the menus show it, e.g. "Ctrl+O"
    const char* description; // what it does
};

// Every shortcut, in the order the Help window lists them. An action may have two entries
// (F1 and ? both open the help); the first is the one menus show.
std::span<const Shortcut> shortcuts();

// The first shortcut of `action` (menus show its keys).
const Shortcut& shortcut_for(Action action);

} // namespace snert::app
