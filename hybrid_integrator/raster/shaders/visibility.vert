#version 330 core
// Visibility pass, vertex stage: world-space positions through the Mitsuba camera's projection
// (reversed depth: camera.RasterCamera.clip_matrix).
uniform mat4 world_to_clip;
in vec3 in_position;

void main() {
    gl_Position = world_to_clip * vec4(in_position, 1.0);
}
