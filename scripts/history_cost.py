"""What Dr.Jit's kernel history costs a frame (issue 10).

Every frame of ``HybridRenderer.render`` runs with ``JitFlag.KernelHistory`` on: the stage times
(``FrameStats.times_ms``) and the budget's cost model, which learns the trace stage's device time,
come from it. On the CUDA backend the history records a pair of CUDA events around every kernel
and reduction of the frozen replay, and after the frame ``StageClock.frame_times`` reads it back
(``host_ms["timing"]``, through Dr.Jit's C API since stop 48: ``history.py``; part of
``times_ms["total"]`` since then). This probe renders the same frames
with the history on and, by wrapping ``drjit.scoped_set_flag`` so that the renderer's request for
it is ignored, off (the probe's one intervention; its frames then have no stage times), in turn,
and prints per kind of frame (1 spp) the median wall time of a frame (``render`` and one
synchronisation, the history's read-back included where it is on) and, with the history on, the
median ``times_ms["total"]`` (what the bench reports; until stop 48 the read-back was left out). Frames without a
budget only (a budget's cost model needs the history).

    python3 scripts/history_cost.py --variant cuda_ad_rgb scenes/armadillo_glass.xml -D resx=1280 -D resy=720 -D models_dir=…
"""
from __future__ import annotations

import argparse
import contextlib
import statistics
import time
from pathlib import Path

#: the kinds of frame: (label, settings)
KINDS = (("hybrid", dict(primary="raster")), ("RT baseline", dict(primary="raytrace")),
         ("DR (nothing traced)", dict(primary="raster", candidates="")))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=30, help="frames of each kind and setting, after warm-up")
    parser.add_argument("--denoise", action=argparse.BooleanOptionalAction, default=True)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    from hybrid_integrator.api import renderer as scene_renderer
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.pipeline import HybridSettings

    history = {"on": True}
    scoped = dr.scoped_set_flag

    @contextlib.contextmanager
    def flag(which, value=True):
        if which == dr.JitFlag.KernelHistory and not history["on"]:
            yield
            return
        with scoped(which, value):
            yield

    dr.scoped_set_flag = flag
    defines = dict(d.split("=", 1) for d in args.defines)
    print(f"{args.variant}: median wall ms per frame (render + one synchronisation), "
          f"{args.frames} frames each, kernel history on / off in turn")
    for path in args.scenes:
        scene, _ = load_bench_scene(str(path), defines)
        renderer = scene_renderer(scene)
        for label, props in KINDS:
            settings = HybridSettings(**props, denoise=args.denoise)
            wall, total = {True: [], False: []}, []
            for frame in range(args.frames + 3):  # three warm-up frames of each (a recording each)
                for on in (True, False):
                    history["on"] = on
                    dr.sync_thread()
                    start = time.perf_counter()
                    result = renderer.render(settings, spp=1, seed=frame, layers=False)
                    dr.sync_thread()
                    if frame >= 3:
                        wall[on].append((time.perf_counter() - start) * 1e3)
                        if on:
                            total.append(result.stats.times_ms["total"])
            on, off = (statistics.median(wall[k]) for k in (True, False))
            print(f"{path.stem:16s} {label:20s} on {on:7.3f} (total {statistics.median(total):7.3f})  off {off:7.3f}  "
                  f"history costs {on - off:+.3f} ms")


if __name__ == "__main__":
    main()
