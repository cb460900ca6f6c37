"""Why the 50 % frame is slower rendered in turn with the RT baseline than in a run of its own
(issue 10, stop 54).

``scripts/budget_benchmark.py`` on the H200 gave the 50 % frame (nested) 4.4-4.7 ms in a run of
its own along the 226 objects' camera path, and 5.1-5.5 ms rendered frame by frame in turn with
the RT baseline (``bench.frames_in_turn``), whose frames took the same time either way. This
probe renders, in one process, along the same path (``budget_benchmark.path_cameras``):

- ``alone``: the 50 % frame, frame after frame (as ``render_sequence``);
- ``turn rt``: the 50 % frame and the RT baseline in turn (a frame each per pose, the order
  rotating, as ``frames_in_turn``);
- ``turn twin``: the 50 % frame in turn with a second 50 % integrator of its own (same settings
  but ``raster_ahead="off"``, so that it takes nothing drawn ahead for the first).

and prints per arrangement the 50 % frame's median total, its device stage times, its host phases
(``FrameStats.host_ms``), and how many of its passes were drawn ahead or discarded. A host phase
that grows in turn with unchanged work is the host's caches: the other frame's code and data
between two of its frames.

    python3 docs/results/gpu/issue10/stop54/interleave.py --variant cuda_ad_rgb --resx 1280 --resy 720
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))

WARM = 5  # the budget's three probe frames, then two


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes/many_objects.xml")
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    parser.add_argument("--repeat", type=int, default=2, help="rounds of the three arrangements")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from budget_benchmark import path_scene
    from hybrid_integrator.api import _integrator, finish, posed
    from hybrid_integrator.raster.camera import camera_pose

    hi.register()
    scene, cameras = path_scene(hi, args.scene, WARM + args.frames, resx=args.resx, resy=args.resy)
    poses = [camera_pose(c) for c in cameras]
    all_ms = statistics.median(f.stats.times_ms["trace"]
                               for f in hi.render_sequence(scene, cameras, spp=1, layers=False))
    hi.render_sequence(scene, cameras[:3], spp=1, layers=False, primary="raytrace")
    budget = {"budget_ms": 0.5 * all_ms}

    def arrangement(sides: dict[str, dict]) -> list:
        """The first side's measured frames' stats, each side rendering every pose in turn."""
        integrators = {name: _integrator(dict(props)) for name, props in sides.items()}
        order, kept = list(sides), []
        with posed(scene.sensors()[0]) as place:
            for k in range(len(poses)):
                place(poses[k])
                upcoming = poses[k + 1] if k + 1 < len(poses) else None
                for name in order:
                    result = integrators[name].render_result(scene, seed=k, spp=1, layers=False, next_camera=upcoming)
                    if name == "budget" and k >= WARM:
                        kept.append(result.stats)
                order = order[1:] + order[:1]
        finish(scene)
        return kept

    arrangements = {"alone": {"budget": budget},
                    "turn rt": {"budget": budget, "rt": {"primary": "raytrace"}},
                    "turn twin": {"budget": budget, "twin": {**budget, "raster_ahead": "off"}}}
    print(f"{args.scene.name}, {args.variant}, {args.resx}x{args.resy}, 50 % budget {0.5 * all_ms:.2f} ms, "
          f"{args.frames} frames per arrangement; medians", flush=True)
    for r in range(args.repeat):
        for name, sides in arrangements.items():
            stats = arrangement(sides)
            med = lambda get: statistics.median(get(s) for s in stats)  # noqa: E731
            stages = {k: round(med(lambda s: s.times_ms.get(k, 0.0)), 3)
                      for k in ("gl", "raster", "lighting", "trace", "compose", "denoise")}
            host = {k: round(med(lambda s: s.host_ms[k]), 3) for k in stats[0].host_ms}
            print(f"[{r}] {name:9s} total {med(lambda s: s.times_ms['total']):.3f} ms; drawn ahead "
                  f"{sum(s.raster_ahead for s in stats)}, discarded {sum(s.raster_discarded for s in stats)}; "
                  f"relevance {med(lambda s: s.relevance_captured):.3f}\n    device {stages}\n    host {host}", flush=True)


if __name__ == "__main__":
    main()
