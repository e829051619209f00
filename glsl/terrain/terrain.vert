#version 450
#extension GL_GOOGLE_include_directive : require
// The terrain mesh (src/render/terrain.rs): world-space positions and the
// ground's normals, drawn once where it lies. The obstacle vertex layout;
// its albedo is unused (the soil gives the colour).
#include "frame.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;

void main() {
    v_world = in_position;
    v_normal = in_normal;
    gl_Position = frame.view_proj * vec4(in_position, 1.0);
}
