"""The fixed cost of one ray-tracing call on the many-object scene (issue 4).

Times (medians, backend synchronized) ``trace.trace_effects`` with ``freeze=True`` for 1, 100,
1 000 and 10 000 traced pixels of one primary-hit buffer, then a frozen function that does nothing
but take the scene as an argument (``lambda scene, x: x + 1``) against the same without the scene:
how much of a call's cost is Dr.Jit replaying a frozen function over the scene's variables.

    python scripts/trace_overhead.py -o docs/results/cpu/trace_overhead
"""
from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def median_ms(fn, repeats: int) -> float:
    import drjit as dr

    fn()  # compiles or records
    fn()  # a frozen function may record again with its literals made opaque
    times = []
    for _ in range(repeats):
        dr.sync_thread()
        start = time.perf_counter()
        dr.eval(fn())
        dr.sync_thread()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes/many_objects.xml")
    parser.add_argument("--repeats", type=int, default=9)
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.primary import camera_rays, shape_indices
    from hybrid_integrator.raster.camera import RasterCamera
    from hybrid_integrator.raster.context import machine
    from hybrid_integrator.trace import trace_effects

    scene = hi.load_scene(args.scene, resx=320, resy=180)
    sensor = scene.sensors()[0]
    ray = camera_rays(sensor, RasterCamera.from_sensor(sensor), (0.5, 0.5))
    si = scene.ray_intersect(ray)
    valid = si.is_valid()
    index = shape_indices(scene, si.shape, valid)
    dr.eval(ray, si, valid, index)
    hits = np.nonzero(np.array(valid))[0]
    effects = ("shadow", "reflection", "refraction")
    rows = {}
    for n in (1, 100, 1000, 10000):
        chosen = np.zeros(dr.width(valid), dtype=bool)
        chosen[hits[:n]] = True
        traced = mi.Bool(chosen)
        rows[n] = median_ms(lambda: trace_effects(scene, ray, si, traced, effects, -1, 5, False, seed=1,
                                                  shape_index=index, n_shapes=len(scene.shapes()), freeze=True)[0],
                            args.repeats)
    x = dr.arange(mi.Float, 10)
    with_scene, without = dr.freeze(lambda scene, x: x + 1), dr.freeze(lambda x: x + 1)
    replay = {"with_scene_ms": median_ms(lambda: with_scene(scene, x), args.repeats),
              "without_scene_ms": median_ms(lambda: without(x), args.repeats)}
    report = {"command": f"python scripts/trace_overhead.py --variant {args.variant} --repeats {args.repeats}",
              "machine": machine(), "shapes": len(scene.shapes()),
              "trace_ms_by_pixels": rows, "frozen_replay": replay}
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.with_suffix(".json").write_text(json.dumps(report, indent=2))
    print(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
