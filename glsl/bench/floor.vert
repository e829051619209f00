#version 450
#extension GL_GOOGLE_include_directive : require
// The bench's floor (not part of the paper's pipeline): the grass's own
// triangles drawn with a vertex and a fragment shader only. Each blade
// becomes `segments` quads along its Bezier curve, the tip's a triangle
// (as blade.geom's), evaluated here from the same control points the
// tessellation stages read, so the floor covers the same pixels with the
// same number of triangles; the ratio of the
// grass draw to this is what tessellation and geometry shaders cost.
#include "frame.glsl"
#include "blade_vertex.glsl"

layout(set = 0, binding = 1, std430) readonly buffer Blades {
    BladeVertex points[];
} blades;

// FloorPush: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    FloorPush push;
};

layout(location = 0) out float v_along;

// Two triangles per quad: (along, side) of each corner. The tip's quad
// keeps the first only: the second's top corners are the tip's one point.
const vec2 CORNERS[6] = vec2[6](
    vec2(0.0, -1.0), vec2(0.0, 1.0), vec2(1.0, -1.0),
    vec2(1.0, -1.0), vec2(0.0, 1.0), vec2(1.0, 1.0));

void main() {
    uint per_blade = 6u * push.segments - 3u;
    uint blade = uint(gl_VertexIndex) / per_blade;
    uint in_blade = uint(gl_VertexIndex) % per_blade;
    uint segment = in_blade / 6u;
    vec2 corner = CORNERS[in_blade % 6u];
    uint base = blade * BLADE_CONTROL_POINTS;
    vec3 p0 = blades.points[base + 0u].position;
    vec3 p1 = blades.points[base + 1u].position;
    vec3 p2 = blades.points[base + 2u].position;
    vec3 p3 = blades.points[base + 3u].position;
    float v = (float(segment) + corner.x) / float(push.segments);
    float u = 1.0 - v;
    vec3 p = u * u * u * p0 + 3.0 * u * u * v * p1 + 3.0 * u * v * v * p2 + v * v * v * p3;
    vec3 half_width = mix(blades.points[base].half_width, blades.points[base + 3u].half_width, v)
                    * sqrt(max(1.0 - v, 0.0));
    p += corner.y * half_width;
    v_along = v;
    gl_Position = frame.view_proj * vec4(p, 1.0);
}
