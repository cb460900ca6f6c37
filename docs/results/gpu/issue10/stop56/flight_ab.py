"""Budgeted frames in flight, against one at a time and against the RT baseline, in turn (issue 10, stop 56).

With ``diffs/budget_in_flight.diff`` applied (``git apply``, as the runs did; tried and reverted) a
budgeted frame with ``frames_in_flight=2`` learns in the frame itself once its trace is done (its
counts, its stages' history, the next plan) and returns without waiting for its denoiser
(``inflight.py``); without it, a budget makes every frame one at a time. Per scene and budget
(fractions ``--budgets`` of the all-candidates hybrid's median trace time, ``bench.turn_scene``),
four integrators render in turn (``bench.frames_in_turn``, rounds of ``--block`` frames per side,
the first of each not measured, as the bench's Gain with frames in flight): the RT baseline and the
budgeted hybrid, each one at a time (``rt``, ``budget``) and with two frames in flight (``rt2``,
``budget2``). A frame's time: one at a time its wall time; in flight the GPU's period from the
frame before's end to its own (``FrameSpan``). Prints each side's median frame time, the paired
ratios RT / budget one at a time and in flight, budget / budget2 (> 1: in flight is faster), and
the share of each budgeted side's frames whose trace took at most the budget + 10 % (item 4).
A scene with a camera path (``NAME_path.json``: the 226 objects) renders along it, a pose per
frame (``bench.frames_in_turn``; the runs of ``outputs/flight.txt`` had one pose per round).

    python3 docs/results/gpu/issue10/stop56/flight_ab.py SCENE... --variant cuda_ad_rgb $D --frames 40
"""
from __future__ import annotations

WARM = 3  # rounds not measured: the budget's three probe frames among them


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, turn_arguments, turn_poses, turn_scene

    args = turn_arguments(__doc__.splitlines()[0], budgets=(0.25, 0.5, 0.75), block=5).parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    params = dict(args.defines)
    for path in args.scenes:
        ready = turn_scene(str(path), params, turn_poses(args.frames, WARM, args.block))
        print(f"{ready.name}: all-candidates trace {ready.all_candidates_trace_ms:.3f} ms", flush=True)
        for fraction in args.budgets:
            budget = fraction * ready.all_candidates_trace_ms
            rt, budgeted = {"primary": "raytrace"}, {"budget_ms": budget}
            sides = {"rt": rt, "budget": budgeted, "rt2": dict(rt, frames_in_flight=2),
                     "budget2": dict(budgeted, frames_in_flight=2)}
            times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                                   cameras=ready.cameras)
            one, two, gain = (paired_ratio(times, a, b, block=args.block)
                              for a, b in (("rt", "budget"), ("rt2", "budget2"), ("budget", "budget2")))
            within = {s: sum(t["trace"] <= 1.1 * budget for t in times[s]) / len(times[s]) for s in ("budget", "budget2")}
            untimed = sum(t["trace"] != t["trace"] for t in times["budget2"])  # NaN: stages not timed (must be 0)
            print(f"{ready.name:16s} {fraction:.0%} budget ({budget:.3f} ms): one at a time RT {one['rt_ms']:.3f} / "
                  f"budget {one['budget_ms']:.3f} ms = {one['median']:.3f} [{one['q25']:.3f}, {one['q75']:.3f}]; "
                  f"in flight RT {two['rt2_ms']:.3f} / budget {two['budget2_ms']:.3f} ms = {two['median']:.3f} "
                  f"[{two['q25']:.3f}, {two['q75']:.3f}]; budget one at a time / in flight {gain['median']:.3f} "
                  f"[{gain['q25']:.3f}, {gain['q75']:.3f}] ({gain['pairs']} rounds); within budget + 10 %: one at "
                  f"a time {within['budget']:.0%}, in flight {within['budget2']:.0%}; untimed {untimed}", flush=True)


if __name__ == "__main__":
    main()
