// Trilinear sampling of the wind (paper section 3.3: each blade samples the
// wind at its tip). Include after wind_grid.glsl with WIND_VELOCITY(i)
// defined to the float at index i of the velocity copy to sample.
#ifndef MEADOW_WIND_SAMPLE_GLSL
#define MEADOW_WIND_SAMPLE_GLSL
#ifndef WIND_VELOCITY
#error "define WIND_VELOCITY(i) before including wind_sample.glsl"
#endif

// The lattice of component `axis` around world position x, clamped: the
// lower and upper corners' sample coordinates and the fractions between.
void component_lattice(WindGridParams g, uint axis, vec3 x, out uvec3 i0, out uvec3 i1,
                       out vec3 f) {
    uvec3 d = face_dims(g, axis);
    vec3 offset = vec3(0.5);
    offset[axis] = 0.0;
    vec3 p = clamp((x - g.origin.xyz) / g.cell_size.xyz - offset, vec3(0.0), vec3(d - 1u));
    i0 = min(uvec3(floor(p)), d - 1u);
    i1 = min(i0 + 1u, d - 1u);
    f = p - vec3(i0);
}

#define MEADOW_AT(i, j, k) WIND_VELOCITY(base + (i) + d.x * ((j) + d.y * (k)))

// Trilinear sample of component `axis` at world position x, clamped to the
// component's sample lattice (paper: the grass samples the wind at its tip).
float sample_component(WindGridParams g, uint axis, vec3 x) {
    uvec3 i0, i1;
    vec3 f;
    component_lattice(g, axis, x, i0, i1, f);
    uvec3 d = face_dims(g, axis);
    uint base = component_offset(g, axis);
    float c00 = MEADOW_AT(i0.x, i0.y, i0.z) * (1.0 - f.x) + MEADOW_AT(i1.x, i0.y, i0.z) * f.x;
    float c10 = MEADOW_AT(i0.x, i1.y, i0.z) * (1.0 - f.x) + MEADOW_AT(i1.x, i1.y, i0.z) * f.x;
    float c01 = MEADOW_AT(i0.x, i0.y, i1.z) * (1.0 - f.x) + MEADOW_AT(i1.x, i0.y, i1.z) * f.x;
    float c11 = MEADOW_AT(i0.x, i1.y, i1.z) * (1.0 - f.x) + MEADOW_AT(i1.x, i1.y, i1.z) * f.x;
    float c0 = c00 * (1.0 - f.y) + c10 * f.y;
    float c1 = c01 * (1.0 - f.y) + c11 * f.y;
    return c0 * (1.0 - f.z) + c1 * f.z;
}

// The least (x) and greatest (y) of the eight samples `sample_component`
// interpolates at x (`WindField::sample_range`).
vec2 sample_range(WindGridParams g, uint axis, vec3 x) {
    uvec3 i0, i1;
    vec3 f;
    component_lattice(g, axis, x, i0, i1, f);
    uvec3 d = face_dims(g, axis);
    uint base = component_offset(g, axis);
    float lo = MEADOW_AT(i0.x, i0.y, i0.z);
    float hi = lo;
    for (uint n = 1u; n < 8u; ++n) {
        uvec3 i = uvec3((n & 1u) != 0u ? i1.x : i0.x, (n & 2u) != 0u ? i1.y : i0.y,
                        (n & 4u) != 0u ? i1.z : i0.z);
        float v = MEADOW_AT(i.x, i.y, i.z);
        lo = min(lo, v);
        hi = max(hi, v);
    }
    return vec2(lo, hi);
}
#undef MEADOW_AT

// The wind velocity at a world position.
vec3 sample_wind(WindGridParams g, vec3 x) {
    return vec3(sample_component(g, 0u, x), sample_component(g, 1u, x), sample_component(g, 2u, x));
}
#endif
