"""A moving camera's next plan made from its raster coverage while the GPU traces, against made
once its counts are in (stop 58's way), in turn in one process (issue 10, stop 59).

Per scene and budget (fractions ``--budgets`` of the all-candidates trace time,
``bench.turn_scene``), along the scene's camera path, three sides render in turn (rounds of
``--block`` frames, the first of each not measured; ``bench.frames_in_turn``, with the host's speed
before each frame): the RT baseline, the budgeted hybrid as it is (``new``: a moving camera plans
the next frame ahead from ``pipeline.raster_coverage``) and the same integrator planning a moving
camera's next frame once the counts are in (``old``: ``HybridRenderer._plans_from`` answering
``None`` where it would answer ``raster``, set before each of its frames through
``frames_in_turn``'s ``before``). Prints each side's median frame, the paired ratios old / new
(> 1: new is faster), RT / new and RT / old, all also by the host's speed
(``bench.paired_ratio_by_host``), and per budgeted side over its measured frames: the relevance
captured, the frames that trace something and that finish within budget + 10 %, and where their
next plans came from.

    python3 docs/results/gpu/issue10/stop59/plan_ab.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 40

It runs at commit 57774bd only: the change it measures was reverted (bcd6c3d), and later trees
have no ``HybridRenderer._plans_from``.
"""
from __future__ import annotations

import collections
import statistics

WARM = 3  # rounds not measured: the budget's three probe frames among them


def main() -> None:
    from hybrid_integrator.bench import (frames_in_turn, paired_ratio, paired_ratio_by_host, turn_arguments,
                                         turn_poses, turn_scene)

    args = turn_arguments(__doc__.splitlines()[0], budgets=(0.25, 0.5, 0.75), block=5).parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    params = dict(args.defines)
    for path in args.scenes:
        ready = turn_scene(str(path), params, turn_poses(args.frames, WARM, args.block))
        renderer = hi.api.renderer(ready.scene)
        plans_from, render = type(renderer)._plans_from, type(renderer).render
        side = [""]
        stats = collections.defaultdict(list)  # per side, every frame's stats (warm-up included)

        def use(name: str) -> None:
            side[0] = name
            if name == "old":
                renderer._plans_from = lambda *a: (lambda r: None if r == "raster" else r)(plans_from(renderer, *a))
            else:
                renderer.__dict__.pop("_plans_from", None)

        def recorded(*a, **k):
            result = render(renderer, *a, **k)
            stats[side[0]].append(result.stats)
            return result

        renderer.render = recorded
        print(f"{ready.name}: all-candidates trace {ready.all_candidates_trace_ms:.3f} ms, "
              f"{len(ready.cameras or [])} poses", flush=True)
        for fraction in args.budgets:
            budget = fraction * ready.all_candidates_trace_ms
            sides = {"rt": {"primary": "raytrace"}, "new": {"budget_ms": budget}, "old": {"budget_ms": budget}}
            stats.clear()
            times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                                   cameras=ready.cameras, before=use, host_speed=True)
            pairs = (("old", "new"), ("rt", "new"), ("rt", "old"))
            ratios = {f"{a} / {b}": paired_ratio(times, a, b, block=args.block) for a, b in pairs}
            by_host = {f"{a} / {b}": paired_ratio_by_host(times, a, b, block=args.block) for a, b in pairs}
            medians = {s: statistics.median(t["total"] for t in times[s]) for s in sides}
            print(f"{ready.name:16s} {fraction:.0%} budget ({budget:.3f} ms): frame ms "
                  + ", ".join(f"{s} {v:.3f}" for s, v in medians.items()), flush=True)
            for key, r in ratios.items():
                h = by_host[key]
                split = ", ".join(f"{label} {h[label]['median']:.3f} ({h[label]['pairs']})" if h[label] else f"{label} -"
                                  for label in ("fast", "slow"))
                print(f"    {key}: {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} rounds); "
                      f"by host: {split}, fastest loop {h['fastest_loop_ms']:.3f} ms", flush=True)
            for name in ("new", "old"):
                measured = stats[name][WARM * args.block:]
                within = [s.times_ms["trace"] <= 1.1 * budget for s in measured]
                print(f"    {name}: relevance captured {statistics.mean(s.relevance_captured for s in measured):.3f}, "
                      f"traces something {statistics.mean(bool(s.selected) for s in measured):.2f}, "
                      f"within budget + 10 % {statistics.mean(within):.2f}, "
                      f"trace {statistics.median(s.times_ms['trace'] for s in measured):.3f} ms, "
                      f"pixels traced {statistics.median(s.pixels_traced for s in measured):.0f}, next plans from "
                      f"{dict(collections.Counter(s.next_plan_from or '-' for s in measured))}", flush=True)
        del renderer.render


if __name__ == "__main__":
    main()
