#version 450
#extension GL_GOOGLE_include_directive : require
// The terrain mesh: the ground's soil (glsl/common/soil.glsl, as the
// backdrop's plane shades it), lit by the ground's normal, shadowed by the
// grass and the hills.
#include "frame.glsl"
#include "shadow.glsl"
#include "sky.glsl"
#include "surfaces.glsl"
#include "canopy.glsl"
#include "soil.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 0) out vec4 out_color;

void main() {
    vec3 n = normalize(v_normal);
    out_color = data_view() ? vec4(0.0, 0.0, 0.0, 1.0) : vec4(soil_lit(v_world, max(dot(n, frame.light_dir), 0.0)), 1.0);
}
