"""A benchmark scene whose triangle count is a parameter (issue 5's scaling curves).

``procedural_scene(triangles)`` builds, in memory, a 4×4 grid of UV spheres on a floor under an
area light and a dim sky. The spheres' materials cycle through the paper's effects: diffuse
(shadows), a silver conductor (reflection), glass (refraction) and smooth plastic (reflection over
a diffuse base), so every kind of secondary ray is spawned at any size. Almost all triangles are in
the spheres: each is one UV sphere of ``segments`` × ``rings`` cells, sized so that the 16 together
have about ``triangles`` triangles (exactly ``scene_triangles(scene)``).

The sphere mesh is written once per size as a PLY under the cache folder
(``$HYBRID_CACHE/procedural``) and instanced by ``to_world``, so the scene is an ordinary Mitsuba
scene of 18 shapes that the rasterizer and the ray tracer both see.
"""
from __future__ import annotations

import math
import os
from pathlib import Path

import mitsuba as mi
import numpy as np

from .cache import disk_cache
from .errors import HybridError

GRID = 4
MATERIALS = (
    {"type": "diffuse", "reflectance": {"type": "rgb", "value": [0.7, 0.35, 0.2]}},
    {"type": "conductor", "material": "Ag"},
    {"type": "dielectric", "int_ior": 1.5},
    {"type": "plastic", "diffuse_reflectance": {"type": "rgb", "value": [0.15, 0.3, 0.6]}},
)
MIN_TRIANGLES, MAX_TRIANGLES = 1_000, 50_000_000


def uv_sphere(segments: int, rings: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit sphere: (vertices (n,3), faces (m,3)) with 2·segments·(rings − 1) outward triangles."""
    theta = np.linspace(0.0, np.pi, rings + 1)[1:-1]  # latitudes between the poles
    phi = np.linspace(0.0, 2 * np.pi, segments, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.cos(t), np.sin(t) * np.sin(p)], axis=-1).reshape(-1, 3)
    vertices = np.vstack([[0.0, 1.0, 0.0], ring, [0.0, -1.0, 0.0]]).astype(np.float32)
    south = len(vertices) - 1
    k = np.arange(segments)
    k1 = (k + 1) % segments
    faces = [np.stack([np.zeros(segments, int), 1 + k1, 1 + k], axis=1)]  # north cap
    for r in range(rings - 2):
        a, b = 1 + r * segments, 1 + (r + 1) * segments
        faces += [np.stack([a + k, a + k1, b + k], axis=1), np.stack([a + k1, b + k1, b + k], axis=1)]
    last = 1 + (rings - 2) * segments
    faces.append(np.stack([last + k, last + k1, np.full(segments, south)], axis=1))  # south cap
    return vertices, np.vstack(faces).astype(np.uint32)


def sphere_mesh(triangles_per_sphere: int) -> Path:
    """The PLY of a UV sphere with about ``triangles_per_sphere`` triangles (written once)."""
    segments = max(8, int(round(math.sqrt(triangles_per_sphere))))
    rings = max(3, int(round(triangles_per_sphere / (2 * segments))) + 1)
    path = disk_cache("procedural") / f"uv_sphere_{segments}x{rings}.ply"
    if not path.is_file():
        vertices, faces = uv_sphere(segments, rings)
        mesh = mi.Mesh("uv_sphere", len(vertices), len(faces))
        params = mi.traverse(mesh)
        params["vertex_positions"] = mi.Float(vertices.ravel())
        params["faces"] = mi.UInt32(faces.ravel())
        params.update()
        path.parent.mkdir(parents=True, exist_ok=True)
        tmp = path.with_suffix(f".{os.getpid()}.ply")
        mesh.write_ply(str(tmp))
        tmp.replace(path)
    return path


def procedural_scene(triangles: int = 100_000, resx: int = 1280, resy: int = 720, spp: int = 1, max_depth: int = 8,
                     integrator: str = "path") -> mi.Scene:
    """The scene described in the module docstring, with about ``triangles`` triangles."""
    if not (MIN_TRIANGLES <= int(triangles) <= MAX_TRIANGLES):
        raise HybridError(f"procedural scene: triangles={triangles} must lie in [{MIN_TRIANGLES:,}, {MAX_TRIANGLES:,}]")
    sphere = str(sphere_mesh(int(triangles) // GRID**2))
    T = mi.ScalarTransform4f
    scene = {
        "type": "scene",
        "integrator": {"type": integrator, "max_depth": int(max_depth)},
        "sensor": {"type": "perspective", "fov": 45.0,
                   "to_world": T().look_at(origin=[0.0, 4.2, 7.5], target=[0.0, 0.3, 0.0], up=[0.0, 1.0, 0.0]),
                   "sampler": {"type": "independent", "sample_count": int(spp)},
                   "film": {"type": "hdrfilm", "width": int(resx), "height": int(resy), "pixel_format": "rgb",
                            "rfilter": {"type": "tent"}}},
        "sky": {"type": "constant", "radiance": {"type": "rgb", "value": 0.15}},
        "light": {"type": "rectangle", "to_world": T().translate([0.0, 5.0, 1.0]) @ T().rotate([1, 0, 0], 90) @ T().scale(1.5),
                  "emitter": {"type": "area", "radiance": {"type": "rgb", "value": 12.0}}},
        "floor": {"type": "rectangle", "to_world": T().rotate([1, 0, 0], -90) @ T().scale(8.0),
                  "bsdf": {"type": "diffuse", "reflectance": {"type": "rgb", "value": 0.5}}},
    }
    for i in range(GRID):
        for j in range(GRID):
            k = i * GRID + j
            scene[f"sphere_{k:02d}"] = {
                "type": "ply", "filename": sphere, "bsdf": MATERIALS[(i + j) % len(MATERIALS)],
                "to_world": T().translate([1.6 * (j - 1.5), 0.6, 1.6 * (i - 1.5)]) @ T().scale(0.6)}
    return mi.load_dict(scene, optimize=False)


def scene_triangles(scene: mi.Scene) -> int:
    """Triangles of every mesh in ``scene``."""
    return sum(int(s.face_count()) for s in scene.shapes() if isinstance(s, mi.Mesh))
