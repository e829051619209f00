// How light crosses the canopy (ours; docs/method.md, "Light in the
// canopy"): Beer-Lambert's law through the leaf area above a point, with
// Ross's G for the leaves' inclination. No bindings: the blade's geometry
// stage, which the depth-only shadow pass shares, works the extinction
// out at the blade's vertices; glsl/common/canopy.glsl adds the canopy
// map. Needs frame.glsl included first.
#ifndef MEADOW_CANOPY_LIGHT_GLSL
#define MEADOW_CANOPY_LIGHT_GLSL

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

// The canopy's extinction per unit of leaf area index at a point
// `height` (m) over the ground, its leaves' normals at `leaf_cos` (cosine)
// from the vertical, the sun at `sun_sin` (sine of its elevation): under
// a leaf area index L, exp(-L x this) is the share of the sun's direct
// light (x) and of the sky's (y) that reaches it; 0 with self-shadowing
// off. The leaf area above it is L's share above its height in a canopy
// whose top is frame.canopy_top: spread over the height as a tapering
// blade's, (1 - z)^1.5. The sky's extinction hardly depends on the
// leaves' angle (G is about 0.5 for every distribution at 57 degrees from
// the zenith, the sky's mean). Smooth along a blade: the blade's stages
// work it out at its vertices.
vec2 canopy_extinction(float height, float leaf_cos, float sun_sin) {
    float z = clamp(height / max(frame.canopy_top, 1e-3), 0.0, 1.0);
    float share = (1.0 - z) * sqrt(1.0 - z);
    float scatter = sqrt(1.0 - CANOPY_SCATTERING);
    float sun_cos = max(sun_sin, 0.1);
    // Self-shadowing off is a factor, not an early return: with a return
    // here the geometry stage made lavapipe (Mesa 22.3) keep about 750 KiB
    // of host memory a frame (tests/host_memory.rs found it; docs/perf.md).
    float on = frame.self_shadowing == 0.0 ? 0.0 : 1.0;
    return on * share * scatter * vec2(leaf_projection(sun_cos, leaf_cos) / sun_cos, CANOPY_K_DIFFUSE);
}

#endif
