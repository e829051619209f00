#version 450
// Vertex stage: passes one control point through. Four consecutive vertices
// are one blade, drawn as one 4-point patch (paper section 5, rendering phase).

// `BladeVertex` (src/interface/defs.rs), a field an attribute.
layout(location = 0) in vec3 in_position;
layout(location = 1) in float in_blade_rand;
layout(location = 2) in vec3 in_half_width;
layout(location = 3) in float in_displacement;

layout(location = 0) out vec3 v_position;
layout(location = 1) out float v_blade_rand;
layout(location = 2) out vec3 v_half_width;
layout(location = 3) out float v_displacement;

void main() {
    v_position = in_position;
    v_blade_rand = in_blade_rand;
    v_half_width = in_half_width;
    v_displacement = in_displacement;
    // Unused by the tessellation stages; written so that the module is a
    // complete vertex shader for tools (naga) that require a position.
    gl_Position = vec4(in_position, 1.0);
}
