// Which blades each pass draws: the tests of the cull pass (glsl/cull/),
// mirrored on the CPU by src/render/visibility.rs. Every test is
// conservative: a blade is left out only when nothing it can put on screen
// (or cast onto what is on screen) survives.
#ifndef MEADOW_CULL_GLSL
#define MEADOW_CULL_GLSL

#include "frame.glsl"
#include "thinning.glsl"

// Flags of one blade.
#define CULL_IN_VIEW 1u   // drawn by the colour pass
#define CULL_CASTER  2u   // drawn by the shadow pass
#define CULL_KEPT    4u   // not thinned out by distance
#define CULL_FACING  8u   // kept, and not seen edge-on from the camera
#define CULL_OCCLUDED 16u // in view but hidden in the previous frame's depth (not drawn)
#define CULL_SHADOW_OCCLUDED 32u // would cast, but where its shadow can fall the
                                 // previous frame's depth hides (not drawn)

// CULL_GROUP, the workgroup of the flag and compaction kernels, and
// BladeVertex.
#include "interface.glsl"

// The box around everything the geometry stage can emit for a blade: the
// Bezier curve (eq. 1) and its interpolated width vector lie in the hull
// of the control points and width vectors, and the taper only narrows.
// `width_scale` is the distance thinning's (glsl/common/thinning.glsl).
void blade_bounds(BladeVertex v[4], float width_scale, out vec3 lo, out vec3 hi) {
    lo = vec3(3.0e38);
    hi = vec3(-3.0e38);
    for (int i = 0; i < 4; ++i) {
        vec3 w = abs(v[i].half_width) * width_scale;
        lo = min(lo, v[i].position - w);
        hi = max(hi, v[i].position + w);
    }
}

// Whether the box lies wholly on the negative side of one clip plane: its
// corner farthest along the plane's normal is behind it.
bool outside(vec4 plane, vec3 lo, vec3 hi) {
    vec3 far_corner = mix(lo, hi, greaterThanEqual(plane.xyz, vec3(0.0)));
    return dot(plane.xyz, far_corner) + plane.w < 0.0;
}

// Whether any of the box may be inside the frustum of `m` (world to
// Vulkan clip space: -w <= x, y <= w, 0 <= z <= w), tested against the
// six planes read off the matrix's rows.
bool box_in_frustum(mat4 m, vec3 lo, vec3 hi) {
    vec4 r0 = vec4(m[0][0], m[1][0], m[2][0], m[3][0]);
    vec4 r1 = vec4(m[0][1], m[1][1], m[2][1], m[3][1]);
    vec4 r2 = vec4(m[0][2], m[1][2], m[2][2], m[3][2]);
    vec4 r3 = vec4(m[0][3], m[1][3], m[2][3], m[3][3]);
    return !(outside(r3 + r0, lo, hi) || outside(r3 - r0, lo, hi)
          || outside(r3 + r1, lo, hi) || outside(r3 - r1, lo, hi)
          || outside(r2, lo, hi) || outside(r3 - r2, lo, hi));
}

// The box grown by the blade's shadow: swept away from the sun `light`
// (toward the light, y > 0) down to the lowest ground, frame.terrain_lowest (0 on
// flat ground). Whatever receives the blade's shadow (ground, other blades,
// obstacles) lies in it.
void shadow_sweep(vec3 light, inout vec3 lo, inout vec3 hi) {
    float floor_y = frame.terrain_lowest;
    vec2 run = light.xz / light.y;   // ground shift per metre of height
    float y0 = max(lo.y, floor_y) - floor_y, y1 = max(hi.y, floor_y) - floor_y;
    vec2 shift_lo = min(run * y0, run * y1);
    vec2 shift_hi = max(run * y0, run * y1);
    lo = vec3(min(lo.x, lo.x - shift_hi.x), min(lo.y, floor_y), min(lo.z, lo.z - shift_hi.y));
    hi = vec3(max(hi.x, hi.x - shift_lo.x), hi.y, max(hi.z, hi.z - shift_lo.y));
}

// How nearly a blade is seen edge-on along `dir[i]` (toward each control
// point): the least |cos| between its width vector and those directions.
// A blade whose width vectors all lie within acos(edge_on) of the rays
// shows (or casts) only a sliver, at most sqrt(1 - edge_on^2) of its
// width; the cull pass leaves it out. A blade without width counts as
// seen face-on (it emits nothing anyway).
float least_alignment(BladeVertex v[4], vec3 dir[4]) {
    float least = 1.0;
    for (int i = 0; i < 4; ++i) {
        vec3 w = v[i].half_width;
        float norms = dot(dir[i], dir[i]) * dot(w, w);
        float c = abs(dot(dir[i], w)) * inversesqrt(max(norms, 1e-30));
        least = min(least, norms > 0.0 ? c : 0.0);
    }
    return least;
}

// How far (m) the shadow map's filter reaches around a receiver: the PCF
// taps' spacing plus a bilinear texel and one more, in metres along the
// light's axes (its projection is orthographic); 0 without shadows.
float shadow_filter_reach() {
    mat4 m = frame.light_view_proj;
    float row0 = length(vec3(m[0][0], m[1][0], m[2][0]));
    float row1 = length(vec3(m[0][1], m[1][1], m[2][1]));
    float texel_m = frame.shadow_texel * 2.0 / max(min(row0, row1), 1e-12);
    return texel_m * (frame.shadow_pcf_radius + 2.0) * frame.shadow_on;   // 0 without shadows
}

// Suns this low cast shadows too long to bound: every blade casts.
#define LOWEST_SWEPT_SUN 0.02

// Branch-free on purpose: lavapipe (Mesa 22.3) inlines uniforms that
// branches depend on and compiles a new shader variant at every dispatch,
// never freed (about 330 KiB and a compile per frame, tests/host_memory.rs
// saw it). A sun too low to sweep leaves every blade a caster; a blade the
// distance thinning drops, or one without width, is drawn by neither
// pass; `edge_on` (a cosine, 1 = off) leaves out blades seen edge-on from
// the camera (colour pass) and from the sun (shadow pass). `lo` and `hi`
// return the blade's bounds, `swept_lo` and `swept_hi` the box its shadow
// can fall in, the filter's reach included (for the occlusion tests,
// glsl/cull/flags.comp); `swept` whether that box bounds it (not with a
// sun too low to sweep).
uint cull_flags(BladeVertex v[4], bool shadows, float edge_on, out vec3 lo, out vec3 hi,
                out vec3 swept_lo, out vec3 swept_hi, out bool swept) {
    float width_scale = thinning_scale(v[0].position, v[0].blade_rand);
    // A blade without width (the cover's beyond its bounds) is no blade.
    uint has_width = uint(any(notEqual(v[0].half_width, vec3(0.0))));
    uint kept = uint(width_scale > 0.0) & has_width;
    blade_bounds(v, width_scale, lo, hi);
    vec3 light = frame.light_dir;
    vec3 to_eye[4], to_sun[4];
    for (int i = 0; i < 4; ++i) {
        to_eye[i] = v[i].position - frame.camera_pos;
        to_sun[i] = light;
    }
    uint facing_eye = uint(least_alignment(v, to_eye) <= edge_on);
    uint facing_sun = uint(least_alignment(v, to_sun) <= edge_on);
    uint in_view = kept & facing_eye & uint(box_in_frustum(frame.view_proj, lo, hi));
    uint low_sun = uint(light.y < LOWEST_SWEPT_SUN);
    light.y = max(light.y, LOWEST_SWEPT_SUN);
    swept = low_sun == 0u;
    swept_lo = lo;
    swept_hi = hi;
    shadow_sweep(light, swept_lo, swept_hi);
    // The shadow map's filter reads around a receiver: a blade whose
    // shadow falls just beyond the view still darkens what it sees a
    // little (`visibility::filter_reach`).
    float reach = shadow_filter_reach();
    swept_lo -= vec3(reach);
    swept_hi += vec3(reach);
    uint caster = kept & facing_sun & uint(shadows)
                & (low_sun | uint(box_in_frustum(frame.view_proj, swept_lo, swept_hi)));
    return in_view * CULL_IN_VIEW | caster * CULL_CASTER | kept * CULL_KEPT
         | (kept & facing_eye) * CULL_FACING;
}

#endif
