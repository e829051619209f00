#version 450
#extension GL_GOOGLE_include_directive : require
// Ground: the plane y = 0 out to the horizon. Each pixel's view ray meets
// it (or the pixel is sky and is discarded); the depth is that point's. The
// soil texture, tiled, with a slow brightness variation so the tiling does
// not show, lit by the sun and darkened where the grass shadows it; beyond
// frame.ground.z metres from the grass it fades into the sky's horizon
// colour, so the ground meets the sky without a band.
#include "frame.glsl"
#include "shadow.glsl"
#include "sky.glsl"
#include "surfaces.glsl"

layout(location = 0) in vec2 v_ndc;
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
    vec4 far_point = frame.inv_view_proj * vec4(v_ndc, 1.0, 1.0);
    vec3 eye = frame.camera_pos.xyz;
    vec3 dir = far_point.xyz / far_point.w - eye;
    // Above the horizon (or a camera under the ground): sky.
    if (dir.y >= 0.0 || eye.y <= 0.0) {
        discard;
    }
    vec3 world = eye + dir * (-eye.y / dir.y);
    vec4 clip = frame.view_proj * vec4(world, 1.0);
    // Beyond the far plane the ground still covers the sky, at the back.
    gl_FragDepth = min(clip.z / clip.w, 0.9999999);

    vec3 soil = texture(sampler2D(ground_texture, surface_sampler), world.xz / GROUND_TILE_M).rgb;
    vec3 albedo = soil * mix(0.85, 1.1, value_noise(world.xz * 0.37));
    float lambert = max(frame.light_dir.y, 0.0);
    vec3 lit = albedo * (frame.light_dir.w + frame.light_color.rgb * lambert * sun_visibility(world));
    float clear = frame.ground.z;
    float beyond = max(distance(world.xz, frame.ground.xy) - clear, 0.0);
    float haze = 1.0 - exp(-beyond / (0.25 * clear + 10.0));
    out_color = vec4(mix(lit, SKY_HORIZON, haze), 1.0);
}
