"""Budgeted frames with their stage times parsed in the next frame: before and after, in turn (issue 10, stop 55).

A budgeted, denoised frame past the cost model's probes leaves the parsing of its kernel history
to the next frame (``HybridRenderer._reads_late``, ``_read_late``). Per scene and budget (fractions
``--budgets`` of the all-candidates hybrid's median trace time), two integrators of the same
settings render in turn (``bench.frames_in_turn``, rounds of ``--block`` frames per side, the
first of each round not measured: it reads the other side's last frame late): ``before``, whose
frames read their times at once (``_reads_late`` refused in this process), and ``after``, the
package's code. Prints each side's median frame time, the paired ratio before / after (> 1: the
late readout's frames are shorter) and each side's share of frames whose trace took at most the
budget + 10 % (item 4). A scene with a camera path (``NAME_path.json``: the 226 objects) renders
along it.

Tried and reverted: apply ``diffs/late_readout.diff`` first (``git apply``), as the runs did.

    python3 docs/results/gpu/issue10/stop55/late_ab.py SCENE... --variant cuda_ad_rgb $D --frames 80 --budgets 0.25 0.5
"""
from __future__ import annotations

WARM = 3  # rounds not measured: the budget's three probe frames among them


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, turn_arguments, turn_poses, turn_scene

    args = turn_arguments(__doc__.splitlines()[0], budgets=(0.25, 0.5), block=3).parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.pipeline import HybridRenderer

    hi.register()
    reads_late, side = HybridRenderer._reads_late, {"late": True}
    HybridRenderer._reads_late = staticmethod(lambda *a: side["late"] and reads_late(*a))

    def before(name: str) -> None:  # the side's frames read their stage times late, or at once
        side["late"] = name == "after"

    params = dict(args.defines)
    for path in args.scenes:
        ready = turn_scene(str(path), params, turn_poses(args.frames, WARM, args.block))
        scene, cameras, all_ms = ready.scene, ready.cameras, ready.all_candidates_trace_ms
        for fraction in args.budgets:
            budget = fraction * all_ms
            times = frames_in_turn(scene, {"before": {"budget_ms": budget}, "after": {"budget_ms": budget}},
                                   args.frames, 1, 0, warmup=WARM, before=before, block=args.block,
                                   cameras=cameras)
            r = paired_ratio(times, "before", "after", block=args.block)
            within = {s: sum(t["trace"] <= 1.1 * budget for t in times[s]) / len(times[s]) for s in times}
            late = sum(t["trace"] != t["trace"] for t in times["after"])  # NaN: never read (must be 0)
            print(f"{path.stem:16s} {fraction:.0%} budget ({budget:.3f} ms): before {r['before_ms']:.3f} ms, "
                  f"after {r['after_ms']:.3f} ms, before / after {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] "
                  f"({r['pairs']} pairs); within budget + 10 %: before {within['before']:.0%}, after "
                  f"{within['after']:.0%}; unread {late}", flush=True)


if __name__ == "__main__":
    main()
