"""What a budgeted frame would gain if its trace's device time came without Dr.Jit's kernel
history (issue 10, stop 59).

A budgeted frame's cost model learns the trace stage's device time from Dr.Jit's kernel history,
the one clock inside a frozen replay. The history costs the frame's host a pair of CUDA events per
launch in the replay, before the GPU reaches the trace, and their readout (``history_cost.py``).
Here, per scene and budget (fractions ``--budgets`` of the all-candidates trace time), along the
scene's camera path, three sides render in turn (rounds of ``--block`` frames, the first of each
not measured; ``bench.frames_in_turn``): the RT baseline, the budgeted hybrid with its stages timed
on every frame (``timed``: ``stage_times`` on), and the same without stage times, so that it times
its trace only on every ``--every``-th frame (``sampled``: ``stage_times=false``,
``timing_interval``; between them the history is off, the cost model learns nothing, and the
frame's trace time is NaN). Prints each side's median frame, the sampled side's untimed frames
apart, the paired ratios, and over the timed frames of each budgeted side the share within budget
+ 10 %. (Its first version, at commit bcb53e5, switched the package's timing per frame itself:
the package had no such setting then.)

    python3 docs/results/gpu/issue10/stop59/untimed_budget.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 40
"""
from __future__ import annotations

import math
import statistics

WARM = 3  # rounds not measured: the budget's three probe frames among them


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, paired_ratio_by_host, turn_arguments, turn_budgets

    parser = turn_arguments(__doc__.splitlines()[0], budgets=(0.25, 0.5, 0.75), block=5)
    parser.add_argument("--every", type=int, default=4, help="the sampled side times every N-th frame")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    for ready, fraction, budget in turn_budgets(args, WARM):
        sides = {"rt": {"primary": "raytrace"}, "timed": {"budget_ms": budget},
                 "sampled": {"budget_ms": budget, "stage_times": False, "timing_interval": args.every}}
        times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                               cameras=ready.cameras, host_speed=True)
        untimed = [t["total"] for t in times["sampled"] if math.isnan(t["trace"])]
        print(f"{ready.name:16s} {fraction:.0%} budget ({budget:.3f} ms): frame ms "
              + ", ".join(f"{s} {statistics.median(t['total'] for t in times[s]):.3f}" for s in sides)
              + f", sampled's untimed frames {statistics.median(untimed):.3f} ({len(untimed)})", flush=True)
        for a, b in (("timed", "sampled"), ("rt", "timed"), ("rt", "sampled")):
            r, h = paired_ratio(times, a, b, block=args.block), paired_ratio_by_host(times, a, b, block=args.block)
            split = ", ".join(f"{label} {h[label]['median']:.3f} ({h[label]['pairs']})" if h[label] else f"{label} -"
                              for label in ("fast", "slow"))
            print(f"    {a} / {b}: {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} rounds); by host: {split}",
                  flush=True)
        for name in ("timed", "sampled"):
            traced = [t["trace"] for t in times[name] if not math.isnan(t["trace"])]
            if not traced:  # none of its measured frames timed (a long --every)
                print(f"    {name}: no timed frame", flush=True)
                continue
            print(f"    {name}: within budget + 10 % {statistics.mean(x <= 1.1 * budget for x in traced):.2f} "
                  f"of {len(traced)} timed frames, trace {statistics.median(traced):.3f} ms", flush=True)


if __name__ == "__main__":
    main()
