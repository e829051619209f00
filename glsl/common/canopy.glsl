// Light in the canopy (ours; docs/method.md, "Light in the canopy"): a
// meadow is a turbid medium of leaves, and the light reaching a point in
// it falls with the leaf area above it by Beer-Lambert's law (Monsi and
// Saeki 1953). The leaf area index (LAI: one side's leaf area over ground
// area) comes from the canopy map (src/render/canopy_map.rs: the meadows'
// and bunches' density, masks included) plus the cover's, where it grows.
// Needs frame.glsl and surfaces.glsl included first.
#ifndef MEADOW_CANOPY_GLSL
#define MEADOW_CANOPY_GLSL

layout(set = 0, binding = 6) uniform texture2D canopy_texture;

const float LEAF_PI_CANOPY = 3.14159265;

// Ross's G function: the mean projection of leaves inclined at theta_l
// (the angle of their normals from the vertical), at every azimuth,
// toward a direction at theta from the zenith; given their cosines. 1 for
// flat leaves under a sun overhead, (2/pi) sin(theta) for upright ones
// (Ross 1981; e.g. Campbell and Norman 1998, ch. 15). A canopy bent over
// by the wind has flatter leaves, which take more of a high sun near the
// top and leave less for below.
float leaf_projection(float cos_theta, float cos_theta_l) {
    float c = clamp(cos_theta, 0.0, 1.0), cl = clamp(cos_theta_l, 0.0, 1.0);
    float s = sqrt(1.0 - c * c), sl = sqrt(1.0 - cl * cl);
    // cot(theta) cot(theta_l): beyond 1 no leaf faces away.
    float k = c * cl / max(s * sl, 1e-6);
    if (k >= 1.0) {
        return c * cl;
    }
    float phi = acos(k);
    return c * cl * (1.0 - 2.0 * phi / LEAF_PI_CANOPY) + (2.0 / LEAF_PI_CANOPY) * s * sl * sqrt(1.0 - k * k);
}
// Extinction of the sky's diffuse light per unit LAI (about 0.8 for
// random leaves over the hemisphere; Campbell and Norman 1998, ch. 15).
const float CANOPY_K_DIFFUSE = 0.8;
// Leaves scatter a share of the green light they intercept (reflectance
// plus transmittance, about 0.3: docs/method.md), which lights the canopy
// from within: extinction times sqrt(1 - scattering) (Goudriaan 1977).
const float CANOPY_SCATTERING = 0.3;

// The leaf area index at (x, z), the map's (meadows, bunches) plus the
// cover's where it grows: x, where the grass grows (the floor's cover); y,
// spread over the canopy's height, the leaf area the light crosses to
// reach a point there (src/render/canopy_map.rs says why).
vec2 leaf_area_index(vec2 xz) {
    vec2 lai = vec2(0.0);
    vec2 uv = (xz - frame.canopy_map.xy) * frame.canopy_map.zw;
    if (all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)))) {
        // The map's border texels are empty, so the repeating sampler
        // brings nothing in from the other side.
        lai = textureLod(sampler2D(canopy_texture, surface_sampler), uv, 0.0).rg * frame.canopy.w;
    }
    if (all(greaterThanEqual(xz, frame.cover_bounds.xy)) && all(lessThan(xz, frame.cover_bounds.zw))) {
        lai += vec2(frame.canopy.x);
    }
    return lai;
}

// The leaf area above a point at `height` (m) over the ground in a canopy
// of `lai` whose top is frame.canopy.y: leaf area spread over the height
// as a tapering blade's (its share above z of its height: (1 - z)^1.5).
float leaf_area_above(float lai, float height) {
    float z = clamp(height / max(frame.canopy.y, 1e-3), 0.0, 1.0);
    return lai * pow(1.0 - z, 1.5);
}

// The share of the sun's direct light that reaches a point under `above`
// of leaf area whose leaves' normals are at `leaf_cos` (cosine) from the
// vertical, the sun at `sun_sin` (sine of its elevation), and of the sky's
// light; both 1 with self-shadowing off. The sky's extinction hardly
// depends on the leaves' angle (G is about 0.5 for every distribution at
// 57 degrees from the zenith, the sky's mean).
vec2 canopy_transmission(float above, float leaf_cos, float sun_sin) {
    if (frame.canopy.z == 0.0) {
        return vec2(1.0);
    }
    float scatter = sqrt(1.0 - CANOPY_SCATTERING);
    float sun_cos = max(sun_sin, 0.1);
    float g = leaf_projection(sun_cos, leaf_cos);
    float sun = exp(-g * scatter * above / sun_cos);
    float sky = exp(-CANOPY_K_DIFFUSE * scatter * above);
    return vec2(sun, sky);
}

#endif
