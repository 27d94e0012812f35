#version 330 core
// One triangle that covers the viewport, made from the vertex index (no vertex buffer).
out float height; // 0 at the bottom of the viewport, 1 at the top

void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    height = corner.y; // the viewport spans corner.y in [0, 1]
    gl_Position = vec4(corner * 2.0 - 1.0, 1.0, 1.0);
}
