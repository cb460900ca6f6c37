"""Probe: what the budget's misses on the 226-object camera path are made of. Renders the path
with every candidate, then at ``--fraction`` of its median trace time, and prints for each frame
after the probes that missed its budget + 10 % or traced over 1.5× its planned rays: its trace
and planned times, rays, and per selected object its pixels in the last frame (what the plan used)
and in this one, and its learnt rays per pixel by kind before and after the frame (NaN: never
traced before).

    python scripts/budget_misses.py --resx 640 --resy 360
"""
from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from budget_benchmark import PROBES, path_scene  # scripts/ is on sys.path when a script runs

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--fraction", type=float, default=0.25)
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    args = parser.parse_args()

    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import _integrator, camera_pose, posed

    hi.register()
    scene, cameras = path_scene(hi, ROOT / "scenes/many_objects.xml", args.frames, resx=args.resx, resy=args.resy)
    names = hi.scene_objects(scene).names
    sensor = scene.sensors()[0]

    def sequence(**props):
        integrator, out = _integrator(dict(props)), []
        for k, camera in enumerate(cameras):
            place(camera_pose(camera))
            state = integrator.state
            before = (state.rays_per_pixel.copy(), None if state.coverage is None else state.coverage.pixels.copy())
            stats = integrator.render_result(scene, sensor=sensor, seed=k, spp=1, layers=False).stats
            out.append((stats, *before, integrator.state.rays_per_pixel.copy(), integrator.state.coverage.pixels.copy()))
        return out

    with posed(sensor) as place:
        budget = args.fraction * statistics.median(f[0].times_ms["trace"] for f in sequence())
        print(f"budget {budget:.2f} ms ({args.fraction:.0%} of the all-candidates trace), {args.resx}x{args.resy}")
        for k, (s, rays_before, pixels_before, rays_after, pixels_now) in enumerate(sequence(budget_ms=budget, selection="greedy")):
            ratio = s.secondary_rays / max(s.predicted_rays, 1)
            if k < PROBES or (s.times_ms["trace"] <= 1.1 * budget and ratio <= 1.5):
                continue
            print(f"frame {k}: trace {s.times_ms['trace']:.2f} ms (planned {s.predicted_trace_ms:.2f}), rays "
                  f"{s.secondary_rays} (planned {s.predicted_rays}, {ratio:.2f}x)")
            for name in s.selected:
                i = names.index(name)
                learnt = [np.round(t[i], 2) if i < len(t) else "never" for t in (rays_before, rays_after)]
                print(f"    {name:12s} pixels {int(pixels_before[i]) if pixels_before is not None else '-':>6} -> "
                      f"{int(pixels_now[i]):6d}   rays/pixel {learnt[0]} -> {learnt[1]}")


if __name__ == "__main__":
    main()
