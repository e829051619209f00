// The ground's soil, as the backdrop's plane (glsl/backdrop/ground.frag)
// and the terrain mesh (glsl/terrain/terrain.frag) shade it: the soil
// texture, tiled, with a slow brightness variation so the tiling does not
// show, lit by the sun (`lambert`: the cosine to it) and darkened where the
// shadow map says the sun is hidden; beyond frame.ground_clear metres from
// the grass it fades into the sky's horizon colour (glsl/common/haze.glsl),
// so the ground meets the sky without a band. Where grass
// grows (glsl/common/canopy.glsl) the ground is the sward's floor, not
// bare soil. Needs frame.glsl, shadow.glsl, sky.glsl, surfaces.glsl and
// canopy.glsl included first.
#ifndef MEADOW_SOIL_GLSL
#define MEADOW_SOIL_GLSL

#include "haze.glsl"

float hash(vec2 p) {
    return fract(sin(dot(p, vec2(127.1, 311.7))) * 43758.5453);
}

float value_noise(vec2 p) {
    vec2 i = floor(p), f = fract(p);
    vec2 u = f * f * (3.0 - 2.0 * f);
    return mix(mix(hash(i), hash(i + vec2(1, 0)), u.x),
               mix(hash(i + vec2(0, 1)), hash(i + vec2(1, 1)), u.x), u.y);
}

// The floor of a sward (linear): dead leaves over low green growth and
// moss, greener than soil.
const vec3 LITTER = vec3(0.075, 0.095, 0.030);
// Leaf area index at which litter covers 63% of the soil: wherever grass
// grows it covers all of it but where a mask thins the grass to nothing.
const float LITTER_LAI = 0.08;

vec3 soil_lit(vec3 world, float lambert) {
    vec3 soil = texture(sampler2D(ground_texture, surface_sampler), world.xz / GROUND_TILE_M).rgb;
    float grain = mix(0.85, 1.1, value_noise(world.xz * 0.37));
    // Under grass the ground is the sward's floor, in the canopy's shade
    // (glsl/common/canopy.glsl); the soil's texture still varies it.
    vec2 lai = leaf_area_index(world.xz);
    float covered = 1.0 - exp(-lai.x / LITTER_LAI);
    float soil_shade = dot(soil, vec3(0.2126, 0.7152, 0.0722)) / 0.09;
    vec3 floor_albedo = LITTER * mix(0.8, 1.2, clamp(soil_shade, 0.0, 1.0));
    vec3 albedo = mix(soil, floor_albedo, covered) * grain;
    // Leaves at random angles above the floor (cos 60 degrees: the mean
    // inclination of a spherical distribution).
    vec2 reach = exp(-lai.y * canopy_extinction(0.0, 0.5, max(frame.light_dir.y, 0.0)));
    vec3 lit = albedo * (frame.ambient * reach.y + frame.light_color * lambert * sun_visibility(world) * reach.x);
    return hazed(lit, world);
}

#endif
