// Light in the canopy (ours; docs/method.md, "Light in the canopy"): a
// meadow is a turbid medium of leaves, and the light reaching a point in
// it falls with the leaf area above it by Beer-Lambert's law (Monsi and
// Saeki 1953). The leaf area index (LAI: one side's leaf area over ground
// area) comes from the canopy map (src/render/canopy_map.rs: the meadows'
// and bunches' density, masks included) plus the cover's, where it grows.
// How light crosses it is glsl/common/canopy_light.glsl. Needs frame.glsl
// and surfaces.glsl included first.
#ifndef MEADOW_CANOPY_GLSL
#define MEADOW_CANOPY_GLSL

#include "canopy_light.glsl"

layout(set = 0, binding = 6) uniform texture2D canopy_texture;

// The cover's leaf area index at (x, z): frame.cover_lai where it grows.
float cover_leaf_area_index(vec2 xz) {
    bool inside = all(greaterThanEqual(xz, frame.cover_min)) && all(lessThan(xz, frame.cover_max));
    return inside ? frame.cover_lai : 0.0;
}

// The leaf area index at (x, z), the map's (meadows, bunches) plus the
// cover's where it grows: x, where the grass grows (the floor's cover); y,
// spread over the canopy's height, the leaf area the light crosses to
// reach a point there (src/render/canopy_map.rs says why).
vec2 leaf_area_index(vec2 xz) {
    vec2 lai = vec2(0.0);
    vec2 uv = (xz - frame.canopy_map_min) * frame.canopy_map_inverse_extent;
    if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)))) {
        // The map's border texels are empty, so the repeating sampler
        // brings nothing in from the other side.
        lai = textureLod(sampler2D(canopy_texture, surface_sampler), uv, 0.0).rg * frame.canopy_map_lai;
    }
    return lai + vec2(cover_leaf_area_index(xz));
}

// The leaf area index spread over the canopy's height (leaf_area_index's
// y) at a blade's root (x, z): the nearest texel, unfiltered. A blade
// reads one value all along itself, and a fetch costs far less than a
// filtered sample on lavapipe, which samples in software.
float blade_leaf_area_index(vec2 root) {
    float lai = 0.0;
    vec2 uv = (root - frame.canopy_map_min) * frame.canopy_map_inverse_extent;
    if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThan(uv, vec2(1.0)))) {
        ivec2 texel = ivec2(uv * vec2(textureSize(sampler2D(canopy_texture, surface_sampler), 0)));
        lai = texelFetch(sampler2D(canopy_texture, surface_sampler), texel, 0).g * frame.canopy_map_lai;
    }
    return lai + cover_leaf_area_index(root);
}

#endif
