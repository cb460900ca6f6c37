"""Why the Armadillo's budgeted frames, bound by the GPU, were 2-4 % slower untimed (issue 10, stop 60).

Stop 59 made a budget without stage times read Dr.Jit's kernel history on every 4th frame only
(``timing_interval``). Along the 226 objects' path that made budgeted frames 1.04-1.19x as fast;
the Armadillo's 50 % frames (the floor's shadows alone, ~3 ms, bound by the GPU) were 0.96-0.98x.
One difference besides the history: a timed frame starts reading its history on a worker thread
(``HybridRenderer._read_ahead``) before it hands the visibility targets back to OpenGL and issues
the next frame's raster pass (``_draw_ahead``); an untimed frame issues them sooner, while the GPU
still denoises, and OpenGL's work then shares the GPU with CUDA's (stop 42: an unmap issued during
the trace made it 0.22-0.46 ms longer). Here, per scene and budget, in turn along the scene's
camera path (``bench.frames_in_turn``): the RT baseline, the budget timed on every frame
(``timed``: ``timing_interval`` 1) and every 4th (``sampled``), each also without the raster pass
drawn ahead (``raster_ahead=off``). Prints each side's median frame and the paired ratios.

    python3 docs/results/gpu/issue10/stop60/ahead_ab.py scenes/armadillo_glass.xml --variant cuda_ad_rgb --frames 40
"""
from __future__ import annotations

import statistics

WARM = 3


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, turn_arguments, turn_budgets

    parser = turn_arguments(__doc__.splitlines()[0], budgets=(0.5,), block=5)
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    for ready, fraction, budget in turn_budgets(args, WARM):
        base = {"budget_ms": budget, "stage_times": False}
        sides = {"rt": {"primary": "raytrace"},
                 "timed": {**base, "timing_interval": 1}, "sampled": {**base, "timing_interval": 4},
                 "timed_off": {**base, "timing_interval": 1, "raster_ahead": "off"},
                 "sampled_off": {**base, "timing_interval": 4, "raster_ahead": "off"}}
        times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                               cameras=ready.cameras)
        print(f"{ready.name:16s} {fraction:.0%} budget ({budget:.3f} ms): frame ms "
              + ", ".join(f"{s} {statistics.median(t['total'] for t in times[s]):.3f}" for s in sides), flush=True)
        for a, b in (("timed", "sampled"), ("timed_off", "sampled_off"), ("timed", "timed_off"),
                     ("sampled", "sampled_off"), ("rt", "sampled"), ("rt", "sampled_off")):
            r = paired_ratio(times, a, b, block=args.block)
            print(f"    {a} / {b}: {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} rounds)", flush=True)


if __name__ == "__main__":
    main()
