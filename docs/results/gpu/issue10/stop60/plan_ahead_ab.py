"""A moving camera's budgeted frame planned ahead, from the view two frames old, against planned
once its counts are in: time, relevance and image error (issue 10, stop 60).

A budgeted frame on the lent H200s is bound by its host. With a moving camera it waits for its
counts, then plans the next frame (``HybridRenderer._account``); a still camera's frame plans while
its GPU traces (``_plan_ahead``, stop 53). ``plan_ahead="always"`` plans a moving camera's next
frame there too, from the last frame's coverage (the view two frames old). Stop 53 measured that
variant by the relevance it captured (6-13 % less) and its time (0.4-0.8 ms shorter); not by the
image. Here, per scene and budget (fractions ``--budgets`` of the all-candidates trace time), along
the scene's camera path in turn by rounds of ``--block`` frames (``bench.frames_in_turn``, the
first frame of each round not measured), three sides as a renderer ships them (``stage_times``
off): the RT baseline (``rt``), the budget planned as by default (``still``) and with
``plan_ahead="always"`` (``always``). Prints each side's median frame and the paired ratios (also
split by the host's speed before each frame: ``bench.paired_ratio_by_host``), the
relevance captured and the pixels traced (means over the measured frames), the timed frames within
budget + 10 %, and the image error of the third frame of every measured round (every side renders
the same pose with the same seed) against Mitsuba's ``path`` at ``--gt-spp`` from that pose: mean
FLIP and relative MSE per side, and the paired FLIP difference always - still.

    python3 docs/results/gpu/issue10/stop60/plan_ahead_ab.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 40
"""
from __future__ import annotations

import math
import statistics

import numpy as np

WARM = 3
KEPT = 2  # the frame of each round whose image is measured against the reference


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, paired_ratio_by_host, turn_arguments, turn_budgets

    parser = turn_arguments(__doc__.splitlines()[0], budgets=(0.25, 0.5, 0.75), block=5)
    parser.add_argument("--gt-spp", type=int, default=256)
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import posed
    from hybrid_integrator.compare import render_path
    from hybrid_integrator.metrics import errors_in_parallel
    from hybrid_integrator.raster.camera import camera_pose

    hi.register()
    tests, keys = [], []  # images measured, and (scene, budget, side, pose) for each
    truths: dict[tuple[str, int], np.ndarray] = {}
    for ready, fraction, budget in turn_budgets(args, WARM):
        base = {"budget_ms": budget, "stage_times": False}
        sides = {"rt": {"primary": "raytrace", "stage_times": False}, "still": base,
                 "always": {**base, "plan_ahead": "always"}}
        stats: dict[str, list] = {s: [] for s in sides}

        def after(name, at, result):
            stats[name].append(result.stats)
            if at % args.block == KEPT:
                tests.append(np.array(result.image)[..., :3])
                keys.append((ready.name, fraction, name, at))
                truths.setdefault((ready.name, at), None)

        times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                               cameras=ready.cameras, after=after, host_speed=True)
        print(f"{ready.name:16s} {fraction:.0%} budget ({budget:.3f} ms): frame ms "
              + ", ".join(f"{s} {statistics.median(t['total'] for t in times[s]):.3f}" for s in sides), flush=True)
        for a, b in (("still", "always"), ("rt", "still"), ("rt", "always")):
            r, h = paired_ratio(times, a, b, block=args.block), paired_ratio_by_host(times, a, b, block=args.block)
            split = ", ".join(f"{label} {h[label]['median']:.3f} ({h[label]['pairs']})" if h[label] else f"{label} -"
                              for label in ("fast", "slow"))
            print(f"    {a} / {b}: {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} rounds); by host: {split}",
                  flush=True)
        for name in ("still", "always"):
            s = stats[name]
            traced = [t["trace"] for t in times[name] if not math.isnan(t["trace"])]
            within = statistics.mean(x <= 1.1 * budget for x in traced) if traced else math.nan
            print(f"    {name}: relevance captured {statistics.mean(f.relevance_captured for f in s):.3f}, "
                  f"pixels traced {statistics.mean(f.pixels_traced for f in s):.0f}, "
                  f"within budget + 10 % {within:.2f} of {len(traced)} timed frames", flush=True)
        if ready.cameras is not None:
            with posed(ready.scene.sensors()[0]) as place:
                for (scene_name, at), image in truths.items():
                    if scene_name == ready.name and image is None:
                        place(camera_pose(ready.cameras[at]))
                        truths[scene_name, at] = np.array(render_path(ready.scene, args.gt_spp, -1, seed=10_000 + at))[..., :3]
    errors = errors_in_parallel(tests, [truths[k[0], k[3]] for k in keys])
    by = {k: e for k, e in zip(keys, errors)}
    print("image error against path at", args.gt_spp, "spp, the third frame of each measured round:")
    for scene_name, fraction in dict.fromkeys((k[0], k[1]) for k in keys):
        row = {side: [e for k, e in by.items() if k[:3] == (scene_name, fraction, side)] for side in ("rt", "still", "always")}
        poses = sorted({k[3] for k in by if k[:2] == (scene_name, fraction) and k[2] == "still"})
        diff = [by[scene_name, fraction, "always", p].flip - by[scene_name, fraction, "still", p].flip for p in poses
                if (scene_name, fraction, "always", p) in by]
        print(f"    {scene_name:16s} {fraction:.0%}: mean FLIP / rel. MSE "
              + ", ".join(f"{side} {statistics.mean(e.flip for e in v):.4f} / {statistics.mean(e.rel_mse for e in v):.4f}"
                          for side, v in row.items() if v)
              + f"; always - still FLIP per pose: mean {statistics.mean(diff):+.4f}, "
                f"[{min(diff):+.4f}, {max(diff):+.4f}] ({len(diff)} poses)", flush=True)


if __name__ == "__main__":
    main()
