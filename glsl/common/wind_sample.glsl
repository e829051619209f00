// Trilinear sampling of the wind (paper section 3.3: each blade samples the
// wind at its tip). Include after wind_grid.glsl with WIND_VELOCITY(i)
// defined to the float at index i of the velocity copy to sample.
#ifndef MEADOW_WIND_SAMPLE_GLSL
#define MEADOW_WIND_SAMPLE_GLSL
#ifndef WIND_VELOCITY
#error "define WIND_VELOCITY(i) before including wind_sample.glsl"
#endif

// The eight samples of component `axis` around a point, clamped to its
// lattice: the lower and upper corners' sample coordinates, the fractions
// between them, and where the component starts and its lattice's size.
struct ComponentLattice {
    uvec3 i0;
    uvec3 i1;
    vec3 f;
    uint base;
    uvec3 d;
};

ComponentLattice component_lattice(WindGridParams g, uint axis, vec3 x) {
    ComponentLattice l;
    l.d = face_dims(g, axis);
    vec3 offset = vec3(0.5);
    offset[axis] = 0.0;
    vec3 p = clamp((x - g.origin.xyz) / g.cell_size.xyz - offset, vec3(0.0), vec3(l.d - 1u));
    l.i0 = min(uvec3(floor(p)), l.d - 1u);
    l.i1 = min(l.i0 + 1u, l.d - 1u);
    l.f = p - vec3(l.i0);
    l.base = component_offset(g, axis);
    return l;
}

// The sample at lattice point (i, j, k) of `l`.
float lattice_sample(ComponentLattice l, uint i, uint j, uint k) {
    return WIND_VELOCITY(l.base + i + l.d.x * (j + l.d.y * k));
}

// Trilinear sample of component `axis` at world position x, clamped to the
// component's sample lattice (paper: the grass samples the wind at its tip).
float sample_component(WindGridParams g, uint axis, vec3 x) {
    ComponentLattice l = component_lattice(g, axis, x);
    uvec3 i0 = l.i0, i1 = l.i1;
    vec3 f = l.f;
    float c00 = lattice_sample(l, i0.x, i0.y, i0.z) * (1.0 - f.x) + lattice_sample(l, i1.x, i0.y, i0.z) * f.x;
    float c10 = lattice_sample(l, i0.x, i1.y, i0.z) * (1.0 - f.x) + lattice_sample(l, i1.x, i1.y, i0.z) * f.x;
    float c01 = lattice_sample(l, i0.x, i0.y, i1.z) * (1.0 - f.x) + lattice_sample(l, i1.x, i0.y, i1.z) * f.x;
    float c11 = lattice_sample(l, i0.x, i1.y, i1.z) * (1.0 - f.x) + lattice_sample(l, i1.x, i1.y, i1.z) * f.x;
    float c0 = c00 * (1.0 - f.y) + c10 * f.y;
    float c1 = c01 * (1.0 - f.y) + c11 * f.y;
    return c0 * (1.0 - f.z) + c1 * f.z;
}

// The least (x) and greatest (y) of the eight samples `sample_component`
// interpolates at x, save that along an axis where the point lies within
// WIND_RANGE_SNAP of a lattice plane only that plane's samples count (the
// eight samples are not continuous there; `WindField::sample_range`).
vec2 sample_range(WindGridParams g, uint axis, vec3 x) {
    ComponentLattice l = component_lattice(g, axis, x);
    vec3 p = vec3(l.i0) + l.f;
    bvec3 on = lessThan(abs(p - round(p)), vec3(WIND_RANGE_SNAP));
    l.i0 = min(uvec3(mix(floor(p), round(p), on)), l.d - 1u);
    l.i1 = mix(min(l.i0 + 1u, l.d - 1u), l.i0, on);
    vec2 range = vec2(lattice_sample(l, l.i0.x, l.i0.y, l.i0.z));
    for (uint n = 1u; n < 8u; ++n) {
        uvec3 i = mix(l.i0, l.i1, bvec3((n & 1u) != 0u, (n & 2u) != 0u, (n & 4u) != 0u));
        float v = lattice_sample(l, i.x, i.y, i.z);
        range = vec2(min(range.x, v), max(range.y, v));
    }
    return range;
}

// The wind velocity at a world position.
vec3 sample_wind(WindGridParams g, vec3 x) {
    return vec3(sample_component(g, 0u, x), sample_component(g, 1u, x), sample_component(g, 2u, x));
}
#endif
