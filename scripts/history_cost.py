"""What Dr.Jit's kernel history costs a frame, and the frame without it against ``path`` (issue 10).

A frame of ``HybridRenderer.render`` reads its stages' device times (``FrameStats.times_ms``) from
Dr.Jit's kernel history (``JitFlag.KernelHistory``): on the CUDA backend a pair of CUDA events
around every kernel and reduction of the frozen replay, read back by the frame (``StageClock.frame_times``,
through Dr.Jit's C API: ``history.py``; since issue 10's stop 51 a denoised frame's while the GPU
denoises it, ``HybridRenderer._read_ahead``; in
``times_ms["total"]`` since issue 10's stop 48). With ``stage_times=False`` (issue 10, stop 50) a
frame without a budget keeps no history. This probe renders each kind of frame (1 spp) with the
stage times on and off, in turn, through one renderer, and prints the median wall time of a frame
(``render`` and one synchronisation) and its median ``times_ms["total"]`` (what the bench
reports) each way; then, for scale, Mitsuba's ``path`` at 1 spp replayed from a recording and the
same with the hybrid's default denoiser ('fast', ``compare.timed_path_denoised``), as the bench
times them (``compare.timed_path``), over as many frames.

    python3 scripts/history_cost.py --variant cuda_ad_rgb scenes/armadillo_glass.xml -D resx=1280 -D resy=720 -D models_dir=…
"""
from __future__ import annotations

import argparse
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
    from hybrid_integrator.compare import timed_path, timed_path_denoised
    from hybrid_integrator.pipeline import HybridSettings

    defines = dict(d.split("=", 1) for d in args.defines)
    print(f"{args.variant}: median ms per frame (render + one synchronisation; total: times_ms), "
          f"{args.frames} frames each, stage times on / off in turn")
    for path in args.scenes:
        scene, _ = load_bench_scene(str(path), defines)
        renderer = scene_renderer(scene)
        for label, props in KINDS:
            wall, total = {True: [], False: []}, {True: [], False: []}
            for frame in range(args.frames + 3):  # three warm-up frames of each (a recording each)
                for on in (True, False):
                    settings = HybridSettings(**props, denoise=args.denoise, stage_times=on)
                    dr.sync_thread()
                    start = time.perf_counter()
                    result = renderer.render(settings, spp=1, seed=frame, layers=False)
                    dr.sync_thread()
                    if frame >= 3:
                        wall[on].append((time.perf_counter() - start) * 1e3)
                        total[on].append(result.stats.times_ms["total"])
            (on, off), (total_on, total_off) = ([statistics.median(v[k]) for k in (True, False)] for v in (wall, total))
            print(f"{path.stem:16s} {label:20s} on {on:7.3f} (total {total_on:7.3f})  off {off:7.3f} (total "
                  f"{total_off:7.3f})  history costs {on - off:+.3f} ms (total {total_on - total_off:+.3f})", flush=True)
        for label, timed in (("path 1 spp, frozen", lambda: timed_path(scene, 1, -1, 0, repeats=args.frames, frozen=True)),
                             ("path + OIDN 'fast'", lambda: timed_path_denoised(scene, 1, -1, 0, repeats=args.frames,
                                                                                quality="fast"))):
            print(f"{path.stem:16s} {label:20s} {statistics.median(timed()[1]):7.3f}", flush=True)


if __name__ == "__main__":
    main()
