#version 450
#extension GL_GOOGLE_include_directive : require
// Geometry stage: each line segment of the tessellated curve becomes a quad,
// a 4-vertex triangle strip whose width tapers toward the tip (paper section 5).
#include "frame.glsl"

layout(lines) in;
layout(triangle_strip, max_vertices = 4) out;

layout(location = 0) in vec3 e_position[];
layout(location = 1) in vec3 e_tangent[];
layout(location = 2) in vec3 e_width[];
layout(location = 3) in float e_v[];
layout(location = 4) in float e_blade_rand[];
layout(location = 5) in float e_tess_level[];
layout(location = 6) in float e_motion[];
layout(location = 7) in vec4 e_blade[];

layout(location = 0) out vec3 g_world;
layout(location = 1) out vec3 g_normal;
layout(location = 2) out vec2 g_uv;          // x: across the blade (0..1), y: v along it
layout(location = 3) flat out float g_blade_rand;
layout(location = 4) flat out float g_tess_level;
layout(location = 5) flat out float g_motion;
layout(location = 6) flat out vec4 g_blade;  // root x, z; reach (m); clump
layout(location = 7) out vec3 g_side;        // unit width direction (across the blade)

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
    g_world = p;
    g_normal = len2 > 1e-20 ? n * inversesqrt(len2) : vec3(0.0, 1.0, 0.0);
    g_uv = vec2(side * 0.5 + 0.5, e_v[i]);
    g_blade_rand = e_blade_rand[0];
    g_tess_level = e_tess_level[0];
    g_motion = e_motion[0];
    g_blade = e_blade[0];
    float w2 = dot(e_width[i], e_width[i]);
    g_side = w2 > 1e-20 ? e_width[i] * inversesqrt(w2) : vec3(1.0, 0.0, 0.0);
    gl_Position = frame.view_proj * vec4(p, 1.0);
    EmitVertex();
}

void main() {
    emit_side(0, -1.0);
    emit_side(0, 1.0);
    emit_side(1, -1.0);
    emit_side(1, 1.0);
    EndPrimitive();
}
