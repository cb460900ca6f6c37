"""The learnt ambient table's fallback for objects never traced, compared on fixed selections
(issue 10, stop 60; run on the CPU).

On eight poses of the 226 objects' camera path (every 5th of 40), two fixed sets of traced objects
(``candidates``: ten objects, or the floor alone) render ``--frames`` frames each, learning the
ambient term as they go, with each fallback for the objects never traced: ``off``
(``learn_ambient=false``), ``mean`` (before this stop: ``turn_error.mean_fallback``), ``median``,
and ``median+`` (now: the median, never below zero: ``lighting.ambient_table``). Prints each
pose's FLIP of the last frame (denoised, unless ``--no-denoise``) against ``path`` at
``--gt-spp``, and the learnt rows of the ten objects (the largest and smallest E, their mean and
median), then the mean FLIP over the poses.

    .venv/bin/python docs/results/gpu/issue10/stop60/ambient_fallback.py --resx 320 --resy 180
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[5]
SETS = {"ten objects": "floor,box_7_7,box_6_5,box_8_6,sphere_6_6,sphere_8_7,sphere_2_7,sphere_4_7,sphere_4_5,box_2_9",
        "the floor alone": "floor"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    parser.add_argument("--frames", type=int, default=8)
    parser.add_argument("--gt-spp", type=int, default=64)
    parser.add_argument("--denoise", action=argparse.BooleanOptionalAction, default=True)
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import pipeline
    from hybrid_integrator.api import _integrator, posed
    from hybrid_integrator.bench import load_bench_scene, path_cameras
    from hybrid_integrator.compare import render_path
    from hybrid_integrator.metrics import flip_map
    from hybrid_integrator.raster.camera import camera_pose

    sys.path.insert(0, str(Path(__file__).parent))
    from turn_error import fallback_table, mean_fallback

    shipped = pipeline.ambient_table
    # median: negative values passed on
    fallbacks = {"off": shipped, "mean": mean_fallback, "median": fallback_table(lambda rows: np.median(rows, axis=0)),
                 "median+": shipped}
    hi.register()
    spec = str(ROOT / "scenes" / "many_objects.xml")
    scene, _ = load_bench_scene(spec, {"resx": str(args.resx), "resy": str(args.resy)})
    cameras = path_cameras(spec, 40)
    errors: dict[tuple[str, str], list[float]] = {}
    with posed(scene.sensors()[0]) as place:
        for at in range(0, 40, 5):
            place(camera_pose(cameras[at]))
            truth = np.array(render_path(scene, args.gt_spp, -1, seed=7))[..., :3]
            for set_name, traced in SETS.items():
                for name, table in fallbacks.items():
                    pipeline.ambient_table = table
                    integrator = _integrator({"candidates": traced, "learn_ambient": name != "off",
                                              "denoise": args.denoise})
                    for k in range(args.frames):
                        result = integrator.render_result(scene, seed=k, spp=1, layers=False)
                    errors.setdefault((set_name, name), []).append(flip_map(np.array(result.image)[..., :3], truth)[1])
                    learnt = np.asarray(integrator.state.ambient)
                    rows = learnt[np.isfinite(learnt).all(axis=1)]
                    if set_name == next(iter(SETS)) and name == "median+" and len(rows):
                        print(f"pose {at}, {set_name}: {len(rows)} learnt rows, the largest E {rows.max(axis=0).round(2)}, "
                              f"the smallest {rows.min(axis=0).round(2)}; their mean {rows.mean(axis=0).round(2)}, "
                              f"median {np.median(rows, axis=0).round(2)}", flush=True)
            pipeline.ambient_table = shipped
            print(f"pose {at}: " + ", ".join(f"{s} / {n} {v[-1]:.3f}" for (s, n), v in errors.items()), flush=True)
    for (set_name, name), values in errors.items():
        print(f"{set_name:16s} {name:8s} mean FLIP over {len(values)} poses {np.mean(values):.4f}")


if __name__ == "__main__":
    main()
