#version 450
#extension GL_GOOGLE_include_directive : require
// Tessellation control: level of detail. A blade close to the viewer is cut
// into 20 segments, a medium one into 10, a far one into 3 (paper section 5.1).
// With culling on, the distance thinning widens the blades it keeps
// (glsl/common/thinning.glsl); the cull pass has left out those it drops.
#include "frame.glsl"
#include "thinning.glsl"
#include "grass_color.glsl"

layout(vertices = 4) out;

layout(location = 0) in vec3 v_position[];
layout(location = 1) in float v_blade_rand[];
layout(location = 2) in vec3 v_half_width[];
layout(location = 3) in float v_displacement[];

layout(location = 0) out vec3 c_position[];
layout(location = 1, component = 0) out vec3 c_half_width[];
layout(location = 1, component = 3) out float c_displacement[];
layout(location = 2) patch out float c_tess_level;
// The blade as a whole, in one location: its root (x, z) and its reach
// (its edges end to end: the same in any pose; m).
layout(location = 3, component = 0) patch out vec2 c_root;
layout(location = 3, component = 2) patch out float c_reach;
// The blade's colour (glsl/common/grass_color.glsl's blade_tint).
layout(location = 4) patch out vec3 c_tint;
layout(location = 5) patch out float c_tip_len;
layout(location = 6) patch out float c_dry;

float tess_level_for(float distance_to_eye) {
    if (frame.lod_on == 0.0) {
        return frame.tess_level.x;          // "without LOD": always the close level
    }
    if (distance_to_eye < frame.lod_close_distance) {
        return frame.tess_level.x;
    }
    if (distance_to_eye < frame.lod_far_distance) {
        return frame.tess_level.y;
    }
    return frame.tess_level.z;
}

// The nearest depth along the view's axis at which a receiver of this
// caster's shadow can be seen, from its root's `depth`. Its shadow falls
// from a point of the blade (within `reach` of its root) down the sun's
// rays to the lowest ground, t metres along them changing the depth by
// -t dot(light, forward): nearer only where the sun is ahead of the eye.
// The shadow filter darkens receivers up to `blur` from that volume. Its
// receivers are no higher than `top` (the blade's, plus `blur`), and the
// view holds such a point only from the depth where its lowest ray has
// fallen from the eye's height to that top (frame.view_bottom_slope).
float receiver_depth(float depth, float reach, float blur, float top) {
    vec3 l = frame.light_dir;
    float drop = top - frame.terrain_lowest;
    float ahead = max(dot(l, frame.view_forward), 0.0);
    float nearest = depth - reach - blur - ahead * max(drop, 0.0) / max(l.y, 0.02);
    float slope = frame.view_bottom_slope;
    float seen_from = slope < 0.0 ? max(frame.camera_pos.y - top, 0.0) / -slope : 0.0;
    return max(nearest, seen_from);
}

// How much a departure of the caster's shape, in any direction, moves
// its shadow on flat ground across the rays of the view, at most: the
// sun's rays carry a departure d to the ground as M d = d - (d.y / l.y) l
// (horizontal), and the view sees a horizontal g across the ray as
// (g . across, sin_g g . along), `along` the ray's horizontal direction,
// `sin_g` the ray's rise at most at the receivers. The largest singular
// value of that 2 x 3 map: 1 / l.y looking straight down, less at a
// grazing ray, which foreshortens the shadow's run along it.
float ground_stretch(vec3 ray, float sin_g) {
    vec3 l = frame.light_dir;
    vec2 h = ray.xz;
    vec2 along = dot(h, h) > 1e-12 ? normalize(h) : vec2(0.0, 1.0);
    vec2 across = vec2(-along.y, along.x);
    float ly = max(l.y, 0.02);
    float p = dot(l.xz, across) / ly, q = dot(l.xz, along) / ly;
    // Rows a1 = M^T across, a2 = sin_g M^T along; their Gram matrix.
    float a = 1.0 + p * p;
    float c = sin_g * sin_g * (1.0 + q * q);
    float b = sin_g * p * q;
    float half_diff = 0.5 * (a - c);
    return sqrt(0.5 * (a + c) + sqrt(half_diff * half_diff + b * b));
}

// How far (m) the shadow pass's copy of a caster may depart from its
// curve: frame.shadow_error_texels texels of the map, or, where more,
// frame.shadow_error_pixels pixels of the view at its nearest visible
// receiver on flat ground. A pixel there spans receiver_depth *
// pixel_per_depth_m across the ray, times the cosine of the ray's angle
// off the axis (its root's: a conservative reading for the receivers
// beside it); the ground under the sun stretches a departure across the
// rays by ground_stretch, the ray rising at most as from the receivers'
// lowest or highest point to the eye over the receiver's depth.
float shadow_tolerance(vec3 root, float reach) {
    float texels = frame.shadow_error_texels * frame.shadow_texel_m;
    vec3 ray = root - frame.camera_pos;
    float depth = dot(ray, frame.view_forward);
    float off_axis = depth / max(length(ray), 1e-6);
    float blur = frame.shadow_texel_m * (frame.shadow_pcf_radius + 2.0);
    float top = root.y + reach + blur;
    float receiver = max(receiver_depth(depth, reach, blur, top), 0.0);
    float pixel = receiver * frame.pixel_per_depth_m * max(off_axis, 0.0);
    float rise = max(frame.camera_pos.y - frame.terrain_lowest, top - frame.camera_pos.y);
    float sin_g = min(max(rise, 0.0) / max(receiver, 1e-3), 1.0);
    float pixels = frame.shadow_error_pixels * pixel / ground_stretch(ray, sin_g);
    return max(texels, pixels);
}

// In the shadow pass (frame.shadow_texel_m > 0), the fewest segments
// whose shape departs from the curved blade by at most `tau` metres
// (shadow_tolerance): a blade is no finer in the map than its size there
// and in the view needs (ours; never finer than its distance level).
// Bounds from the control points, each the segments n it needs:
// - the centreline: n chords of a curve of reach L that turns by theta in
//   all (the control polygon's turn bounds the cubic's) depart from it by
//   L theta / (8 n^2);
// - the edges: a width vector of half width w turning by phi from root
//   to tip, interpolated across n segments, by w (phi / n)^2 / 8;
// - the tapered tip (sqrt(1 - v), blade.geom): the last of n segments'
//   chord by about 0.207 w / sqrt(n).
float shadow_segments(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float reach, float width_scale, float tau) {
    vec3 d0 = p1 - p0, d1 = p2 - p1, d2 = p3 - p2;
    float turn = 0.0;
    if (dot(d0, d0) > 1e-20 && dot(d1, d1) > 1e-20) {
        turn += acos(clamp(dot(normalize(d0), normalize(d1)), -1.0, 1.0));
    }
    if (dot(d1, d1) > 1e-20 && dot(d2, d2) > 1e-20) {
        turn += acos(clamp(dot(normalize(d1), normalize(d2)), -1.0, 1.0));
    }
    vec3 w0 = v_half_width[0], w3 = v_half_width[3];
    float w = length(w0) * width_scale;
    float twist = 0.0;
    if (dot(w0, w0) > 1e-20 && dot(w3, w3) > 1e-20) {
        twist = acos(clamp(dot(normalize(w0), normalize(w3)), -1.0, 1.0));
    }
    float bend = sqrt(reach * turn / (8.0 * tau));
    float edges = twist * sqrt(w / (8.0 * tau));
    float tip = 0.207 * w / tau;
    // One segment widens its triangle by a third at the root
    // (taper_area_gain(1)): within tau only for blades narrow enough.
    float one = w > 3.0 * tau ? 2.0 : 1.0;
    return max(ceil(max(max(bend, edges), tip * tip)), one);
}

// The shadow pass's width gain for a caster of n segments: the ratio of
// the taper's area (sqrt(1 - v) from root to tip: 2/3) to that of its n
// trapezoids, which cut inside the concave taper (a quarter of it at one
// segment, 5% at three). Without it a coarser copy casts a smaller
// shadow and the frame brightens with every segment left out (ours).
// Its widening departs from the shape by (gain - 1) w at the root: under
// the tip's chord for n > 1, and bounded for n = 1 in shadow_segments.
float taper_area_gain(float n) {
    float sum = 0.0;
    for (float i = 0.0; i < n; i += 1.0) {
        sum += sqrt(1.0 - i / n);
    }
    return (2.0 / 3.0) / ((sum - 0.5) / n);
}

// The blade's segments in this pass: its distance level, in the shadow
// pass no finer than its shadow's tolerance needs.
float segments(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float reach, float width_scale) {
    float level = tess_level_for(distance(frame.camera_pos, p0));
    float tau = frame.shadow_texel_m > 0.0 ? shadow_tolerance(p0, reach) : 0.0;
    if (tau > 0.0) {
        level = min(level, shadow_segments(p0, p1, p2, p3, reach, width_scale, tau));
    }
    return level;
}

void main() {
    c_position[gl_InvocationID] = v_position[gl_InvocationID];
    float width_scale = thinning_scale(v_position[0], v_blade_rand[0]);
    vec3 p0 = v_position[0], p1 = v_position[1], p2 = v_position[2], p3 = v_position[3];
    float reach = distance(p0, p1) + distance(p1, p2) + distance(p2, p3);
    // Every invocation finds the level (the same, from the same inputs):
    // the shadow pass's width gain follows it.
    float level = segments(p0, p1, p2, p3, reach, width_scale);
    float gain = frame.shadow_texel_m > 0.0 ? taper_area_gain(level) : 1.0;
    c_half_width[gl_InvocationID] = v_half_width[gl_InvocationID] * (width_scale * gain);
    c_displacement[gl_InvocationID] = v_displacement[gl_InvocationID];

    if (gl_InvocationID == 0) {
        // Isolines: outer[0] is the number of lines (one blade), outer[1] the
        // number of segments along it.
        gl_TessLevelOuter[0] = 1.0;
        gl_TessLevelOuter[1] = level;
        c_tess_level = level;
        float clump = clump_of(p0.xz);
        c_root = p0.xz;
        c_reach = reach;
        BladeTint tint = blade_tint(v_blade_rand[0], clump);
        c_tint = tint.tint;
        c_tip_len = tint.tip_len;
        c_dry = tint.dry;
    }
}
