#version 450
// Ground: the plane y = 0 out to the horizon, found per pixel by the
// fragment shader (ground.frag); this is one triangle covering the screen.
layout(location = 0) out vec2 v_ndc;

void main() {
    vec2 ndc = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
    v_ndc = ndc;
    gl_Position = vec4(ndc, 0.0, 1.0);
}
