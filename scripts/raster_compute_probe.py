"""Probe: the visibility pass in compute shaders against OpenGL's draw (``Rasterizer.render``,
``method="compute"`` / ``"draw"``): the GL time of each (a timer query around the pass, median of
``--repeats``), the compute pass's stages, how many triangles each tier takes, how many pixels
keep the draw's triangle, and how many agree with Mitsuba's camera rays (``raster/agreement.py``),
per scene. Where the GL has 64-bit atomics (the one-pass compute pass, ``raster/compute.py``), the
two-pass pass too: its visibility buffer must be the one-pass's bit for bit, and its times beside.

    python3 scripts/raster_compute_probe.py --variant cuda_ad_rgb SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

import statistics

from raster_cull_probe import arguments, rasterizers, timed_draw  # scripts/ is on sys.path when a script runs


def stage_times(raster, render, repeats: int, visibility: type | None = None) -> dict[int, float]:
    """Median GL time (ms) of each stage of the compute pass ``render()`` (a timer query per dispatch)
    of the class ``visibility`` (default: ``compute.ComputeVisibility``)."""
    from hybrid_integrator.raster import compute

    visibility = visibility or compute.ComputeVisibility
    queries, times = {}, {}
    run = visibility._run

    def timed_run(self, stage, grid):
        with queries.setdefault(stage, raster.ctx.query(time=True)):
            run(self, stage, grid)

    visibility._run = timed_run
    try:
        for r in range(repeats + 2):
            render()
            raster.ctx.finish()
            for stage, query in queries.items():
                if r >= 2:
                    times.setdefault(stage, []).append(query.elapsed * 1e-6)
    finally:
        visibility._run = run
    return {stage: statistics.median(t) for stage, t in times.items()}


def main() -> None:
    import numpy as np

    import hybrid_integrator as hi
    from hybrid_integrator.raster import compute
    from hybrid_integrator.raster.agreement import visibility_agreement

    args = arguments(__doc__)
    names = {getattr(compute, n): n.lower() for n in ("CLEAR", "SMALL_DEPTH", "MEDIUM_GROUPS", "MEDIUM_DEPTH",
                                                       "SMALL_NUMBERS", "MEDIUM_NUMBERS", "TILES")}
    for name, scene, raster, camera, query in rasterizers(args):
        tris = len(raster.geometry.faces)
        fbo = raster.target(camera.width, camera.height)
        for offset in ((0.5, 0.5), (0.13, 0.77)):
            drawn = raster.read_ids(raster.render(camera, offset, "draw")).copy()
            computed = raster.read_ids(raster.render(camera, offset, "compute"))
            rays = {m: visibility_agreement(scene, scene.sensors()[0], hi.rasterize(scene, offset=offset, method=m))
                    for m in ("draw", "compute")}
            print(f"{name}: {tris:,} triangles, offset {offset}: same triangle on {100 * np.mean(drawn == computed):.3f} % "
                  f"of pixels, hit/miss differs on {int(np.sum((drawn == 0) != (computed == 0)))}; the camera rays' "
                  f"triangle: draw {100 * rays['draw'].shape_and_triangle:.3f} %, "
                  f"compute {100 * rays['compute'].shape_and_triangle:.3f} %", flush=True)
        draw_ms, _ = timed_draw(raster, camera, query, args.repeats, "draw")
        compute_ms, _ = timed_draw(raster, camera, query, args.repeats, "compute")
        large, medium = raster.compute_tiers()
        one_pass = raster._compute.one_pass
        stages = {names[k]: round(v, 4) for k, v in
                  stage_times(raster, lambda: raster.render(camera, method="compute"), args.repeats).items()}
        print(f"{name}: GL draw {draw_ms:.3f} ms, compute {compute_ms:.3f} ms ({draw_ms / compute_ms:.2f}x, "
              f"{'one pass' if one_pass else 'two passes'}); large {large:,}, medium {medium:,} triangles; "
              f"stages (ms) {stages}", flush=True)
        if one_pass:
            two = compute.ComputeVisibility(raster.ctx, raster.vertices, raster.faces, tris, one_pass=False)
            for offset in ((0.5, 0.5), (0.13, 0.77)):
                ones = raster.read_ids(raster.render(camera, offset, "compute")).copy()
                twos = raster.read_ids(two.render(camera, offset, fbo))
                print(f"{name}: offset {offset}: one pass = two passes on {int(np.sum(ones == twos)):,} of "
                      f"{ones.size:,} pixels (bit for bit: {np.array_equal(ones, twos)})", flush=True)
            times = []
            for r in range(args.repeats + 2):
                with query:
                    two.render(camera, (0.5, 0.5), fbo)
                raster.ctx.finish()
                if r >= 2:
                    times.append(query.elapsed * 1e-6)
            stages = {names[k]: round(v, 4) for k, v in
                      stage_times(raster, lambda: two.render(camera, (0.5, 0.5), fbo), args.repeats).items()}
            print(f"{name}: two passes {statistics.median(times):.3f} ms against one pass {compute_ms:.3f} ms; "
                  f"stages (ms) {stages}", flush=True)


if __name__ == "__main__":
    main()
