"""When a hybrid frame's work is issued by the host and when the GPU reaches it (issue 10).

A CUDA frame's wall time is its host issue, the device work the host did not hide, and the host
work after the synchronization. This probe marks points of a frame with a host clock
(``time.perf_counter``) and a CUDA event on Dr.Jit's stream, then prints for each point the median
host time since the frame began and the median time at which the GPU's stream reached it (events
measured from one recorded at the frame's start, when the stream is idle). Where the GPU time of a
point is close to its host time, the GPU waited for the host; where it is later, the host was
ahead. The OpenGL draw runs on its own queue: the stream reaches ``ids copied`` once the copy,
which waits for the draw through the interop mapping, is done.

The points wrap the renderer's own methods on one instance (no copy of the frame's code): the
raster pass and its interop copy, each device pass (a frozen replay), the film's development and
the post-processing (history, denoiser). Five kinds of frame: nothing traced (DR), the default
frame, a budget of ``--budget`` × the default frame's trace time (after five frames, the first of
which probe), and the RT baseline with nothing traced and with everything.

    python3 scripts/frame_timeline.py scenes/armadillo_glass.xml --variant cuda_ad_rgb -D resx=1280 -D resy=720 ...
"""
from __future__ import annotations

import argparse
import ctypes
import statistics
import time
from pathlib import Path

from frame_profile import print_kernels  # scripts/ is on sys.path when a script runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="cuda_ad_rgb")
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--save-images", type=Path, default=None, metavar="DIR",
                        help="save each kind of frame's first timed image as DIR/SCENE-KIND.npy (to compare two versions)")
    parser.add_argument("--budget", type=float, default=0.5,
                        help="the budgeted frame's budget, as a fraction of the default frame's trace time")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import pipeline
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.raster.interop import _Driver

    driver = _Driver() if args.variant.startswith("cuda") else None  # the CPU: host times alone
    defines = dict(d.split("=", 1) for d in args.defines)
    for path in args.scenes:
        scene, _ = load_bench_scene(str(path), defines)
        trace_all = None  # the default frame's trace time: what the budget is a fraction of
        for kind, label, props in (("dr", "DR (nothing traced)", {"candidates": ""}), ("default", "default frame", {}),
                                   ("budget", f"{args.budget:.0%} budget", None),
                                   ("rt-dr", "RT baseline, nothing traced", {"candidates": "", "primary": "raytrace"}),
                                   ("rt", "RT baseline", {"primary": "raytrace"})):
            props = props if props is not None else {"budget_ms": args.budget * trace_all}
            integrator = hi.api._integrator(dict(props))
            for seed in range(5 if kind == "budget" else 3):  # compiles and records; a budget's first frames probe
                integrator.render_result(scene, seed=seed, spp=1, layers=False)
            renderer = hi.api.renderer(scene)
            marks = Marks(driver)
            with marks.around(renderer, pipeline):
                rows = []
                kernels, phases, totals, traces = [], [], [], []
                for seed in range(args.frames):
                    marks.start()
                    result = integrator.render_result(scene, seed=3 + seed, spp=1, layers=False)
                    rows.append(marks.finish())
                    stats = result.stats
                    phases.append(stats.host_ms)
                    totals.append(stats.times_ms["total"])
                    if args.save_images and seed == 0:
                        args.save_images.mkdir(parents=True, exist_ok=True)
                        np.save(args.save_images / f"{path.stem}-{kind}.npy", np.array(result.image))
                    kernels.append(sum(v for k, v in stats.times_ms.items() if k not in ("gl", "issue", "total"))
                                   - stats.times_ms["gl"])
                    traces.append(stats.times_ms["trace"])
            if kind == "default":
                trace_all = statistics.median(traces)
            print(f"\n{path.name}, {label}: median ms since the frame began, over {args.frames} frames")
            print(f"frame time (FrameStats total, as the bench reports it): {statistics.median(totals):.3f} ms")
            print(f"{'point':28s} {'host':>7s} {'GPU':>7s}")
            # a point may be missing from some frames (a budget's frame that draws its raster pass
            # again, "GL draw issue (2)", where the pass drawn ahead served another selection)
            for name in dict.fromkeys(name for r in rows for name in r):
                seen = [r[name] for r in rows if name in r]
                gpu = [g for _, g in seen if g is not None]
                print(f"{name:28s} {statistics.median(h for h, _ in seen):7.3f} "
                      f"{statistics.median(gpu) if gpu else float('nan'):7.3f}"
                      + ("" if len(seen) == len(rows) else f"   (in {len(seen)} of {len(rows)} frames)"))
            print(f"device work of the frame's Dr.Jit kernels and denoiser (kernel history, CUDA events): "
                  f"{statistics.median(kernels):.3f} ms; the last frame's launches:")
            print_kernels(renderer.clock.last)
            print("host ms by phase (FrameStats.host_ms):",
                  {k: round(statistics.median(p[k] for p in phases), 3) for k in phases[0]})


class Marks:
    """Host times and CUDA events (with a CUDA driver) at named points of a frame."""

    def __init__(self, driver):
        self.driver = driver
        self.events: list = []
        self.points: list[tuple[str, float, int | None]] = []

    def _event(self) -> int:
        k = len(self.points)
        while len(self.events) <= k:
            event = ctypes.c_void_p()
            self.driver.call("cuEventCreate", ctypes.byref(event), ctypes.c_uint(0))
            self.events.append(event)
        self.driver.call("cuEventRecord", self.events[k], self.driver.stream)
        return k

    def mark(self, name: str, gpu: bool = True) -> None:
        now = time.perf_counter()
        self.points.append((name, now, self._event() if gpu and self.driver else None))

    def start(self) -> None:
        self.points = []
        self.mark("frame start")

    def finish(self) -> dict[str, tuple[float, float | None]]:
        self.mark("render returned", gpu=False)
        t0 = self.points[0][1]
        out = {}
        for name, host, event in self.points:
            gpu = None
            if event is not None:
                ms = ctypes.c_float()
                self.driver.call("cuEventElapsedTime", ctypes.byref(ms), self.events[0], self.events[event])
                gpu = float(ms.value)
            key, n = name, 2
            while key in out:
                key, n = f"{name} ({n})", n + 1
            out[key] = ((host - t0) * 1e3, gpu)
        return out

    def around(self, renderer, pipeline):
        """Wrap the renderer's stages (this instance only) and the module's ``develop``."""
        import contextlib

        @contextlib.contextmanager
        def wrapped():
            originals = {}

            def wrap(owner, name, before=None, after=None):
                original = getattr(owner, name)
                originals[(owner, name)] = original

                def call(*a, **k):
                    if before:
                        self.mark(before, gpu=False)
                    out = original(*a, **k)
                    self.mark(after)
                    return out
                setattr(owner, name, call)

            wrap(renderer.raster, "render", before="GL draw issue", after="GL draw issued")
            wrap(renderer.raster, "device_ids", after="ids copied")
            wrap(renderer, "_device", after="device pass issued")
            wrap(pipeline, "develop", after="developed")
            wrap(renderer, "_post", after="post issued")
            try:
                yield
            finally:
                for (owner, name), original in originals.items():
                    if owner is renderer or owner is renderer.raster:
                        delattr(owner, name)  # the class's method again
                    else:
                        setattr(owner, name, original)
        return wrapped()


if __name__ == "__main__":
    main()
