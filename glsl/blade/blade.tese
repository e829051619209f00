#version 450
#extension GL_GOOGLE_include_directive : require
// Tessellation evaluation: evaluates the blade's cubic Bezier curve at u
// (paper eq. 1), its tangent, and the interpolated width vector.
#include "frame.glsl"

layout(isolines, equal_spacing) in;

layout(location = 0) in vec3 c_position[];
layout(location = 1, component = 0) in vec3 c_half_width[];
layout(location = 1, component = 3) in float c_displacement[];
layout(location = 2) patch in float c_tess_level;
layout(location = 3, component = 0) patch in vec2 c_root;
layout(location = 3, component = 2) patch in float c_reach;
layout(location = 4) patch in vec3 c_tint;
layout(location = 5) patch in float c_tip_len;
layout(location = 6) patch in float c_dry;

layout(location = 0) out vec3 e_position;
layout(location = 1) out vec3 e_tangent;
layout(location = 2) out vec3 e_width;
layout(location = 3) out float e_v;          // texture coordinate along the blade: v = u
layout(location = 5) out float e_tess_level;
layout(location = 6) out float e_motion;
layout(location = 7, component = 0) out vec2 e_root;
layout(location = 7, component = 2) out float e_reach;
layout(location = 8) out vec3 e_tint;
layout(location = 9) out float e_tip_len;
layout(location = 10) out float e_dry;

void main() {
    float t = gl_TessCoord.x;
    float s = 1.0 - t;
    // Bernstein basis of the cubic and its derivative.
    vec4 b = vec4(s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t);
    vec4 db = vec4(-3.0 * s * s, 3.0 * s * s - 6.0 * s * t, 6.0 * s * t - 3.0 * t * t, 3.0 * t * t);

    vec3 p0 = c_position[0], p1 = c_position[1], p2 = c_position[2], p3 = c_position[3];
    e_position = b.x * p0 + b.y * p1 + b.z * p2 + b.w * p3;
    e_tangent = db.x * p0 + db.y * p1 + db.z * p2 + db.w * p3;
    e_width = b.x * c_half_width[0] + b.y * c_half_width[1] + b.z * c_half_width[2] + b.w * c_half_width[3];
    e_v = t;
    e_tess_level = c_tess_level;
    e_motion = abs(c_displacement[3]);
    e_root = c_root;
    e_reach = c_reach;
    e_tint = c_tint;
    e_tip_len = c_tip_len;
    e_dry = c_dry;
}
