"""Host and GPU memory over many frames in one process, and one very large frame (issue 12).

Renders ``--frames`` frames of a camera path that goes back and forth through the scene with one
integrator (its carried state: selection, cost model, learnt ambient, history), as a long
interactive session would, and samples every ``--every`` frames, after a synchronization:
the host's resident memory (``/proc/self/statm``) and, with a CUDA variant, the GPU memory in use
(``cuMemGetInfo``: total − free; the machine's GPU is this process's alone). Growth is measured
from the level after ``--warmup`` frames to the last sample. Then two fresh integrators render the
path's first camera with the same seed: the images must be equal (bit for bit) after all those
frames. With ``--large N`` it also renders one N×N frame of the scene (time and memory).

    python scripts/memory_soak.py scenes/default.xml --frames 500 --resx 64 --resy 48 -o out/soak
    python3 scripts/memory_soak.py scenes/showcase.xml -D showcase_dir=/tmp/scn/cbox --variant cuda_ad_rgb \\
        --frames 10000 --large 8192 -o docs/results/gpu/issue12

Writes ``memory.json``, ``memory.md`` and ``memory.png`` to ``-o``.
"""
from __future__ import annotations

import argparse
import ctypes
import json
import sys
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def rss_mb() -> float:
    return int(Path("/proc/self/statm").read_text().split()[1]) * 4096 / 2**20


def gpu_used_mb(driver) -> float:
    """GPU memory in use on Dr.Jit's device (``cuMemGetInfo`` through ``interop``'s CUDA driver)."""
    free, total = ctypes.c_size_t(), ctypes.c_size_t()
    driver.call("cuMemGetInfo_v2", ctypes.byref(free), ctypes.byref(total))
    return (total.value - free.value) / 2**20


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scene")
    parser.add_argument("-D", dest="define", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=10000)
    parser.add_argument("--every", type=int, default=100, help="frames between samples")
    parser.add_argument("--warmup", type=int, default=500, help="frames before the reference level")
    parser.add_argument("--resx", type=int, default=1280)
    parser.add_argument("--resy", type=int, default=720)
    parser.add_argument("--budget-ms", type=float, default=2.0, help="the frames' budget (selection and cost model)")
    parser.add_argument("--large", type=int, default=0, help="also render one N×N frame")
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "out" / "soak")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.raster.camera import camera_pose
    from hybrid_integrator.raster.context import machine

    from hybrid_integrator.raster.interop import _Driver

    gpu = _Driver() if args.variant.startswith("cuda") else None
    params = dict(d.split("=", 1) for d in args.define)
    scene = hi.load_scene(args.scene, **params, resx=str(args.resx), resy=str(args.resy))
    sensor = mi.traverse(scene.sensors()[0])
    start = np.array(sensor["to_world"].matrix).reshape(4, 4)
    origin, target = start[:3, 3], start[:3, 3] + start[:3, 2]
    up = start[:3, 1]
    leg = hi.camera_path([(origin, target, up), (origin + 0.1 * np.linalg.norm(target - origin) * start[:3, 0], target, up)],
                         100)
    cameras = leg + leg[::-1]  # back and forth: every camera is seen again, the state keeps changing
    properties = {"budget_ms": args.budget_ms, "temporal": True}
    integrator = hi.api._integrator(dict(properties))
    samples, frame_ms = [], []
    poses = [camera_pose(c) for c in cameras]
    with hi.api.posed(scene.sensors()[0]) as place:  # the sensor moved as render_sequence moves it
        for k in tqdm(range(args.frames), desc="frames", unit="frame", mininterval=5):
            place(poses[k % len(poses)])
            t = time.perf_counter()
            result = integrator.render_result(scene, seed=k, spp=1, layers=False)
            frame_ms.append((time.perf_counter() - t) * 1e3)
            if k % args.every == 0 or k == args.frames - 1:
                dr.sync_thread()
                image = np.array(result.image)
                samples.append({"frame": k, "rss_mb": rss_mb(), "gpu_mb": gpu_used_mb(gpu) if gpu else None,
                                "finite": bool(np.isfinite(image).all()), "mean": float(image[..., :3].mean())})
    warm = next(s for s in samples if s["frame"] >= min(args.warmup, args.frames - 1))
    last = samples[-1]
    growth = {key: (last[key] - warm[key]) / warm[key] for key in ("rss_mb", "gpu_mb") if warm[key]}

    sensor["to_world"] = cameras[0]
    sensor.update()
    same = [np.array(hi.api._integrator(dict(properties)).render_result(scene, seed=0, spp=1, layers=False).image)
            for _ in range(2)]
    report = {"command": " ".join(sys.argv), "machine": machine(), "scene": args.scene, "frames": args.frames,
              "resolution": [args.resx, args.resy], "properties": properties, "warmup": warm["frame"],
              "growth": growth, "median_frame_ms": float(np.median(frame_ms)),
              "all_finite": all(s["finite"] for s in samples), "same_seed_same_image": bool(np.array_equal(*same)),
              "samples": samples}
    if args.large:
        del scene, integrator, result
        big = hi.load_scene(args.scene, **params, resx=str(args.large), resy=str(args.large))
        before = gpu_used_mb(gpu) if gpu else None
        t = time.perf_counter()
        frame = hi.render(big, spp=1, layers=False)
        image = np.array(frame.image)
        report["large"] = {"size": args.large, "wall_s": time.perf_counter() - t, "rss_mb": rss_mb(),
                           "gpu_mb_before": before, "gpu_mb_after": gpu_used_mb(gpu) if gpu else None,
                           "finite": bool(np.isfinite(image).all()), "mean": float(image[..., :3].mean()),
                           "fallback": frame.stats.fallback, "readback": frame.stats.readback}
    args.output.mkdir(parents=True, exist_ok=True)
    (args.output / "memory.json").write_text(json.dumps(report, indent=1))
    write_markdown(report, args.output / "memory.md")
    chart(report, args.output / "memory.png")
    print(json.dumps({k: v for k, v in report.items() if k != "samples"}, indent=1))


def write_markdown(report: dict, path: Path) -> None:
    g = report["growth"]
    lines = [f"# Memory over {report['frames']} frames: {Path(report['scene']).stem}, "
             f"{report['resolution'][0]}×{report['resolution'][1]}", "", f"`{report['command']}`", "",
             f"Machine: {report['machine']}; integrator properties {report['properties']}", "",
             "| | after warm-up (frame {0}) | last (frame {1}) | growth |".format(report["warmup"], report["samples"][-1]["frame"]),
             "|---|---|---|---|"]
    warm = next(s for s in report["samples"] if s["frame"] == report["warmup"])
    for key, name in (("rss_mb", "host RSS, MB"), ("gpu_mb", "GPU memory in use, MB")):
        if warm[key] is not None:
            lines.append(f"| {name} | {warm[key]:.1f} | {report['samples'][-1][key]:.1f} | {100 * g[key]:+.2f} % |")
    lines += ["", f"Median frame (`render_result`'s wall time; it synchronizes once): {report['median_frame_ms']:.2f} ms. "
              f"Every sampled frame finite: {report['all_finite']}. Two fresh integrators, same camera and seed, "
              f"after the run: {'the same image' if report['same_seed_same_image'] else 'DIFFERENT images'}."]
    if "large" in report:
        big = report["large"]
        lines += ["", f"One {big['size']}×{big['size']} frame: {big['wall_s']:.1f} s (first frame at that size: "
                  f"kernels compiled), host RSS {big['rss_mb']:.0f} MB, GPU memory {big['gpu_mb_before']} → "
                  f"{big['gpu_mb_after']} MB, finite: {big['finite']}, mean {big['mean']:.4f}, "
                  f"fallback '{big['fallback']}', readback {big['readback']}."]
    path.write_text("\n".join(lines) + "\n")


def chart(report: dict, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    frames = [s["frame"] for s in report["samples"]]
    keys = [(k, n) for k, n in (("rss_mb", "host RSS (MB)"), ("gpu_mb", "GPU memory in use (MB)"))
            if report["samples"][0][k] is not None]
    fig, axes = plt.subplots(1, len(keys), figsize=(5 * len(keys), 3.4), squeeze=False)
    for ax, (key, name) in zip(axes[0], keys):
        ax.plot(frames, [s[key] for s in report["samples"]])
        ax.axvline(report["warmup"], color="grey", lw=0.8, ls="--")
        ax.set_xlabel("frame")
        ax.set_ylabel(name)
        ax.set_ylim(0, 1.2 * max(s[key] for s in report["samples"]))
        ax.set_title(f"{100 * report['growth'][key]:+.2f} % after warm-up")
    fig.suptitle(f"{Path(report['scene']).stem}, {report['frames']} frames, {report['machine']['variant']}")
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()
