#version 450
#extension GL_GOOGLE_include_directive : require
// Ground: the soil texture, tiled, with a slow brightness variation over
// it so the tiling does not show, lit by the sun and darkened where the
// grass shadows it.
#include "frame.glsl"
#include "shadow.glsl"
#include "surfaces.glsl"

layout(location = 0) in vec3 v_world;
layout(location = 0) out vec4 out_color;

float hash(vec2 p) {
    return fract(sin(dot(p, vec2(127.1, 311.7))) * 43758.5453);
}

float value_noise(vec2 p) {
    vec2 i = floor(p), f = fract(p);
    vec2 u = f * f * (3.0 - 2.0 * f);
    return mix(mix(hash(i), hash(i + vec2(1, 0)), u.x),
               mix(hash(i + vec2(0, 1)), hash(i + vec2(1, 1)), u.x), u.y);
}

void main() {
    vec3 soil = texture(sampler2D(ground_texture, surface_sampler), v_world.xz / GROUND_TILE_M).rgb;
    vec3 albedo = soil * mix(0.85, 1.1, value_noise(v_world.xz * 0.37));
    float lambert = max(frame.light_dir.y, 0.0);
    vec3 lit = albedo * (frame.light_dir.w + frame.light_color.rgb * lambert * sun_visibility(v_world));
    out_color = vec4(lit, 1.0);
}
