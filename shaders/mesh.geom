#version 330 core
// Per triangle: the facet normal (flat shading), the triangle's index (its quality lives in a
// buffer texture) and barycentric coordinates, whose screen-space derivatives give the
// distance to the nearest edge for the wireframe overlay in the same pass (no line primitives,
// which core profiles only draw one pixel wide). The barycentrics are interpolated with
// perspective correction: their screen derivatives are still exact per pixel, and llvmpipe
// interpolates `noperspective` outputs wrongly in primitives it clips at the viewport edge.
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in VertexData {
    vec3 position_view;
    vec3 normal_view;
} vertex_in[];

out FragmentData {
    vec3 position_view;
    vec3 normal_view;
    vec3 barycentric;
    flat vec3 facet_normal_view;
    flat int triangle;
} fragment_out;

// The first triangle of this draw: a mesh drawn in parts numbers its triangles from 0 in each.
uniform int first_triangle;

void main() {
    vec3 facet = cross(vertex_in[1].position_view - vertex_in[0].position_view,
                       vertex_in[2].position_view - vertex_in[0].position_view);
    // A zero-area triangle has no direction of its own: face the viewer.
    facet = dot(facet, facet) > 0.0 ? normalize(facet) : vec3(0.0, 0.0, 1.0);
    for (int i = 0; i < 3; ++i) {
        fragment_out.position_view = vertex_in[i].position_view;
        fragment_out.normal_view = vertex_in[i].normal_view;
        fragment_out.barycentric = vec3(i == 0, i == 1, i == 2);
        fragment_out.facet_normal_view = facet;
        fragment_out.triangle = first_triangle + gl_PrimitiveIDIn;
        gl_Position = gl_in[i].gl_Position;
        EmitVertex();
    }
    EndPrimitive();
}
