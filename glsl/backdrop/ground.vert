#version 450
#extension GL_GOOGLE_include_directive : require
// Ground: a square on y = 0 centred under the field, two triangles.
#include "frame.glsl"

layout(location = 0) out vec3 v_world;

void main() {
    const vec2 corners[6] = vec2[](vec2(-1, -1), vec2(1, -1), vec2(1, 1),
                                   vec2(-1, -1), vec2(1, 1), vec2(-1, 1));
    vec2 xz = frame.ground.xy + corners[gl_VertexIndex] * frame.ground.z;
    v_world = vec3(xz.x, 0.0, xz.y);
    gl_Position = frame.view_proj * vec4(v_world, 1.0);
}
