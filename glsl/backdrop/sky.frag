#version 450
#extension GL_GOOGLE_include_directive : require
// Sky gradient by the elevation of the view ray and the sun's (sky.glsl).
#include "frame.glsl"
#include "sky.glsl"

layout(location = 0) in vec2 v_ndc;
layout(location = 0) out vec4 out_color;

void main() {
    vec4 far_point = frame.inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 dir = normalize(far_point.xyz / far_point.w - frame.camera_pos);
    out_color = data_view() ? vec4(0.0, 0.0, 0.0, 1.0) : vec4(sky_color(dir, frame.light_dir), 1.0);
}
