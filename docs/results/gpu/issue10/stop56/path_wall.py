"""Wall time per frame along a camera path: the sensor moved by ``params.update()`` or by ``place_sensor`` (issue 10, stop 56).

``api.posed`` moves the sensor between the frames of a camera path (``hi.render_sequence``). Until
stop 56 it called Mitsuba's ``params.update()``, whose read-back of the new transform waits for all
the work queued on the device (``pose_wait.py``), so with two frames in flight the next frame could
not be issued while the GPU finished the last; now it calls ``raster.camera.place_sensor``, which
waits for nothing. Per scene with a path (``NAME_path.json``), the hybrid and its RT baseline (all
candidates, denoised, 1 spp), each one frame at a time and two in flight, each with the sensor
moved the old way (``update``) and the new (``place``), render the path in turn, ``--blocks``
blocks of ``--frames`` frames each after a warm-up. A block's wall time runs from its first call
to the synchronization after its last frame's times are read (``render_sequence`` reads them),
the pose sets between frames included. With ``--budgets`` (fractions of the all-candidates trace
time, ``bench.turn_scene``), the budgeted hybrid too, one at a time and two in flight, the sensor
moved the new way (a budget renders one frame at a time whatever ``frames_in_flight`` says, unless
``diffs/budget_in_flight.diff`` is applied). Prints per side the median wall ms per frame of the
blocks.

    python3 docs/results/gpu/issue10/stop56/path_wall.py scenes/many_objects.xml --variant cuda_ad_rgb -D resx=1280 -D resy=720
"""
from __future__ import annotations

import statistics
import time


def main() -> None:
    from hybrid_integrator.bench import turn_arguments

    parser = turn_arguments(__doc__.splitlines()[0], budgets=())
    parser.add_argument("--blocks", type=int, default=3)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import api
    from hybrid_integrator.bench import turn_scene

    placed = api.place_sensor

    def updated(sensor, matrix) -> None:  # the way before stop 56
        params = mi.traverse(sensor)
        params["to_world"] = mi.ScalarTransform4f(matrix)
        params.update()

    hi.register()
    for path in args.scenes:
        ready = turn_scene(str(path), dict(args.defines), args.frames)
        scene, name, cameras = ready.scene, ready.name, ready.cameras
        sides = {(p, n, how): dict(primary=p, frames_in_flight=n)
                 for p in ("raster", "raytrace") for n in (1, 2) for how in ("update", "place")}
        sides |= {(f"{b:.0%}", n, "place"): dict(budget_ms=b * ready.all_candidates_trace_ms, frames_in_flight=n)
                  for b in args.budgets for n in (1, 2)}
        wall = {k: [] for k in sides}
        for block in range(args.blocks + 1):  # the first: warm-up
            for key, props in sides.items():
                api.place_sensor = placed if key[2] == "place" else updated
                dr.sync_thread()
                start = time.perf_counter()
                hi.render_sequence(scene, cameras, seed=block, layers=False, **props)
                dr.sync_thread()
                if block:
                    wall[key].append((time.perf_counter() - start) * 1e3 / len(cameras))
        api.place_sensor = placed
        for (primary, n, how), values in wall.items():
            print(f"{name:14s} {primary:8s} {n} in flight, sensor by {how:6s}: {statistics.median(values):.3f} ms "
                  f"per frame (blocks {', '.join(f'{v:.3f}' for v in values)})", flush=True)


if __name__ == "__main__":
    main()
