#version 450
#extension GL_GOOGLE_include_directive : require
// Fragment stage: two-sided lighting of the blade (the normal is flipped on
// back faces), shadows from the sun's shadow map, the grass texture along
// the blade coloured per blade and per clump, and debug views. The light
// is a leaf's (glsl/common/leaf_optics.glsl): diffuse reflection on the lit
// side, diffuse transmission through to the other, and the cuticle's
// sheen, all on the normal of the deformed curve (bend, swing and twist
// turn it), so a bending blade turns its sheen toward or away from the eye.
// The canopy above a point shades it (glsl/common/canopy.glsl); far over
// the clear ground the haze veils it as it does the ground
// (glsl/common/haze.glsl).
#include "frame.glsl"
#include "hash.glsl"
#include "shadow.glsl"
#include "surfaces.glsl"
#include "canopy.glsl"
#include "leaf_optics.glsl"
#include "grass_color.glsl"
#include "sky.glsl"
#include "haze.glsl"

layout(location = 0) in vec3 g_world;
layout(location = 1) in vec3 g_normal;
layout(location = 2) in vec2 g_uv;
layout(location = 4) flat in float g_tess_level;
layout(location = 5) flat in float g_motion;
layout(location = 6) flat in vec2 g_root;    // the blade's root (x, z)
layout(location = 7) in vec3 g_side;
layout(location = 8) in vec2 g_extinction;  // the canopy's per unit of leaf area index (sun, sky)
layout(location = 9) in vec3 g_sky;         // the sky the cuticle mirrors toward the eye
// The blade's colour (grass_color.glsl's blade_tint).
layout(location = 10) flat in vec3 g_tint;
layout(location = 11) flat in float g_tip_len;
layout(location = 12) flat in float g_dry;

layout(location = 0) out vec4 out_color;

vec3 lod_color(float level) {
    if (level >= frame.tess_level.x) return vec3(0.85, 0.10, 0.08);   // close: red
    if (level >= frame.tess_level.y) return vec3(0.95, 0.75, 0.05);   // medium: yellow
    return vec3(0.10, 0.35, 0.90);                                   // far: blue
}

void main() {
    if (data_view()) {
        // Data, not a picture: the displacement and the blade's coverage.
        out_color = vec4(clamp(g_motion / DISPLACEMENT_FULL_SCALE, 0.0, 1.0), 0.0, 1.0, 1.0);
        return;
    }
    vec3 n = normalize(g_normal);
    if (!gl_FrontFacing) {
        n = -n;                                   // two-sided lighting
    }
    vec3 l = frame.light_dir;
    float ambient = frame.ambient;
    vec3 to_eye = frame.camera_pos - g_world;
    float eye_distance = length(to_eye);
    vec3 v = to_eye / max(eye_distance, 1e-6);

    vec3 albedo;
    if (frame.view == VIEW_LOD) {
        albedo = lod_color(g_tess_level);
    } else if (frame.view == VIEW_MOTION) {
        albedo = mix(vec3(0.05, 0.15, 0.6), vec3(0.9, 0.1, 0.05), clamp(g_motion / 0.6, 0.0, 1.0));
    } else {
        vec3 base = texture(sampler2D(grass_texture, surface_sampler), g_uv).rgb;
        albedo = grass_albedo(base, g_uv, g_tint, g_tip_len, g_dry);
    }
    // The shadow map's 9 taps, once: lavapipe runs both sides of a branch.
    float shadow = sun_visibility(g_world);
    // The debug views keep the plain two-sided Lambert light they always
    // had, so their colours read as their keys say.
    if (frame.view != VIEW_SHADED) {
        float lambert = max(dot(n, l), 0.0) + 0.35 * max(dot(-n, l), 0.0);
        float occlusion = mix(0.35, 1.0, g_uv.y);
        out_color = vec4(albedo * (ambient + frame.light_color * lambert * shadow) * occlusion, 1.0);
        return;
    }

    // The surface's normal, rounded across the blade; facing the eye.
    vec3 ns = rounded_normal(n, g_side, 2.0 * g_uv.x - 1.0);
    // Far blades are thinner than a pixel: the sheen is spread over the
    // normals a pixel sees (a rougher surface), so it does not sparkle.
    float pixel_angle = length(fwidth(ns));
    float alpha = sqrt(CUTICLE_ALPHA * CUTICLE_ALPHA + min(pixel_angle * pixel_angle, 0.5));

    // The canopy above this point (its extinction worked out along the
    // blade by the geometry stage) under the leaf area index here.
    vec2 reach = exp(-blade_leaf_area_index(g_root) * g_extinction);
    float sun = shadow * reach.x;

    float n_l = dot(ns, l);
    float n_v = max(dot(ns, v), 1e-4);
    vec3 light = frame.light_color;
    // Diffuse: reflected on the lit side, transmitted (greener, yellower)
    // when the sun is behind the blade.
    vec3 diffuse = albedo * max(n_l, 0.0)
                 + albedo * LEAF_T_TINT * (LEAF_T_OVER_R * frame.translucency) * max(-n_l, 0.0);
    // The sky's light: from above, less from below the blade's horizon.
    float sky_seen = 0.75 + 0.25 * ns.y;
    vec3 color = albedo * ambient * sky_seen * reach.y + light * diffuse * sun;
    // The sheen: the sun's highlight and the sky's reflection, white
    // (off the cuticle, before the leaf's pigments).
    float sheen = frame.sheen;
    color += sheen * light * cuticle_sheen(ns, v, l, alpha) * sun;
    // (The sky it mirrors, smooth over the blade, is the geometry stage's.)
    color += sheen * cuticle_sky_albedo(n_v, alpha) * g_sky * reach.y;
    // Far over the clear ground, the haze the ground fades into.
    out_color = vec4(hazed(color, g_world), 1.0);
}
