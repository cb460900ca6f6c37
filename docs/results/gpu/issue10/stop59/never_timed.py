"""A budget whose trace is timed only while its cost model calibrates (``timing_interval`` far
beyond the sequence), against one timed on every frame and every 4th (issue 10, stop 59): what
each frame selects, its predicted and (where timed) measured trace, and its total, for the
Armadillo at 50 % of its all-candidates trace time, a still camera.

    python3 docs/results/gpu/issue10/stop59/never_timed.py scenes/armadillo_glass.xml --variant cuda_ad_rgb -D …
"""
from __future__ import annotations

import statistics


def main() -> None:
    from hybrid_integrator.bench import turn_arguments, turn_scene

    args = turn_arguments(__doc__.splitlines()[0]).parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    for path in args.scenes:
        ready = turn_scene(str(path), dict(args.defines), 2)
        for fraction in args.budgets:
            budget = fraction * ready.all_candidates_trace_ms
            for name, props in (("every frame", {}), ("every 4th", {"stage_times": False}),
                                ("calibration only", {"stage_times": False, "timing_interval": 10 ** 6})):
                integrator = hi.api._integrator({"budget_ms": budget, **props})
                stats = [integrator.render_result(ready.scene, seed=k, spp=1, layers=False).stats for k in range(args.frames)]
                model = integrator.state.cost_model
                print(f"{ready.name} {fraction:.0%} ({budget:.3f} ms), timed {name}: median frame "
                      f"{statistics.median(s.times_ms['total'] for s in stats[5:]):.3f} ms; model launch {model.launch_ms:.3f}, "
                      f"rates {', '.join(f'{k} {v:.2e}' for k, v in model.rates.items())}, margin {model.margin:.2f}", flush=True)
                for k in (0, 1, 2, 3, 4, 5, 10, args.frames - 1):
                    s = stats[k]
                    print(f"    frame {k}: selected {s.selected}, predicted {s.predicted_trace_ms:.3f}, "
                          f"trace {s.times_ms['trace']:.3f}, total {s.times_ms['total']:.3f}", flush=True)


if __name__ == "__main__":
    main()
