#version 450
#extension GL_GOOGLE_include_directive : require
// Fragment stage: two-sided lighting of the blade (the normal is flipped on
// back faces, and light passes through to the back a little), shadows from
// the sun's shadow map, the grass texture along the blade tinted per blade,
// and debug views.
#include "frame.glsl"
#include "shadow.glsl"
#include "surfaces.glsl"

layout(location = 0) in vec3 g_world;
layout(location = 1) in vec3 g_normal;
layout(location = 2) in vec2 g_uv;
layout(location = 3) flat in float g_blade_rand;
layout(location = 4) flat in float g_tess_level;
layout(location = 5) flat in float g_motion;

layout(location = 0) out vec4 out_color;

vec3 grass_albedo(vec2 uv, float r) {
    // The texture is the meadow's average blade (dark root, light tip,
    // midrib and veins); each blade is tinted by its random number r,
    // fresher green or yellower, more toward the tip, so a meadow is not
    // one flat colour.
    vec3 base = texture(sampler2D(grass_texture, surface_sampler), uv).rgb;
    vec3 tint = mix(vec3(0.70, 0.93, 0.70), vec3(1.35, 1.07, 1.30), r);
    return base * mix(vec3(1.0), tint, uv.y);
}

vec3 lod_color(float level) {
    if (level >= frame.tess_level.x) return vec3(0.85, 0.10, 0.08);   // close: red
    if (level >= frame.tess_level.y) return vec3(0.95, 0.75, 0.05);   // medium: yellow
    return vec3(0.10, 0.35, 0.90);                                   // far: blue
}

void main() {
    vec3 n = normalize(g_normal);
    if (!gl_FrontFacing) {
        n = -n;                                   // two-sided lighting
    }
    vec3 l = frame.light_dir.xyz;
    float ambient = frame.light_dir.w;
    float lambert = max(dot(n, l), 0.0);
    // Light through the blade: a thin leaf passes some of the light that hits
    // its other side.
    float translucent = 0.35 * max(dot(-n, l), 0.0);
    // Self-shadowing of the tuft: less light reaches the lower blade.
    float occlusion = mix(0.35, 1.0, g_uv.y);

    vec3 albedo;
    if (frame.view.x == VIEW_LOD) {
        albedo = lod_color(g_tess_level);
    } else if (frame.view.x == VIEW_MOTION) {
        albedo = mix(vec3(0.05, 0.15, 0.6), vec3(0.9, 0.1, 0.05), clamp(g_motion / 0.6, 0.0, 1.0));
    } else {
        albedo = grass_albedo(g_uv, g_blade_rand);
    }
    // The sun reaches both faces only where the shadow map says it is not
    // blocked (by this blade, its neighbours, or the tuft in front).
    float sun = sun_visibility(g_world);
    vec3 lit = albedo * (ambient + frame.light_color.rgb * (lambert + translucent) * sun) * occlusion;
    out_color = vec4(lit, 1.0);
}
