#version 450
#extension GL_GOOGLE_include_directive : require
// Geometry stage: each line segment of the tessellated curve becomes a quad,
// a 4-vertex triangle strip whose width tapers toward the tip (paper section 5);
// the tip's segment, whose top closes to a point, a triangle.
// What varies smoothly along the blade is worked out here, at its vertices,
// rather than at every pixel: the canopy's extinction above a point and
// the sky its cuticle mirrors (the blade's light: glsl/blade/blade.frag).
#include "frame.glsl"
#include "sky.glsl"
#include "canopy_light.glsl"
#include "leaf_optics.glsl"

layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;

layout(location = 0) in vec3 e_position[];
layout(location = 1) in vec3 e_tangent[];
layout(location = 2) in vec3 e_width[];
layout(location = 3) in float e_v[];
layout(location = 5) in float e_tess_level[];
layout(location = 6) in float e_motion[];
layout(location = 7, component = 0) in vec2 e_root[];
layout(location = 7, component = 2) in float e_reach[];
layout(location = 8) in vec3 e_tint[];
layout(location = 9) in float e_tip_len[];
layout(location = 10) in float e_dry[];

layout(location = 0) out vec3 g_world;
layout(location = 1) out vec3 g_normal;
layout(location = 2) out vec2 g_uv;          // x: across the blade (0..1), y: v along it
layout(location = 4) flat out float g_tess_level;
layout(location = 5) flat out float g_motion;
layout(location = 6) flat out vec2 g_root;   // the blade's root (x, z)
layout(location = 7) out vec3 g_side;        // unit width direction (across the blade)
layout(location = 8) out vec2 g_extinction;  // the canopy's per unit of leaf area index (sun, sky)
layout(location = 9) out vec3 g_sky;         // the sky the cuticle mirrors toward the eye here
// The blade's colour (grass_color.glsl's blade_tint).
layout(location = 10) flat out vec3 g_tint;
layout(location = 11) flat out float g_tip_len;
layout(location = 12) flat out float g_dry;

// Width profile along the blade: full near the root, a point at the tip.
float taper(float v) {
    return sqrt(max(1.0 - v, 0.0));
}

void emit_side(int i, float side) {
    vec3 half_width = e_width[i] * taper(e_v[i]);
    vec3 p = e_position[i] + side * half_width;
    // E_n = E_w x E_e (docs/method.md section 2). Guard a zero tangent or width.
    vec3 n = cross(e_width[i], e_tangent[i]);
    float len2 = dot(n, n);
    n = len2 > 1e-20 ? n * inversesqrt(len2) : vec3(0.0, 1.0, 0.0);
    g_world = p;
    g_normal = n;
    g_uv = vec2(side * 0.5 + 0.5, e_v[i]);
    g_tess_level = e_tess_level[0];
    g_motion = e_motion[0];
    g_root = e_root[0];
    g_tint = e_tint[0];
    g_tip_len = e_tip_len[0];
    g_dry = e_dry[0];
    float w2 = dot(e_width[i], e_width[i]);
    vec3 across = w2 > 1e-20 ? e_width[i] * inversesqrt(w2) : vec3(1.0, 0.0, 0.0);
    g_side = across;
    // The canopy above this point: its height at rest along the blade (its
    // share of the blade's reach: the same in any pose, as the canopy
    // bends together); the leaves around it lie as this blade does here.
    vec3 l = frame.light_dir;
    g_extinction = canopy_extinction(e_v[i] * e_reach[0], abs(n.y), max(l.y, 0.0));
    // The sky the cuticle mirrors at this edge: the rounded normal of the
    // face the eye sees (blade.frag's), the sky above the mirror's horizon.
    vec3 v = normalize(frame.camera_pos - p);
    vec3 seen = dot(n, v) < 0.0 ? -n : n;
    vec3 ns = rounded_normal(seen, across, side);
    vec3 mirrored = reflect(-v, ns);
    float sky_open = smoothstep(-0.05, 0.25, mirrored.y);
    g_sky = sky_open * sky_color(normalize(vec3(mirrored.x, max(mirrored.y, 0.0), mirrored.z)), l);
    gl_Position = frame.view_proj * vec4(p, 1.0);
    EmitVertex();
}

void main() {
    emit_side(0, -1.0);
    emit_side(0, 1.0);
    emit_side(1, -1.0);
    // The tip's segment is a triangle: its two top corners are the one
    // point the taper closes to, and a second copy of it would only add a
    // triangle of no area (ours; the same pixels, one primitive fewer a
    // blade in each pass).
    if (taper(e_v[1]) > 0.0) {
        emit_side(1, 1.0);
    }
    EndPrimitive();
}
