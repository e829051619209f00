#version 450
#extension GL_GOOGLE_include_directive : require
// Ground: the plane y = 0 out to the horizon. Each pixel's view ray meets
// it (or the pixel is sky and is discarded); the depth is that point's.
// Soil-shaded (glsl/common/soil.glsl). Over terrain, the terrain mesh draws
// the ground in its square and this plane only the hazy rest beyond.
#include "frame.glsl"
#include "shadow.glsl"
#include "sky.glsl"
#include "surfaces.glsl"
#include "canopy.glsl"
#include "soil.glsl"

layout(location = 0) in vec2 v_ndc;
layout(location = 0) out vec4 out_color;

void main() {
    vec4 far_point = frame.inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 eye = frame.camera_pos;
    vec3 dir = far_point.xyz / far_point.w - eye;
    // Above the horizon (or a camera under the ground): sky.
    if (dir.y >= 0.0 || eye.y <= 0.0) {
        discard;
    }
    vec3 world = eye + dir * (-eye.y / dir.y);
    // Over terrain its mesh draws the ground in its square (src/render/terrain.rs).
    if (frame.terrain_half_side > 0.0 && all(lessThan(abs(world.xz - frame.terrain_center), vec2(frame.terrain_half_side)))) {
        discard;
    }
    vec4 clip = frame.view_proj * vec4(world, 1.0);
    // Beyond the far plane the ground still covers the sky, at the back.
    gl_FragDepth = min(clip.z / clip.w, 0.9999999);

    out_color = data_view() ? vec4(0.0, 0.0, 0.0, 1.0) : vec4(soil_lit(world, max(frame.light_dir.y, 0.0)), 1.0);
}
