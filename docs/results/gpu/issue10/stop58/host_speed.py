"""Frames in turn, each classified by the host CPU's speed just before it (issue 10, stop 58).

The device machines' CPUs run at two speeds, about 1.7x apart, and which CPUs are slow changes every
few milliseconds to a second (``core_speed.sh``, ``pin_ab.py``). A frame bound by its host's work (a budgeted frame) then takes as
long as the CPU it lands on allows; a frame bound by the GPU (the RT baseline, the all-candidates
hybrid) hides it. This probe renders the RT baseline, the all-candidates hybrid and budgets of
``--budgets`` × the all-candidates trace time in turn (``bench.frames_in_turn``, rounds of
``--block`` frames per side, the first of each not measured), along the scene's camera path where
it has one, and before each frame times a fixed pure-Python loop (``bench.host_loop_ms``: best of
3 runs of 2,500 additions, ~0.1 ms on a fast CPU; outside the frame's time). (The run of
``outputs/speed.txt`` timed the same loop with a copy of its own, before ``frames_in_turn`` took
``host_speed``.) A frame whose loop took at most
``--fast`` × the run's fastest loop counts as rendered on a fast host, the others on a slow one.
Prints, per side and class, the share of frames and the median frame, and the ratios that
issue 10's items 2 and 4 take (RT / hybrid, RT / budget) by class; and the rank correlation of
loop time and frame time per side.

    python3 docs/results/gpu/issue10/stop58/host_speed.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 80
"""
from __future__ import annotations

import statistics

WARM = 3  # rounds not measured: the budget's three probe frames among them


def rank_correlation(a: list[float], b: list[float]) -> float:
    import numpy as np

    ra, rb = (np.argsort(np.argsort(x)) for x in (a, b))
    return float(np.corrcoef(ra, rb)[0, 1])


def main() -> None:
    from hybrid_integrator.bench import FAST_HOST, fast_hosts, frames_in_turn, turn_arguments, turn_poses, turn_scene

    parser = turn_arguments(__doc__.splitlines()[0], budgets=(0.25, 0.5), block=5)
    parser.add_argument("--fast", type=float, default=FAST_HOST, help="a fast host's loop: at most this × the fastest")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    params = dict(args.defines)
    for path in args.scenes:
        ready = turn_scene(str(path), params, turn_poses(args.frames, WARM, args.block))
        sides = {"rt": {"primary": "raytrace"}, "hybrid": {}}
        sides |= {f"{b:.0%}": {"budget_ms": b * ready.all_candidates_trace_ms} for b in args.budgets}
        times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                               cameras=ready.cameras, host_speed=True)
        loops = {name: [t["host_loop"] for t in times[name]] for name in sides}
        totals = {name: [t["total"] for t in times[name]] for name in sides}
        classes, fastest = fast_hosts(list(loops.values()), args.fast)
        fast = dict(zip(loops, classes))
        print(f"{ready.name}: all-candidates trace {ready.all_candidates_trace_ms:.3f} ms; fastest loop "
              f"{fastest:.3f} ms, a fast host's at most {args.fast * fastest:.3f}", flush=True)
        medians = {}
        for name in sides:
            for label, keep in (("fast", True), ("slow", False)):
                values = [t for t, f in zip(totals[name], fast[name]) if f == keep]
                medians[name, label] = statistics.median(values) if values else float("nan")
            loop_median = statistics.median(loops[name])
            print(f"  {name:7s} frames {len(totals[name])}, on a fast host {sum(fast[name]) / len(fast[name]):.0%}; "
                  f"median frame fast {medians[name, 'fast']:.3f} ms, slow {medians[name, 'slow']:.3f} ms, all "
                  f"{statistics.median(totals[name]):.3f}; median loop {loop_median:.3f} ms; rank correlation loop / "
                  f"frame {rank_correlation(loops[name], totals[name]):+.2f}", flush=True)
        for name in sides:
            if name != "rt":
                print(f"  RT / {name}: fast host {medians['rt', 'fast'] / medians[name, 'fast']:.3f}, slow host "
                      f"{medians['rt', 'slow'] / medians[name, 'slow']:.3f}, all "
                      f"{statistics.median(totals['rt']) / statistics.median(totals[name]):.3f}", flush=True)


if __name__ == "__main__":
    main()
