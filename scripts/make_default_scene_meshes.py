"""Write the meshes of the embedded default scene (``scenes/default.xml``).

The default scene's glass and mirror spheres are triangle meshes, so that the raster stage sees
exactly what Mitsuba's ray tracer sees (an analytic ``sphere`` would be a tessellated proxy). One
unit icosphere is written once and placed twice by ``to_world`` in the XML:

    python scripts/make_default_scene_meshes.py      # writes scenes/meshes/icosphere.ply
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np


def icosphere(subdivisions: int) -> tuple[np.ndarray, np.ndarray]:
    """Unit sphere from a subdivided icosahedron: (vertices (n,3), faces (m,3)), outward winding."""
    t = (1.0 + 5 ** 0.5) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
         (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2),
         (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5),
         (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    verts = [np.array(p, float) / np.linalg.norm(p) for p in v]
    faces = f
    for _ in range(subdivisions):
        midpoint: dict[tuple[int, int], int] = {}

        def mid(a: int, b: int) -> int:
            key = (min(a, b), max(a, b))
            if key not in midpoint:
                p = verts[a] + verts[b]
                verts.append(p / np.linalg.norm(p))
                midpoint[key] = len(verts) - 1
            return midpoint[key]

        faces = [tri for a, b, c in faces
                 for tri in ((a, mid(a, b), mid(c, a)), (b, mid(b, c), mid(a, b)),
                             (c, mid(c, a), mid(b, c)), (mid(a, b), mid(b, c), mid(c, a)))]
    return np.array(verts, dtype=np.float32), np.array(faces, dtype=np.uint32)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--subdivisions", type=int, default=4)
    parser.add_argument("-o", "--output", type=Path, default=Path(__file__).resolve().parents[1] / "scenes/meshes/icosphere.ply")
    args = parser.parse_args()

    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    verts, faces = icosphere(args.subdivisions)
    mesh = mi.Mesh("icosphere", len(verts), len(faces), has_vertex_normals=True)
    params = mi.traverse(mesh)
    params["vertex_positions"] = verts.ravel()
    params["vertex_normals"] = verts.ravel()  # unit sphere: the normal is the position
    params["faces"] = faces.ravel()
    params.update()
    args.output.parent.mkdir(parents=True, exist_ok=True)
    mesh.write_ply(str(args.output))
    print(f"wrote {args.output}: {len(verts)} vertices, {len(faces)} triangles")


if __name__ == "__main__":
    main()
