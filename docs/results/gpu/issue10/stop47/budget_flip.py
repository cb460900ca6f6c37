"""What budgets buy (issue 10, stop 47): per scene, the hybrid's default frame and frames at 0 / 25 /
50 / 75 % of its all-candidates trace time, as the bench renders them (``render_sequence``, the
budgeted runs from a fresh state: 5 frames of warm-up, then FRAMES), each frame's total time and
trace time (and every stage's and host phase's median), and FLIP against ``path`` at GT_SPP (the bench's cached ground truth), the mean of the
last 5 frames' FLIP. One JSON line per scene is appended to OUT; run once per tree (this one, or an
old one on PYTHONPATH) to compare selections, or with ``--selections nested,greedy`` to compare
selectors in one process (stop 51).

    python docs/results/gpu/issue10/stop47/budget_flip.py --variant cuda_ad_rgb --label new -o out.jsonl SCENE.xml -D …
"""
from __future__ import annotations

import argparse
import json
import statistics


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--gt-spp", type=int, default=1024)
    parser.add_argument("--fractions", default="0,0.25,0.5,0.75")
    parser.add_argument("--label", default="")
    parser.add_argument("--selections", default="nested",
                        help="selectors to run at each budget (stop 51: nested,greedy); rows of others than nested are "
                             "keyed 'FRACTION SELECTOR'")
    parser.add_argument("--no-denoise", action="store_true", help="frames without the denoiser")
    parser.add_argument("-D", dest="defines", action="append", default=[])
    parser.add_argument("-o", dest="out", required=True)
    args = parser.parse_args()
    import mitsuba as mi
    mi.set_variant(args.variant)
    import numpy as np
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.compare import ground_truth
    from hybrid_integrator.metrics import flip_map
    from hybrid_integrator.raster.camera import sensor_to_world

    params = dict(d.split("=", 1) for d in args.defines)
    for spec in args.scenes:
        scene, name = load_bench_scene(spec, params)
        reference, _, _ = ground_truth(spec, scene, params, args.gt_spp, -1)
        camera = sensor_to_world(scene.sensors()[0])

        def run(warmup: int, **props) -> dict:
            props = {"denoise": False, **props} if args.no_denoise else props
            frames = hi.render_sequence(scene, [camera] * (warmup + args.frames), spp=1, seed=0, layers=False, **props)[warmup:]
            stats = [f.stats for f in frames]
            flips = [flip_map(np.array(f.image)[..., :3], reference)[1] for f in frames[-5:]]
            return {"stages_ms": {k: statistics.median(s.times_ms[k] for s in stats) for k in stats[0].times_ms},
                    "host_ms": {k: statistics.median(s.host_ms[k] for s in stats) for k in stats[0].host_ms},
                    "total_ms": statistics.median(s.times_ms["total"] for s in stats),
                    "trace_ms": statistics.median(s.times_ms["trace"] for s in stats),
                    "predicted_ms": statistics.median(s.predicted_trace_ms for s in stats),
                    "pixels": statistics.median(s.pixels_traced for s in stats),
                    "flip": float(np.mean(flips)), "flip_frames": [float(x) for x in flips]}

        row = {"label": args.label, "scene": name, "hybrid": run(3)}
        trace_all = row["hybrid"]["trace_ms"]
        for fraction in (float(x) for x in args.fractions.split(",")):
            for selection in args.selections.split(","):
                key = f"{fraction:.0%}" + ("" if selection == "nested" else f" {selection}")
                budget = max(fraction * trace_all, 1e-6)
                row[key] = {"budget_ms": budget, **run(5, budget_ms=budget, selection=selection)}
        print(json.dumps({k: ({kk: (round(vv, 4) if isinstance(vv, float) else vv) for kk, vv in v.items()
                               if kk not in ("flip_frames", "stages_ms", "host_ms")}
                              if isinstance(v, dict) else v) for k, v in row.items()}), flush=True)
        with open(args.out, "a") as fh:
            fh.write(json.dumps(row) + "\n")


if __name__ == "__main__":
    main()
