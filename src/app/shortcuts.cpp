// The shortcut table.
#include "shortcuts.h"

#include <array>

namespace snert::app {

namespace {

constexpr std::array kShortcuts = {
    Shortcut{Action::PlayPause, key::Space, false, "Space",
             "play / pause the relaxation's iterations"},
    Shortcut{Action::StepBack, key::Left, false, "Left", "one iteration back"},
    Shortcut{Action::StepForward, key::Right, false, "Right", "one iteration forward"},
    Shortcut{Action::FirstIteration, key::Home, false, "Home", "first iteration (the initial net)"},
    Shortcut{Action::LastIteration, key::End, false, "End",
             "newest iteration (follow the relaxation)"},
    Shortcut{Action::RunToConvergence, key::C, false, "C", "run to convergence (relax further)"},
    Shortcut{Action::ResetCamera, key::R, false, "R", "reset the camera"},
    Shortcut{Action::ViewFront, key::Digit1, false, "1", "view from the front"},
    Shortcut{Action::ViewSide, key::Digit2, false, "2", "view from the side"},
    Shortcut{Action::ViewTop, key::Digit3, false, "3", "view from the top"},
    Shortcut{Action::ViewIso, key::Digit4, false, "4", "isometric view"},
    Shortcut{Action::ShadingFlat, key::F, false, "F", "flat shading (facets visible)"},
    Shortcut{Action::ShadingSmooth, key::S, false, "S", "smooth shading"},
    Shortcut{Action::ShadingQuality, key::Q, false, "Q", "colour triangles by quality"},
    Shortcut{Action::ToggleWireframe, key::W, false, "W", "wireframe on / off"},
    Shortcut{Action::OpenFile, key::O, true, "Ctrl+O", "open a volume file"},
    Shortcut{Action::Screenshot, key::S, true, "Ctrl+S", "save a screenshot of the views (PNG)"},
    Shortcut{Action::ExportMeshes, key::E, true, "Ctrl+E", "export the meshes shown"},
    Shortcut{Action::ToggleSidePanel, key::L, true, "Ctrl+L", "show / hide the parameter panel"},
    Shortcut{Action::ToggleBottomPanel, key::B, true, "Ctrl+B", "show / hide the bottom panel"},
    Shortcut{Action::ToggleSliceView, key::V, false, "V",
             "show / hide the slice view beside the 3D views"},
    Shortcut{Action::NextSlice, key::PageUp, false, "PageUp", "slice view: next slice"},
    Shortcut{Action::PreviousSlice, key::PageDown, false, "PageDown", "slice view: previous slice"},
    Shortcut{Action::Help, key::F1, false, "F1", "this help"},
    Shortcut{Action::Help, key::H, false, "H", "this help"},
    Shortcut{Action::Quit, key::Q, true, "Ctrl+Q", "quit"},
};

} // namespace

std::span<const Shortcut> shortcuts() {
    return kShortcuts;
}

const Shortcut& shortcut_for(Action action) {
    for (const Shortcut& s : kShortcuts)
        if (s.action == action) return s;
    return kShortcuts.front(); // every action has an entry; a unit test checks it
}

} // namespace snert::app
