// Per-frame uniforms shared by every render stage. Mirrors `FrameUniforms`
// in src/render/frame_uniforms.rs (std140; a test compares the offsets).
#ifndef MEADOW_FRAME_GLSL
#define MEADOW_FRAME_GLSL

#include "interface.glsl"

// View modes (frame.view.x), matching `ViewMode` in Rust, and the data
// view VIEW_DISPLACEMENT (src/interface/defs.rs) that `--light-waves`
// draws beside each shaded frame.
#define VIEW_SHADED 0u
#define VIEW_LOD    1u
#define VIEW_MOTION 2u

layout(set = 0, binding = 0, std140) uniform Frame {
    mat4 view_proj;
    mat4 inv_view_proj;
    vec4 camera_pos;    // xyz: eye in world space
    vec4 light_dir;     // xyz: unit vector toward the light; w: ambient strength
    vec4 light_color;   // rgb: sun colour (linear); w: unused
    vec4 lod_distance;  // x: close/medium boundary, y: medium/far boundary, z: 1 = LOD on
    vec4 tess_level;    // x: close (20), y: medium (10), z: far (3): paper section 5
    vec4 ground;        // xy: the grass's centre (world x, z); z: how far from it the ground is clear (m)
    uvec4 view;         // x: view mode
    mat4 light_view_proj; // world -> the shadow map's clip space (orthographic, from the sun)
    vec4 shadow;        // x: one texel (uv units), y: 1 = shadows on, z: depth bias, w: PCF radius (texels)
    vec4 thinning;      // x: distance it begins (m), y: least share, z: band, w: 1 = on (glsl/common/thinning.glsl)
    vec4 shadow_tess_level; // tess_level of the shadow pass, which reads it as its tess_level
    vec4 terrain;       // x: the lowest ground shadows fall on (m); y: half side of the terrain mesh (0: flat, none); zw: its centre (x, z)
    vec4 canopy;        // x: leaf area index of the cover (0: none); y: the canopy's top (m); z: 1 = self-shadowing on; w: the map's LAI at 1.0 (glsl/common/canopy.glsl)
    vec4 canopy_map;    // xy: the canopy map's least corner (x, z); zw: 1 / its extent (x, z)
    vec4 cover_bounds;  // x0, z0, x1, z1: where the cover grows
    vec4 look;          // x: hue spread, y: dry share, z: dry tips, w: clump size (m) (glsl/common/grass_color.glsl)
    vec4 look_more;     // x: clump variation, y: sheen, z: translucency, w: the scene's seed, 16 bits
} frame;

// In the data view only the blades write (their displacement); the sky,
// the ground and the obstacles write black.
bool data_view() {
    return frame.view.x == VIEW_DISPLACEMENT;
}

#endif
