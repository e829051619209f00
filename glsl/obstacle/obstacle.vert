#version 450
#extension GL_GOOGLE_include_directive : require
// Obstacles (paper Fig. 13) and colliders: the wall, boulder and post the
// wind meets, the ball and walker that press the grass, drawn as triangle
// meshes made on the CPU (src/render/obstacles.rs), each placed by its
// model matrix (the identity for obstacles, made in world space). The same
// shader serves the shadow pass, whose frame uniforms are the light's.
#include "frame.glsl"
#include "interface.glsl"

// Placement: src/interface/defs.rs.
layout(push_constant, std430) uniform Push {
    Placement placement;
};

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec3 in_albedo;

layout(location = 0) out vec3 v_world;
layout(location = 1) out vec3 v_normal;
layout(location = 2) out vec3 v_albedo;
layout(location = 3) out vec3 v_local;

void main() {
    v_world = (placement.model * vec4(in_position, 1.0)).xyz;
    v_normal = mat3(placement.model) * in_normal;
    v_albedo = in_albedo;
    v_local = in_position;
    gl_Position = frame.view_proj * vec4(v_world, 1.0);
}
