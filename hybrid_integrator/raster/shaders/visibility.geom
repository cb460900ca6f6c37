#version 330 core
// Visibility pass, geometry stage: tags each triangle's corners with the barycentric coordinates
// of Mitsuba's prim_uv convention, p = (1 - u - v) p0 + u p1 + v p2, and passes the triangle's
// index within the draw call (= Mitsuba's prim_index, one draw call per shape).
layout(triangles) in;
layout(triangle_strip, max_vertices = 3) out;

in vec3 v_world[];
out vec3 g_world;
out vec2 g_bary;
flat out uint g_prim;

const vec2 CORNER[3] = vec2[3](vec2(0.0, 0.0), vec2(1.0, 0.0), vec2(0.0, 1.0));

void main() {
    for (int k = 0; k < 3; ++k) {
        gl_Position = gl_in[k].gl_Position;
        g_world = v_world[k];
        g_bary = CORNER[k];
        g_prim = uint(gl_PrimitiveIDIn);
        EmitVertex();
    }
    EndPrimitive();
}
