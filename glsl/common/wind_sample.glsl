// Trilinear sampling of the wind (paper section 3.3: each blade samples the
// wind at its tip). Include after wind_grid.glsl with WIND_VELOCITY(i)
// defined to the float at index i of the velocity copy to sample.
#ifndef MEADOW_WIND_SAMPLE_GLSL
#define MEADOW_WIND_SAMPLE_GLSL
#ifndef WIND_VELOCITY
#error "define WIND_VELOCITY(i) before including wind_sample.glsl"
#endif

// Trilinear sample of component `axis` at world position x, clamped to the
// component's sample lattice (paper: the grass samples the wind at its tip).
float sample_component(WindGridParams g, uint axis, vec3 x) {
    uvec3 d = face_dims(g, axis);
    vec3 offset = vec3(0.5);
    offset[axis] = 0.0;
    vec3 p = clamp((x - g.origin.xyz) / g.cell_size.xyz - offset, vec3(0.0), vec3(d - 1u));
    uvec3 i0 = min(uvec3(floor(p)), d - 1u);
    uvec3 i1 = min(i0 + 1u, d - 1u);
    vec3 f = p - vec3(i0);
    uint base = component_offset(g, axis);
    #define AT(i, j, k) WIND_VELOCITY(base + (i) + d.x * ((j) + d.y * (k)))
    float c00 = AT(i0.x, i0.y, i0.z) * (1.0 - f.x) + AT(i1.x, i0.y, i0.z) * f.x;
    float c10 = AT(i0.x, i1.y, i0.z) * (1.0 - f.x) + AT(i1.x, i1.y, i0.z) * f.x;
    float c01 = AT(i0.x, i0.y, i1.z) * (1.0 - f.x) + AT(i1.x, i0.y, i1.z) * f.x;
    float c11 = AT(i0.x, i1.y, i1.z) * (1.0 - f.x) + AT(i1.x, i1.y, i1.z) * f.x;
    #undef AT
    float c0 = c00 * (1.0 - f.y) + c10 * f.y;
    float c1 = c01 * (1.0 - f.y) + c11 * f.y;
    return c0 * (1.0 - f.z) + c1 * f.z;
}

// The wind velocity at a world position.
vec3 sample_wind(WindGridParams g, vec3 x) {
    return vec3(sample_component(g, 0u, x), sample_component(g, 1u, x), sample_component(g, 2u, x));
}
#endif
