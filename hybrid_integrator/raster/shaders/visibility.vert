#version 330 core
// Visibility pass, vertex stage: world-space positions through the Mitsuba camera's projection.
uniform mat4 world_to_clip;
in vec3 in_position;
out vec3 v_world;

void main() {
    v_world = in_position;
    gl_Position = world_to_clip * vec4(in_position, 1.0);
}
