"""Stage 1 of the pipeline, the deferred rasterizer (paper §3.1): OpenGL context, camera,
geometry, visibility buffer and G-buffer."""
