"""Which of a frame's host work its frame time waits for (issue 10, stop 53).

A GPU frame overlaps its host's work with the device's where it can: the host issues the trace and
goes on (film, denoiser) while the GPU traces, and learns from the frame's counts while the GPU
denoises it. Host work at a point where the GPU has nothing queued adds to the frame; host work
the GPU's queue covers does not. This probe measures which is which: it renders a camera path and
adds ``--delay`` ms of busy host work at one point of each frame, the point taking turns frame by
frame (so every point sees the same frames, the same process and the same moment). A scene with a
``NAME_path.json`` beside it is rendered along that path, any other from its own sensor, still:

- ``none``: no delay (the baseline);
- ``start``: before the frame's set-up (the GPU idle since the last synchronization: fully exposed);
- ``traced``: right after the device passes are issued (the GPU traces meanwhile);
- ``counts``: once the frame's counts are on the host, before it learns from them (the GPU denoises
  meanwhile): where a budgeted frame's plan for the next frame was made until stop 53 (a moving
  camera's still is);
- ``end``: after the frame's synchronization (fully exposed);
- ``late plan``: no delay, but a still camera's plan for the next frame made once the counts are in
  (``HybridRenderer._account``), as before stop 53, not while the GPU traces (``_plan_ahead``): the
  two ways in turn, in one process.

Prints per run the median frame time at each point, and the part of the delay the frame waited
for, (median − none) / delay: 0 where the GPU's queue hides the work, 1 where the frame waits for
all of it (for ``late plan``, its median − none in ms); ``--phases`` adds the host's phases at each
point (``FrameStats.host_ms``, and ``waits``: the frame's time outside them, for the counts and the
synchronization).

    python3 docs/results/gpu/issue10/stop53/exposure.py --variant cuda_ad_rgb --resx 1280 --resy 720
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))

POINTS = ("none", "start", "traced", "counts", "end", "late plan")


def busy(ms: float) -> None:
    """Hold the host (and Python's lock) for ``ms``, as host work would."""
    until = time.perf_counter() + ms * 1e-3
    while time.perf_counter() < until:
        pass


def install(pipeline, delay_ms: float, turn: list) -> None:
    """Wrap the renderer's methods so that the point ``turn[0]`` is delayed by ``delay_ms``."""
    R = pipeline.HybridRenderer
    marks = {"start": ("_frame", True), "traced": ("_device", False), "counts": ("_account", True),
             "end": ("_account_times", True)}
    plan_ahead = R._plan_ahead

    def ahead(self, *a, **k):  # "late plan": the plan is then made in _account, once the counts are in
        if turn[0] != "late plan":
            plan_ahead(self, *a, **k)
    R._plan_ahead = ahead
    for point, (name, before) in marks.items():
        original = getattr(R, name)

        def call(self, *a, _original=original, _point=point, _before=before, **k):
            if _before and turn[0] == _point:
                busy(delay_ms)
            out = _original(self, *a, **k)
            if not _before and turn[0] == _point:
                busy(delay_ms)
            return out
        setattr(R, name, call)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="*", default=[ROOT / "scenes" / "many_objects.xml"],
                        help="scenes: along NAME_path.json beside one where there is one, else from its own sensor")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=200, help="frames per run (the points take turns)")
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    parser.add_argument("--delay", type=float, default=0.5,
                        help="ms of host work added at a point (0: none, the median of every frame: an A/B of two versions)")
    parser.add_argument("--budgets", type=float, nargs="+", default=[0.25, 0.5, 0.75])
    parser.add_argument("--phases", action="store_true", help="also print the host's phases at each point")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import pipeline
    from budget_benchmark import PROBES
    from hybrid_integrator.bench import load_bench_scene

    turn = ["none"]
    install(pipeline, args.delay, turn)
    for path in args.scenes:
        keyframes = path.with_name(path.stem + "_path.json")
        defines = {"resx": args.resx, "resy": args.resy} | dict(d.split("=", 1) for d in args.defines)
        scene, _ = load_bench_scene(str(path), defines)
        if keyframes.is_file():
            cameras = hi.camera_path(json.loads(keyframes.read_text())["keyframes"], args.frames)
        else:  # a still camera
            cameras = [mi.ScalarTransform4f(hi.api.transform_matrix(mi.traverse(scene.sensors()[0])["to_world"]))] * args.frames
        run(hi, mi, scene, path, cameras, args, turn, PROBES)


def run(hi, mi, scene, path: Path, cameras: list, args, turn: list, probes: int) -> None:
    """The frame time at each point of :data:`POINTS` on one scene, for every kind of frame."""
    integrator_runs = [("all candidates", {}), ("RT baseline", {"primary": "raytrace"})] + \
                      [(f"nested {b:.0%}", {"budget_ms": b}) for b in args.budgets]
    trace_all = None
    print(f"\n{path.name}, {args.variant}, {args.resx}x{args.resy}, {args.frames} frames per run, "
          f"delay {args.delay} ms; median frame ms at each point, and the part of the delay the frame waited for")
    for label, props in integrator_runs:
        if "budget_ms" in props:
            props = {"budget_ms": props["budget_ms"] * trace_all}
        turn[0] = "none"
        hi.render_sequence(scene, cameras[:6], spp=1, layers=False, **props)  # compiles, records
        integrator = hi.api._integrator(dict(props))
        frames = {p: [] for p in POINTS}
        phases = {p: [] for p in POINTS}
        traces = []
        try:
            with hi.api.posed(scene.sensors()[0]) as place:  # as render_sequence poses the sensor
                for k, camera in enumerate(cameras):
                    place(hi.api.camera_pose(camera))
                    turn[0] = POINTS[k % len(POINTS)]
                    upcoming = cameras[k + 1] if k + 1 < len(cameras) else None
                    result = integrator.render_result(scene, seed=k, spp=1, layers=False, next_camera=upcoming)
                    if k >= probes + len(POINTS):
                        frames[turn[0]].append(result.stats.times_ms["total"])
                        waits = result.stats.times_ms["total"] - sum(result.stats.host_ms.values())  # for the counts, the sync
                        phases[turn[0]].append({**result.stats.host_ms, "waits": waits})
                        traces.append(result.stats.times_ms["trace"])
        finally:
            turn[0] = "none"
        if label == "all candidates":
            trace_all = statistics.median(traces)
        base = statistics.median(frames["none"])
        cells = [f"{p} {statistics.median(frames[p]):.3f}"
                 + ("" if p == "none" else f" ({statistics.median(frames[p]) - base:+.3f} ms)" if p == "late plan"
                    else f" ({(statistics.median(frames[p]) - base) / args.delay:+.2f})") for p in POINTS] \
            if args.delay > 0 else [f"frame {statistics.median(t for p in POINTS for t in frames[p]):.3f} (every frame)"]
        print(f"{label:16s} trace {statistics.median(traces):.3f} | " + " | ".join(cells))
        if args.phases:  # the host's phases at each point: where a delay shortens a phase, that phase waited
            for p in POINTS:
                print(f"{'':16s} {p:6s} host ms by phase: " + ", ".join(
                    f"{k} {statistics.median(h[k] for h in phases[p]):.3f}" for k in phases[p][0]))


if __name__ == "__main__":
    main()
