"""The still-camera histories' rivals with a denoiser (issue 10, stop 49): for each scene, the spp
that this stop's bench gave `path` at each history's total time (`outputs/SCENE/bench.json`, rows
`path@history-time…`), rendered as `path` + the hybrid's denoiser at its default quality ('fast',
`compare.timed_path_denoised`, replayed from a recording, 20 frames as far as they fit in a
second), measured against the same ground truth (`path` at 1024 spp). Printed beside the bench's
own rows (the history after all its frames, and raw `path` at that spp); one JSON line per rival.

    python3 docs/results/gpu/issue10/stop49/history_rivals.py --variant cuda_ad_rgb SCENE... $D
"""
import argparse
import json
import statistics
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("-D", dest="defines", action="append", default=[])
    args = parser.parse_args()
    import mitsuba as mi
    mi.set_variant(args.variant)
    import numpy as np

    from hybrid_integrator.bench import history_rival, load_bench_scene
    from hybrid_integrator.compare import ground_truth, timed_path_denoised
    from hybrid_integrator.metrics import errors_in_parallel

    params = dict(d.split("=", 1) for d in args.defines)
    measured = []
    for spec in args.scenes:
        scene, name = load_bench_scene(spec, params)
        (report,) = json.loads((HERE / "outputs" / name / "bench.json").read_text())
        rows = {m["method"]: m for m in report["methods"]}
        reference = ground_truth(spec, scene, params, 1024, -1)[0]
        for history in ("hybrid+history", "hybrid+history, 8 paths/hit"):
            raw = rows[history_rival(history)]
            image, times = timed_path_denoised(scene, raw["spp"], -1, 0, repeats=20, quality="fast")
            measured.append((name, history, rows[history], raw, statistics.median(times),
                             np.array(image, dtype=np.float32)[..., :3], reference))
    errors = errors_in_parallel([m[5] for m in measured], [m[6] for m in measured])
    for (name, history, hist, raw, ms, _, _), error in zip(measured, errors):
        total = hist["time_ms"] * hist["frames_accumulated"]
        print(f"{name} {history}: {hist['frames_accumulated']} frames {total:.1f} ms FLIP {hist['flip']:.4f} "
              f"relMSE {hist['rel_mse']:.4f} | path {raw['spp']} spp {raw['time_ms']:.1f} ms FLIP {raw['flip']:.4f} "
              f"relMSE {raw['rel_mse']:.4f} | path + OIDN 'fast' {ms:.1f} ms FLIP {error.flip:.4f} relMSE {error.rel_mse:.4f}")
        print(json.dumps({"scene": name, "history": history, "frames": hist["frames_accumulated"], "history_total_ms": total,
                          "history_flip": hist["flip"], "history_rel_mse": hist["rel_mse"], "spp": raw["spp"],
                          "path_ms": raw["time_ms"], "path_flip": raw["flip"], "path_rel_mse": raw["rel_mse"],
                          "path_denoised_ms": ms, "path_denoised_flip": error.flip,
                          "path_denoised_rel_mse": error.rel_mse}))


if __name__ == "__main__":
    main()
