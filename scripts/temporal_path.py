"""A moving camera with and without history (issue 11, acceptance 4): per frame, FLIP against its
own reference and the frame's time.

The camera pans sideways along its own x axis, by ``--move`` × the distance to the scene's centre
over the path, looking at a fixed point (``hi.camera_path``). Each frame is rendered by
``hi.render_sequence`` twice with the default hybrid: once as is, once with ``temporal=true``
(history reprojected through the visibility buffer, ``temporal.py``); each frame's reference is
Mitsuba ``path`` at ``--ref-spp``. Writes ``NAME.json``, ``NAME.md`` and the chart ``NAME.png``
into ``-o``.

    python3 scripts/temporal_path.py scenes/showcase.xml --variant cuda_ad_rgb -D resx=1280 -D resy=720 \\
        -D showcase_dir=/tmp/scn/cbox -o docs/results/gpu/issue11/temporal
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--move", type=float, default=0.3, help="sideways travel / distance to the scene's centre")
    parser.add_argument("--ref-spp", type=int, default=256)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "results" / "cpu" / "temporal")
    args = parser.parse_args()

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import mitsuba as mi
    import numpy as np
    from tqdm import tqdm

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.raster.camera import sensor_to_world, transform_matrix
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.metrics import errors_in_parallel

    scene, name = load_bench_scene(args.scene, dict(d.split("=", 1) for d in args.defines))
    start = transform_matrix(sensor_to_world(scene.sensors()[0]))
    origin, right, forward, up = start[:3, 3], start[:3, 0], start[:3, 2], start[:3, 1]
    distance = float(np.linalg.norm(np.array(scene.bbox().center()) - origin))
    target = origin + forward * distance
    shift = right * args.move * distance
    cameras = hi.camera_path([(origin - shift / 2, target, up), (origin + shift / 2, target, up)], args.frames)

    runs = {}
    for label, temporal in (("no history", False), ("history", True)):
        hi.render_sequence(scene, cameras[:3], spp=1, seed=100, layers=False, temporal=temporal)  # compiles
        runs[label] = hi.render_sequence(scene, cameras, spp=1, seed=1, layers=False, temporal=temporal)
    params = mi.traverse(scene.sensors()[0])
    path = mi.load_dict({"type": "path", "max_depth": -1})
    truths = []
    for k, camera in enumerate(tqdm(cameras, desc=f"{name}: references")):
        params["to_world"] = camera
        params.update()
        truths.append(np.array(mi.render(scene, integrator=path, spp=args.ref_spp, seed=10_000 + k))[..., :3])
    params["to_world"] = mi.ScalarTransform4f(start)
    params.update()
    tests = [np.array(frames[k].image)[..., :3] for frames in runs.values() for k in range(len(cameras))]
    flips = errors_in_parallel(tests, truths * len(runs), flip_only=True)
    rows = [{"frame": k, **{f"flip {label}": flips[j * len(cameras) + k] for j, label in enumerate(runs)},
             **{f"ms {label}": frames[k].stats.times_ms["total"] for label, frames in runs.items()}}
            for k in range(len(cameras))]

    worse = [r["frame"] for r in rows if r["flip history"] > r["flip no history"] + 0.005]
    summary = {"scene": name, "variant": args.variant, "frames": args.frames, "move": args.move,
               "ref_spp": args.ref_spp, "resolution": list(scene.sensors()[0].film().crop_size()),
               "frames_worse_with_history": worse,
               "median ms": {label: statistics.median(r[f"ms {label}"] for r in rows) for label in runs},
               "mean flip": {label: float(np.mean([r[f"flip {label}"] for r in rows])) for label in runs},
               "rows": rows, "command": " ".join(sys.argv)}
    args.output.mkdir(parents=True, exist_ok=True)
    (args.output / f"{name}.json").write_text(json.dumps(summary, indent=1))
    fig, ax = plt.subplots(figsize=(7, 3.5))
    for label in runs:
        ax.plot([r["frame"] for r in rows], [r[f"flip {label}"] for r in rows], marker="o", ms=3,
                label=f"{label} (median {summary['median ms'][label]:.1f} ms/frame)")
    ax.set(xlabel="frame of the camera path", ylabel=f"FLIP vs path {args.ref_spp} spp",
           title=f"{name}: moving camera, {summary['resolution'][0]}×{summary['resolution'][1]}, {args.variant}")
    ax.set_ylim(bottom=0)
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.output / f"{name}.png", dpi=120)
    lines = [f"# {name}: moving camera with and without history", "", f"Command: `{summary['command']}`", "",
             "| frame | FLIP no history | FLIP history | ms no history | ms history |", "|---|---|---|---|---|"]
    lines += [f"| {r['frame']} | {r['flip no history']:.4f} | {r['flip history']:.4f} | {r['ms no history']:.2f} | "
              f"{r['ms history']:.2f} |" for r in rows]
    lines += ["", f"Frames where history is worse by more than 0.005: {worse or 'none'}. Mean FLIP: "
              + ", ".join(f"{k} {v:.4f}" for k, v in summary["mean flip"].items()) + "."]
    (args.output / f"{name}.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines[-1:]), summary["median ms"])
    return 1 if worse else 0


if __name__ == "__main__":
    raise SystemExit(main())
