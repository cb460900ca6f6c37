#version 330 core
// Visibility pass, fragment stage: the minimal primary-hit record of a pixel.
//   target 0 (RGBA32UI): shape index + 1 (0 = background), triangle index, barycentrics (as bits)
//   target 1 (R32F):     distance from the centre of projection along the camera ray
// The depth test runs on that distance, linearly scaled, so precision does not collapse far from
// the camera as a 1/z depth buffer would.
uniform uint shape_id;
uniform vec3 eye;
uniform float inv_max_distance;

in vec3 g_world;
in vec2 g_bary;
flat in uint g_prim;

layout(location = 0) out uvec4 out_hit;
layout(location = 1) out float out_distance;

void main() {
    // Interpolation overshoots the triangle at its edges; clamp so the point stays on it.
    vec2 b = max(g_bary, vec2(0.0));
    float s = b.x + b.y;
    if (s > 1.0) b /= s;
    float t = distance(g_world, eye);
    out_hit = uvec4(shape_id + 1u, g_prim, floatBitsToUint(b.x), floatBitsToUint(b.y));
    out_distance = t;
    gl_FragDepth = clamp(t * inv_max_distance, 0.0, 1.0);
}
