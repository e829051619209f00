#version 450
// Sky: one triangle covering the screen, drawn behind everything (depth 1).
layout(location = 0) out vec2 v_ndc;

void main() {
    vec2 ndc = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
    v_ndc = ndc;
    gl_Position = vec4(ndc, 1.0, 1.0);
}
