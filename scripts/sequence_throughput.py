"""Throughput of a camera path on one worker against N Ray workers (issue 13, acceptance 3).

One run renders the same camera path with ``hi.render_frames`` twice or more: ``--workers 1``
in this process (what ``hybrid sequence`` does on one GPU), then on N Ray actors, one GPU each
(``--gpus-per-worker 1``) or one CPU worker each. Every frame is written as EXR + PNG + JSON, as a
user's run writes it. From the frames' JSON files (written last, so their modification time is
when the frame was finished) it reports:

- end to end: frames / wall time of the whole call (start-up, scene loading and kernel
  compilation of every worker included);
- steady state: frames finished after every worker has finished its first frame, per second of
  the time from then to the last frame (the warm rate a long path runs at);
- what the chunks change (``frames.py``): each chunk of the path starts its carried state (cost
  model, selection, learnt ambient) afresh, so its first frames can differ from the single
  process's; the relative difference of every frame to the one-worker frame, and the frame time
  (``FrameStats.times_ms["total"]``) at the chunk starts against the rest.

    python scripts/sequence_throughput.py scenes/default.xml --frames 12 --workers 1 2 --resx 160 --resy 120
    python3 scripts/sequence_throughput.py scenes/sponza_mirror.xml --variant cuda_ad_rgb --gpus-per-worker 1 \\
        --frames 60 --workers 1 2 -D sponza_dir=/tmp/scn/sponza-dabrovic -o docs/results/gpu/issue13

Writes ``throughput.json``, ``throughput.md`` and ``throughput.png`` to ``-o``.
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

#: a dolly through each bench scene, as look-at key frames (origin, target, up) at its own camera
PATHS = {
    "sponza_mirror": [[[2.25067, 8.24132, -0.0492483], [3.15037, 7.8048, -0.0501832], [0.436514, 0.899693, -0.00291584]],
                      [[-1.5, 8.0, 1.2], [-0.6, 7.56, 1.2], [0.436514, 0.899693, -0.00291584]]],
}


def run(args, workers: int, out: Path) -> dict:
    import hybrid_integrator as hi
    from hybrid_integrator.frames import chunks, frame_name

    keys = json.loads(args.camera_path) if args.camera_path else PATHS.get(Path(args.scene).stem)
    if keys is None:
        sys.exit(f"no camera path for {args.scene}: give --camera-path")
    params = dict(d.split("=", 1) for d in args.define)
    params.update(resx=str(args.resx), resy=str(args.resy))
    start = time.time()
    hi.render_frames(Path(args.scene).resolve(), hi.camera_path(keys, args.frames), out, spp=1, seed=args.seed,
                     workers=workers, params=params, gpus_per_worker=args.gpus_per_worker if workers > 1 else 0.0,
                     preview=False, variant=args.variant)
    wall = time.time() - start
    done = np.array([os.stat(out / f"{frame_name(k)}.json").st_mtime for k in range(args.frames)])
    stats = [json.loads((out / f"{frame_name(k)}.json").read_text()) for k in range(args.frames)]
    firsts = [c[0] for c in chunks(list(range(args.frames)), workers)]
    warm = max(done[firsts])
    later = done > warm
    steady = later.sum() / (done.max() - warm) if later.sum() and done.max() > warm else float("nan")
    return {"workers": workers, "wall_s": wall, "frames_per_s": args.frames / wall, "steady_frames_per_s": float(steady),
            "steady_frames": int(later.sum()), "chunk_starts": firsts,
            "frame_ms": [s["times_ms"]["total"] for s in stats], "readback": sorted({s["readback"] for s in stats})}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("-D", dest="define", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--camera-path", default=None, help="JSON key frames (default: the scene's entry in PATHS)")
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--gpus-per-worker", type=float, default=0.0)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--resx", type=int, default=1280)
    parser.add_argument("--resy", type=int, default=720)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "out" / "throughput")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    from hybrid_integrator.frames import frame_name
    from hybrid_integrator.io import read_exr
    from hybrid_integrator.metrics import relative_mse
    from hybrid_integrator.raster.context import machine

    def rgb(workers: int, k: int) -> np.ndarray:
        channels, _ = read_exr(scratch / f"w{workers}" / f"{frame_name(k)}.exr")
        return np.stack([channels[c] for c in "RGB"], axis=-1)

    args.output.mkdir(parents=True, exist_ok=True)
    scratch = Path(tempfile.mkdtemp(prefix="throughput-"))
    runs = []
    for w in args.workers:
        runs.append(run(args, w, scratch / f"w{w}"))
        print(json.dumps({k: v for k, v in runs[-1].items() if k != "frame_ms"}), flush=True)
    base = runs[0]
    for r in runs[1:]:  # each frame against the same frame of the first (single-process) run
        r["relative_difference"] = [relative_mse(rgb(r["workers"], k), rgb(base["workers"], k))
                                    for k in range(args.frames)]
        r["speedup_steady"] = r["steady_frames_per_s"] / base["steady_frames_per_s"]
        r["speedup_end_to_end"] = r["frames_per_s"] / base["frames_per_s"]
    shutil.rmtree(scratch)
    report = {"command": " ".join(sys.argv), "machine": machine(), "scene": args.scene, "frames": args.frames,
              "resolution": [args.resx, args.resy], "gpus_per_worker": args.gpus_per_worker,
              "cuda_visible_devices": os.environ.get("CUDA_VISIBLE_DEVICES"), "runs": runs}
    (args.output / "throughput.json").write_text(json.dumps(report, indent=1))
    write_markdown(report, args.output / "throughput.md")
    chart(report, args.output / "throughput.png")
    print(f"wrote {args.output}/throughput.{{json,md,png}}")


def write_markdown(report: dict, path: Path) -> None:
    lines = [f"# Camera path throughput: {Path(report['scene']).stem}, {report['frames']} frames, "
             f"{report['resolution'][0]}×{report['resolution'][1]}", "",
             f"`{report['command']}`", "", f"Machine: {report['machine']}", "",
             "| workers | wall s | frames/s end to end | frames/s steady | speed-up end to end | speed-up steady | "
             "median frame ms | chunk-start frame ms | max rel. difference to 1 worker | readback |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in report["runs"]:
        ms = np.array(r["frame_ms"])
        diff = r.get("relative_difference")
        lines.append(f"| {r['workers']} | {r['wall_s']:.1f} | {r['frames_per_s']:.2f} | {r['steady_frames_per_s']:.2f} | "
                     f"{r.get('speedup_end_to_end', 1.0):.2f}× | {r.get('speedup_steady', 1.0):.2f}× | "
                     f"{np.median(ms):.1f} | {', '.join(f'{ms[k]:.1f}' for k in r['chunk_starts'])} | "
                     f"{'—' if diff is None else f'{max(diff):.2e}'} | {', '.join(r['readback'])} |")
    path.write_text("\n".join(lines) + "\n")


def chart(report: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 3.6))
    names = [f"{r['workers']} worker{'s' if r['workers'] > 1 else ''}" for r in report["runs"]]
    x = np.arange(len(names))
    a.bar(x - 0.2, [r["frames_per_s"] for r in report["runs"]], 0.4, label="end to end")
    a.bar(x + 0.2, [r["steady_frames_per_s"] for r in report["runs"]], 0.4, label="steady state")
    a.set_xticks(x, names)
    a.set_ylabel("frames / s")
    a.legend()
    for r in report["runs"]:
        b.plot(r["frame_ms"], label=names[report["runs"].index(r)])
    b.set_xlabel("frame")
    b.set_ylabel("frame time (ms, FrameStats total)")
    b.set_yscale("log")
    b.legend()
    fig.suptitle(f"{Path(report['scene']).stem}, {report['frames']} frames, {report['machine']['variant']}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
