#version 330 core
// Mesh vertices to view space. The view matrix is rigid (rotation + translation), so normals
// transform by its upper 3x3 without an inverse transpose.
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;

uniform mat4 view;
uniform mat4 projection;

// SNERT_DIRECT: no geometry shader (mesh.geom) between this stage and the fragment shader.
#ifdef SNERT_DIRECT
out FragmentData {
#else
out VertexData {
#endif
    vec3 position_view;
    vec3 normal_view;
} vertex_out;

void main() {
    vec4 p = view * vec4(position, 1.0);
    vertex_out.position_view = p.xyz;
    vertex_out.normal_view = mat3(view) * normal;
    gl_Position = projection * p;
}
