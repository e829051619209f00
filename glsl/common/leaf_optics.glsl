// How a grass leaf reflects and transmits light (ours; docs/method.md,
// "A blade's light", says where each figure comes from). A leaf is a thin
// slab: its cells scatter light diffusely, back toward the lit side
// (reflectance R) and through to the other (transmittance T, about as
// much as R in the green: Woolley 1971; Jacquemoud and Ustin 2019), and
// its waxy cuticle reflects a white specular sheen off its surface by
// Fresnel's law, blurred by the surface's roughness (Grant 1987;
// Bousquet et al. 2005, who fit it with a microfacet model). The sheen is
// what a bending blade turns toward or away from the eye: the waves of
// light over a meadow in gusts.
#ifndef MEADOW_LEAF_OPTICS_GLSL
#define MEADOW_LEAF_OPTICS_GLSL

const float LEAF_PI = 3.14159265;
// The cuticle's refractive index (epicuticular wax, about 1.5): the
// sheen's reflectance at normal incidence ((n - 1) / (n + 1))^2.
const float CUTICLE_F0 = 0.04;
// GGX roughness (alpha) of the blade's surface: within Bousquet et al.'s
// fitted range (0.1-0.5) for smooth leaves.
const float CUTICLE_ALPHA = 0.28;
// Transmittance over reflectance of the diffuse light and the colour the
// leaf's interior leaves it: the light through a leaf is greener and
// yellower than the light off it (chlorophyll absorbs twice over).
const float LEAF_T_OVER_R = 0.85;
const vec3 LEAF_T_TINT = vec3(1.05, 1.0, 0.45);

// How far the normal turns across the blade, edge to edge (a leaf is
// folded along its midrib and curls at its edges, not flat): the sheen
// runs along the blade as a band rather than lighting it all at once.
const float BLADE_ROUNDING = 0.55;

// The normal of the blade's surface at `at` across it (-1 one edge, 0 the
// midrib, 1 the other): the flat blade's `n` turned toward its width
// direction `across`.
vec3 rounded_normal(vec3 n, vec3 across, float at) {
    vec3 side = normalize(across - n * dot(across, n));
    return normalize(n + side * (at * BLADE_ROUNDING));
}

// Schlick's Fresnel for the cuticle.
float cuticle_fresnel(float cos_theta) {
    float m = clamp(1.0 - cos_theta, 0.0, 1.0);
    float m2 = m * m;
    return CUTICLE_F0 + (1.0 - CUTICLE_F0) * m2 * m2 * m;
}

// GGX's distribution of microfacet normals (Walter et al. 2007).
float ggx_d(float n_h, float alpha) {
    float a2 = alpha * alpha;
    float d = n_h * n_h * (a2 - 1.0) + 1.0;
    return a2 / (LEAF_PI * d * d);
}

// Smith's height-correlated masking and shadowing over 4 n.l n.v
// (Heitz 2014).
float smith_v(float n_l, float n_v, float alpha) {
    float a2 = alpha * alpha;
    float gv = n_l * sqrt(n_v * n_v * (1.0 - a2) + a2);
    float gl = n_v * sqrt(n_l * n_l * (1.0 - a2) + a2);
    return 0.5 / max(gv + gl, 1e-5);
}

// The sheen's share of the sun's light toward the eye, per unit of the
// light's irradiance on a surface facing it (times pi: the frame's light
// colour is the irradiance that gives a white Lambertian surface its own
// colour), for a surface of normal n seen along v (toward the eye) lit
// from l (toward the sun).
float cuticle_sheen(vec3 n, vec3 v, vec3 l, float alpha) {
    float n_l = dot(n, l);
    float n_v = dot(n, v);
    if (n_l <= 0.0 || n_v <= 0.0) {
        return 0.0;
    }
    vec3 h = normalize(l + v);
    return LEAF_PI * ggx_d(max(dot(n, h), 0.0), alpha) * smith_v(n_l, n_v, alpha)
        * cuticle_fresnel(max(dot(v, h), 0.0)) * n_l;
}

// The share of the sky's light the sheen reflects toward the eye: the
// directional albedo of the rough cuticle (Karis' fit of the split sum,
// 2014), seen at n.v.
float cuticle_sky_albedo(float n_v, float alpha) {
    vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022);
    vec4 c1 = vec4(1.0, 0.0425, 1.04, -0.04);
    vec4 r = sqrt(alpha) * c0 + c1;
    float a004 = min(r.x * r.x, exp2(-9.28 * max(n_v, 0.0))) * r.x + r.y;
    vec2 ab = vec2(-1.04, 1.04) * a004 + r.zw;
    return CUTICLE_F0 * ab.x + ab.y;
}

#endif
