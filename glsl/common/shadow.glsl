// The sun's shadow map (paper section 5: an 8192 x 8192 depth map from the
// light, drawn through the same tessellation and geometry stages as the
// blades themselves), sampled with percentage-closer filtering.
#ifndef MEADOW_SHADOW_GLSL
#define MEADOW_SHADOW_GLSL

#include "frame.glsl"

// Depth comparison in the sampler (compareOp LESS_OR_EQUAL): each tap
// returns the bilinearly filtered fraction of texels not nearer the sun
// than the reference depth. Image and sampler are bound apart (not as a
// combined sampler2DShadow): naga's SPIR-V reader, which the reflection
// tests use, does not take combined image samplers.
layout(set = 0, binding = 1) uniform texture2D shadow_map;
layout(set = 0, binding = 2) uniform samplerShadow shadow_sampler;

float shadow_tap(vec2 uv, float reference) {
    return texture(sampler2DShadow(shadow_map, shadow_sampler), vec3(uv, reference));
}

// How much sunlight reaches `world`: 1 lit, 0 in shadow. Outside the
// map's footprint everything is lit.
float sun_visibility(vec3 world) {
    if (frame.shadow_on == 0.0) {
        return 1.0;
    }
    vec4 clip = frame.light_view_proj * vec4(world, 1.0);
    vec3 ndc = clip.xyz / clip.w;
    vec2 uv = ndc.xy * 0.5 + 0.5;
    if (any(lessThan(uv, vec2(0.0))) || any(greaterThan(uv, vec2(1.0))) || ndc.z >= 1.0) {
        return 1.0;
    }
    float reference = ndc.z - frame.shadow_bias;
    vec2 step_uv = vec2(frame.shadow_texel * frame.shadow_pcf_radius);
    // 3 x 3 bilinear PCF taps: a soft edge some 4 texels wide.
    float lit = shadow_tap(uv, reference)
              + shadow_tap(uv + vec2(-1.0, -1.0) * step_uv, reference)
              + shadow_tap(uv + vec2( 0.0, -1.0) * step_uv, reference)
              + shadow_tap(uv + vec2( 1.0, -1.0) * step_uv, reference)
              + shadow_tap(uv + vec2(-1.0,  0.0) * step_uv, reference)
              + shadow_tap(uv + vec2( 1.0,  0.0) * step_uv, reference)
              + shadow_tap(uv + vec2(-1.0,  1.0) * step_uv, reference)
              + shadow_tap(uv + vec2( 0.0,  1.0) * step_uv, reference)
              + shadow_tap(uv + vec2( 1.0,  1.0) * step_uv, reference);
    return lit / 9.0;
}

#endif
