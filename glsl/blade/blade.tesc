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

layout(location = 0) in vec4 v_position[];
layout(location = 1) in vec4 v_width[];

layout(location = 0) out vec4 c_position[];
layout(location = 1) out vec4 c_width[];
layout(location = 2) patch out float c_tess_level;
// The blade as a whole, in one location: its root (x, z) and its reach
// (its edges end to end: the same in any pose; m).
layout(location = 3, component = 0) patch out vec2 c_root;
layout(location = 3, component = 2) patch out float c_reach;
// The blade's colour (glsl/common/grass_color.glsl's blade_tint).
layout(location = 4) patch out vec4 c_tint;

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

// In the shadow pass (frame.shadow_texel_m > 0), the fewest segments
// whose shape departs from the curved blade by at most
// frame.shadow_error_texels texels (tau, in metres): a blade is no
// finer in the map than its size there needs (ours; never finer than
// its distance level). Bounds from the control points, each the
// segments n it needs:
// - the centreline: n chords of a curve of reach L that turns by theta in
//   all (the control polygon's turn bounds the cubic's) depart from it by
//   L theta / (8 n^2);
// - the edges: a width vector of half width w turning by phi from root
//   to tip, interpolated across n segments, by w (phi / n)^2 / 8;
// - the tapered tip (sqrt(1 - v), blade.geom): the last of n segments'
//   chord by about 0.207 w / sqrt(n).
float shadow_segments(vec3 p0, vec3 p1, vec3 p2, vec3 p3, float reach, float width_scale) {
    float tau = frame.shadow_error_texels * frame.shadow_texel_m;
    vec3 d0 = p1 - p0, d1 = p2 - p1, d2 = p3 - p2;
    float turn = 0.0;
    if (dot(d0, d0) > 1e-20 && dot(d1, d1) > 1e-20) {
        turn += acos(clamp(dot(normalize(d0), normalize(d1)), -1.0, 1.0));
    }
    if (dot(d1, d1) > 1e-20 && dot(d2, d2) > 1e-20) {
        turn += acos(clamp(dot(normalize(d1), normalize(d2)), -1.0, 1.0));
    }
    vec3 w0 = v_width[0].xyz, w3 = v_width[3].xyz;
    float w = length(w0) * width_scale;
    float twist = 0.0;
    if (dot(w0, w0) > 1e-20 && dot(w3, w3) > 1e-20) {
        twist = acos(clamp(dot(normalize(w0), normalize(w3)), -1.0, 1.0));
    }
    float bend = sqrt(reach * turn / (8.0 * tau));
    float edges = twist * sqrt(w / (8.0 * tau));
    float tip = 0.207 * w / tau;
    return max(ceil(max(max(bend, edges), tip * tip)), 1.0);
}

void main() {
    c_position[gl_InvocationID] = v_position[gl_InvocationID];
    float width_scale = thinning_scale(v_position[0]);
    c_width[gl_InvocationID] = vec4(v_width[gl_InvocationID].xyz * width_scale, v_width[gl_InvocationID].w);

    if (gl_InvocationID == 0) {
        // Distance from the eye to the blade's root decides the level.
        float level = tess_level_for(distance(frame.camera_pos, v_position[0].xyz));
        vec3 p0 = v_position[0].xyz, p1 = v_position[1].xyz, p2 = v_position[2].xyz, p3 = v_position[3].xyz;
        float reach = distance(p0, p1) + distance(p1, p2) + distance(p2, p3);
        if (frame.shadow_texel_m > 0.0 && frame.shadow_error_texels > 0.0) {
            level = min(level, shadow_segments(p0, p1, p2, p3, reach, width_scale));
        }
        // Isolines: outer[0] is the number of lines (one blade), outer[1] the
        // number of segments along it.
        gl_TessLevelOuter[0] = 1.0;
        gl_TessLevelOuter[1] = level;
        c_tess_level = level;
        float clump = clump_of(p0.xz);
        c_root = p0.xz;
        c_reach = reach;
        c_tint = blade_tint(v_position[0].w, clump);
    }
}
