"""Stop 69 probe: what a budget buys, with and without the part of an object it can afford.

For each scene: the all-candidates trace stage's device time (median), then at budgets of 25, 50
and 75 % of it, a still camera's frames (``hi.render_sequence``, 1 spp, ``stage_times=False`` as
the bench times them), with ``partial_objects`` off (an object is traced whole or not at all) and
on (the budget left after the selection buys a part of the next object's pixels, pipeline.py).
With ``--rt``, the RT baseline's frames too (``primary="raytrace"``, timed as the budgets' frames).
Prints per budget and mode the median frame and trace times, the timed frames within budget,
the pixels traced and the objects traced in part, and the error of the last frames against
``path`` at ``--gt-spp`` (FLIP, mean over the last ``--error-frames``; ``metrics.py``).

    python3 docs/results/gpu/issue10/stop69/partial_probe.py --variant cuda_ad_rgb $D scenes/armadillo_glass.xml
"""
import argparse
import math
import statistics

import mitsuba as mi

def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("-D", action="append", default=[])
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--error-frames", type=int, default=3)
    parser.add_argument("--gt-spp", type=int, default=1024)
    parser.add_argument("--budgets", type=float, nargs="+", default=[0.25, 0.5, 0.75])
    parser.add_argument("--modes", nargs="+", default=["whole", "partial"])
    parser.add_argument("--effects", default=None)
    parser.add_argument("--rt", action="store_true", help="a row for the RT baseline (primary='raytrace', every "
                        "candidate), timed as the budgets' frames: item 4's 50 %% frame against it")
    args = parser.parse_args()
    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.compare import ground_truth
    from hybrid_integrator.metrics import errors_in_parallel
    from hybrid_integrator.raster.camera import sensor_to_world

    params = dict(d.split("=", 1) for d in args.D)
    for spec in args.scenes:
        scene, name = load_bench_scene(spec, params)
        used = {k: v for k, v in params.items() if f"${k}" in open(spec).read()}
        reference, _, _ = ground_truth(spec, scene, used, args.gt_spp, -1)
        camera = sensor_to_world(scene.sensors()[0])
        base = {"effects": args.effects} if args.effects else {}
        every = hi.render_sequence(scene, [camera] * 13, layers=False, **base)[3:]
        trace_all = statistics.median(r.stats.times_ms["trace"] for r in every)
        rows = [("all", "-", every)]
        if args.rt:
            rows.append(("rt", "-", hi.render_sequence(scene, [camera] * (5 + args.frames), layers=False, stage_times=False,
                                                       primary="raytrace", **base)[5:]))
        for fraction in args.budgets:
            for mode in args.modes:
                frames = hi.render_sequence(scene, [camera] * (5 + args.frames), layers=False, stage_times=False,
                                            budget_ms=fraction * trace_all, partial_objects=mode == "partial", **base)[5:]
                rows.append((f"{fraction:.0%}", mode, frames))
        tests = [r.image for _, _, frames in rows for r in frames[-args.error_frames:]]
        errors = iter(errors_in_parallel([mi.TensorXf(t).numpy()[..., :3] for t in tests], [reference] * len(tests),
                                         flip_only=True))
        print(f"== {name}: all-candidates trace {trace_all:.3f} ms ({args.variant})", flush=True)
        print("budget | mode | frame ms | trace ms (timed frames) | timed frames within budget | pixels traced | "
          "in part (most frames) | FLIP")
        for budget, mode, frames in rows:
            flip = statistics.mean(next(errors) for _ in frames[-args.error_frames:])
            traces = [r.stats.times_ms["trace"] for r in frames if not math.isnan(r.stats.times_ms["trace"])]
            met = [r.stats.budget_met for r in frames if r.stats.budget_met is not None]
            parts = [f"{r.stats.partial_object} {r.stats.partial_quarters}/4" if r.stats.partial_quarters else "-"
                     for r in frames]
            print(f"{budget} | {mode} | {statistics.median(r.stats.times_ms['total'] for r in frames):.3f} | "
                  f"{statistics.median(traces) if traces else float('nan'):.3f} | "
                  f"{sum(met)}/{len(met)} | {statistics.median(r.stats.pixels_traced for r in frames):.0f} | "
                  f"{max(set(parts), key=parts.count)} | {flip:.4f}", flush=True)


if __name__ == "__main__":  # the error workers are spawned: they import this file
    main()
