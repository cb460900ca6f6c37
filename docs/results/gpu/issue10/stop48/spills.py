"""What OptiX makes of the two megakernels (stop 48): Mitsuba's ``path`` at 1 spp and the hybrid's
all-candidates trace, per scene, compiled in this process (the disk caches emptied by run.sh). OptiX's
compiler reports each entry function's registers and spills on stderr at Dr.Jit's log level Info
(the hybrid's recording sets Debug by itself: ``frozen.py``); markers between the renders tell which
is which. Device times: ``path``'s longest kernel (kernel history), the hybrid's trace stage
(its own ``times_ms``), medians of FRAMES.

    python3 docs/results/gpu/issue10/stop48/spills.py SCENE.xml -D … 2> spills.log
"""
import argparse
import statistics
import sys


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("-D", dest="defines", action="append", default=[])
    args = parser.parse_args()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("cuda_ad_rgb")
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.raster.camera import sensor_to_world

    scene, name = load_bench_scene(args.scene, dict(d.split("=", 1) for d in args.defines))
    width = dr.prod(scene.sensors()[0].film().size())

    def biggest(run) -> float:
        with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
            dr.kernel_history_clear()
            run()
            dr.sync_thread()
            times = [float(e["execution_time"]) for e in dr.kernel_history()
                     if str(e["type"]).endswith("JIT") and e.get("size") == width]
        return max(times)

    path = (lambda: dr.eval(mi.render(scene, spp=1, seed=1)))
    hybrid = (lambda: hi.render(scene, layers=False, denoise=False).stats.times_ms["trace"])
    for label, run in (("path", path), ("hybrid", hybrid)):
        print(f"=== {name} {label}: compiling", file=sys.stderr, flush=True)
        level = dr.log_level()
        dr.set_log_level(dr.LogLevel.Info)
        run()
        dr.sync_thread()
        dr.set_log_level(level)
        print(f"=== {name} {label}: compiled", file=sys.stderr, flush=True)
    ms = statistics.median(biggest(path) for _ in range(args.frames))
    print(f"{name} path: longest kernel of the frame's width, median of {args.frames}: {ms:.3f} ms", flush=True)
    ms = statistics.median(hybrid() for _ in range(args.frames))
    print(f"{name} hybrid: trace stage, median of {args.frames}: {ms:.3f} ms", flush=True)


if __name__ == "__main__":
    main()
