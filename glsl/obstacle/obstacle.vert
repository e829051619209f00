#version 450
#extension GL_GOOGLE_include_directive : require
// Obstacles (paper Fig. 13): the wall, boulder and post the wind meets,
// drawn as triangle meshes made on the CPU (src/render/obstacles.rs). The
// same shader serves the shadow pass, whose frame uniforms are the light's.
#include "frame.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_albedo;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec3 v_albedo;

void main() {
    v_world = in_position;
    v_normal = in_normal;
    v_albedo = in_albedo;
    gl_Position = frame.view_proj * vec4(in_position, 1.0);
}
