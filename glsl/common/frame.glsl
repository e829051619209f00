// Per-frame uniforms shared by every render stage: `FrameUniforms`, whose
// fields src/interface/defs.rs defines for both sides (tests/shaders.rs
// reads each field's offset in every shader).
#ifndef MEADOW_FRAME_GLSL
#define MEADOW_FRAME_GLSL

#include "interface.glsl"

// View modes (frame.view), matching `ViewMode` in Rust, and the data
// view VIEW_DISPLACEMENT (src/interface/defs.rs) that `--light-waves`
// draws beside each shaded frame.
#define VIEW_SHADED 0u
#define VIEW_LOD    1u
#define VIEW_MOTION 2u

// `FrameUniforms`: src/interface/defs.rs, one named field each.
layout(set = 0, binding = 0, std140) uniform Frame {
    FrameUniforms frame;
};

// In the data view only the blades write (their displacement); the sky,
// the ground and the obstacles write black.
bool data_view() {
    return frame.view == VIEW_DISPLACEMENT;
}

#endif
