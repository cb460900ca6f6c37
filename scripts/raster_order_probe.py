"""Probe: does the order of the triangles change the OpenGL visibility draw's time? (issue 10)

The draw is geometry-bound on the H100 (``raster_cull_probe.py``). A GPU shades each vertex once
per batch of nearby indices (its post-transform vertex cache), so triangles in an order that
reuses vertices shade fewer of them. This times the draw (a GL timer query around
``Rasterizer.render``, its clear and draw; median of ``--repeats``) with the scene's triangles
in several orders: as loaded, shuffled, sorted along a Morton curve of their centroids (over the
whole scene, or within each shape), each also with the vertices renumbered in order of first use
(``SceneGeometry.renumbered``, which changes no triangle's number; the rasterizer draws "as
loaded, renumbered"); and the clear alone (no triangles).

    python3 scripts/raster_order_probe.py --variant cuda_ad_rgb SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

from raster_cull_probe import arguments, rasterizers, timed_draw  # scripts/ is on sys.path when a script runs


def morton_order(centroids, bits: int = 10):
    """Indices that sort points along a 3D Morton (Z-order) curve of ``bits`` bits per axis."""
    import numpy as np

    lo, hi = centroids.min(axis=0), centroids.max(axis=0)
    q = ((centroids - lo) / np.maximum(hi - lo, 1e-30) * (2 ** bits - 1)).astype(np.uint64)
    code = np.zeros(len(q), dtype=np.uint64)
    for b in range(bits):
        for axis in range(3):
            code |= ((q[:, axis] >> np.uint64(b)) & np.uint64(1)) << np.uint64(3 * b + axis)
    return np.argsort(code, kind="stable")


def main() -> None:
    import numpy as np

    from hybrid_integrator.raster.geometry import SceneGeometry, scene_geometry

    args = arguments(__doc__)
    for name, scene, raster, camera, query in rasterizers(args):
        g = scene_geometry(scene)  # as loaded (the rasterizer draws it renumbered)
        faces, positions = g.faces, g.positions
        shuffled = np.random.default_rng(1).permutation(len(faces))
        morton = morton_order(positions[faces].mean(axis=1))
        # Morton order within each shape (a shape's triangles stay one range of the global numbering)
        per_shape = np.concatenate([a + morton_order(positions[faces[a:b]].mean(axis=1))
                                    for a, b in zip(g.first_triangle[:-1], g.first_triangle[1:]) if b > a])
        orders = {"as loaded": (faces, positions, None), "shuffled": (faces[shuffled], positions, shuffled)}
        for label, perm in (("renumbered", None), ("morton", morton), ("shape morton", per_shape)):
            f = faces if perm is None else faces[perm]
            renumbered = SceneGeometry(positions, f, g.first_triangle, g.proxy).renumbered()
            if perm is not None:
                orders[label] = (f, positions, perm)
            orders[label if perm is None else label + "+renumbered"] = (renumbered.faces, renumbered.positions, perm)
        orders["clear only"] = (None, None, None)
        base = None
        for label, (f, p, perm) in orders.items():
            if f is None:
                raster._vao = None
            else:
                vbo = raster.ctx.buffer(np.ascontiguousarray(p, dtype="f4").tobytes())
                ibo = raster.ctx.buffer(np.ascontiguousarray(f, dtype="u4").tobytes())
                raster._vao = raster.ctx.vertex_array(raster.program, [(vbo, "3f", "in_position")], index_buffer=ibo,
                                                      index_element_size=4)
            ms, fbo = timed_draw(raster, camera, query, args.repeats)
            ids = raster.read_ids(fbo).astype(np.int64)
            if perm is not None:  # back to the loaded numbering
                ids = np.where(ids > 0, perm[np.maximum(ids - 1, 0)] + 1, 0)
            base = ids if base is None else base
            print(f"{name}: {len(faces):,} triangles, {label:26s}: GL {ms:.3f} ms, "
                  f"same triangle on {100 * np.mean(ids == base):.3f} % of pixels", flush=True)


if __name__ == "__main__":
    main()
