// The turbulence's Fourier modes summed at a point (`component_at` and
// `velocity_at` in src/model/turbulence.rs): the wind's turbulence kernel
// sums the grid's at each face, the grass step the modes finer than the
// grid at each blade's tip. x is in metres from the grid's minimum corner.
// TurbulenceMode: src/interface/defs.rs.
#ifndef MEADOW_TURBULENCE_GLSL
#define MEADOW_TURBULENCE_GLSL

#include "interface.glsl"

// Component `axis` of mode m at x, the modes mirrored across the axes
// in `mirrored` (each mode's own, or a constant a kernel is specialised
// to): the phase along the axes not mirrored, times per mirrored axis sin
// (the component across it) or cos; the component across a mirrored axis
// takes -sin of the phase.
float turbulence_component_mirrored(TurbulenceMode m, uint mirrored, uint axis, vec3 x) {
    vec3 k = m.wavenumber;
    float theta = m.phase;
    for (uint a = 0u; a < 3u; ++a) {
        if ((mirrored & (1u << a)) == 0u) {
            theta += k[a] * x[a];
        }
    }
    float value = (mirrored & (1u << axis)) != 0u ? -sin(theta) : cos(theta);
    for (uint a = 0u; a < 3u; ++a) {
        if ((mirrored & (1u << a)) != 0u) {
            value *= a == axis ? sin(k[a] * x[a]) : cos(k[a] * x[a]);
        }
    }
    return m.amplitude[axis] * value;
}

float turbulence_component(TurbulenceMode m, uint axis, vec3 x) {
    return turbulence_component_mirrored(m, m.mirrored, axis, x);
}

// All three components of mode m at x.
vec3 turbulence_velocity(TurbulenceMode m, vec3 x) {
    return vec3(turbulence_component(m, 0u, x), turbulence_component(m, 1u, x),
                turbulence_component(m, 2u, x));
}
#endif
