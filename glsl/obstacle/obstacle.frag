#version 450
#extension GL_GOOGLE_include_directive : require
// Obstacles: their albedo, varied slowly so a face is not one flat colour,
// lit by the sun (Lambert) and the ambient sky, and darkened where the
// shadow map says the sun is hidden (by the grass or another obstacle).
#include "frame.glsl"
#include "shadow.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 1) in vec3 v_normal;
layout(location = 2) in vec3 v_albedo;
// The mesh's own frame: the grain moves with a rolling ball.
layout(location = 3) in vec3 v_local;
layout(location = 0) out vec4 out_color;

float hash3(vec3 p) {
    return fract(sin(dot(p, vec3(127.1, 311.7, 74.7))) * 43758.5453);
}

// Value noise in 3D: stone and wood grain enough at a metre's scale.
float value_noise3(vec3 p) {
    vec3 i = floor(p), f = fract(p);
    vec3 u = f * f * (3.0 - 2.0 * f);
    float n000 = hash3(i), n100 = hash3(i + vec3(1, 0, 0));
    float n010 = hash3(i + vec3(0, 1, 0)), n110 = hash3(i + vec3(1, 1, 0));
    float n001 = hash3(i + vec3(0, 0, 1)), n101 = hash3(i + vec3(1, 0, 1));
    float n011 = hash3(i + vec3(0, 1, 1)), n111 = hash3(i + vec3(1, 1, 1));
    return mix(mix(mix(n000, n100, u.x), mix(n010, n110, u.x), u.y),
               mix(mix(n001, n101, u.x), mix(n011, n111, u.x), u.y), u.z);
}

void main() {
    vec3 n = normalize(v_normal);
    float grain = 0.6 * value_noise3(v_local * 7.0) + 0.4 * value_noise3(v_local * 23.0);
    vec3 albedo = v_albedo * mix(0.8, 1.15, grain);
    float lambert = max(dot(n, frame.light_dir), 0.0);
    float sky = 0.75 + 0.25 * n.y;
    vec3 lit = albedo * (frame.ambient * sky + frame.light_color * lambert * sun_visibility(v_world));
    out_color = data_view() ? vec4(0.0, 0.0, 0.0, 1.0) : vec4(lit, 1.0);
}
