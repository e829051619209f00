// Per-frame uniforms shared by every render stage. Mirrors `FrameUniforms`
// in src/render/frame_uniforms.rs (std140; a test compares the offsets).
#ifndef MEADOW_FRAME_GLSL
#define MEADOW_FRAME_GLSL

// View modes (frame.view.x), matching `ViewMode` in Rust.
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
} frame;

#endif
