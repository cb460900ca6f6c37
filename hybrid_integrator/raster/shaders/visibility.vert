#version 330 core
// Visibility pass, vertex stage: world-space positions through the Mitsuba camera's projection
// (reversed depth: camera.RasterCamera.clip_matrix), relative to the eye: subtracting the eye's
// float32 position is exact for points near it (Sterbenz), and the projection of the eye itself
// is folded into the matrix's last column on the host in float64, so a scene far from the
// origin keeps the precision the ray tracer has (camera.RasterCamera.relative_clip).
uniform mat4 world_to_clip;
uniform vec3 origin;
in vec3 in_position;

void main() {
    gl_Position = world_to_clip * vec4(in_position - origin, 1.0);
}
