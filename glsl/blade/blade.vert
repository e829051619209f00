#version 450
// Vertex stage: passes one control point through. Four consecutive vertices
// are one blade, drawn as one 4-point patch (paper section 5, rendering phase).

layout(location = 0) in vec4 in_position;
layout(location = 1) in vec4 in_width;

layout(location = 0) out vec4 v_position;
layout(location = 1) out vec4 v_width;

void main() {
    v_position = in_position;
    v_width = in_width;
    // Unused by the tessellation stages; written so that the module is a
    // complete vertex shader for tools (naga) that require a position.
    gl_Position = vec4(in_position.xyz, 1.0);
}
