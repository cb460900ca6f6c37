#version 330 core
// Visibility pass, fragment stage: the minimal primary-hit record of a pixel, the global number of
// the frontmost triangle + 1 (0 = background). The whole scene is one draw call, so that number is
// gl_PrimitiveID; which shape and object it belongs to, where on it the pixel's camera ray hits
// and how far away, are found from it on the device (primary.py). The shader writes no depth, so
// the depth test runs before it (early depth testing).
layout(location = 0) out uint out_triangle;

void main() {
    out_triangle = uint(gl_PrimitiveID) + 1u;
}
