#version 450
// The bench's floor: a flat colour along the blade, the least a fragment
// shader can do and still draw grass.
layout(location = 0) in float v_along;
layout(location = 0) out vec4 out_color;

void main() {
    out_color = vec4(mix(vec3(0.03, 0.09, 0.01), vec3(0.3, 0.45, 0.08), v_along), 1.0);
}
