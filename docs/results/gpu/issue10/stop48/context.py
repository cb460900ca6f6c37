"""Does the hybrid's OpenGL context slow CUDA's kernels down (stop 48)? In one process: Mitsuba's
``path`` at 1 spp (``max_depth`` -1, as the hybrid's) before any OpenGL context exists, then the hybrid (which makes its EGL context,
maps its interop targets and draws), then ``path`` again, and so on in turn; per round, ``path``'s
longest kernel (kernel history) and the hybrid's trace stage (its own ``times_ms``), medians of
FRAMES, all candidates, no denoiser. ``--hybrid "k=v,k=v"`` (repeated) adds hybrid sides with
those integrator properties (default: one side, the integrator's defaults); ``STOP48_LOOP`` changes the
trace loop (``loop_variants.py``).

    python3 docs/results/gpu/issue10/stop48/context.py SCENE.xml --rounds 3 -D …
    python3 docs/results/gpu/issue10/stop48/context.py SCENE.xml --hybrid "" --hybrid primary=raytrace --hybrid refine=primary -D …
"""
import argparse
import sys
from pathlib import Path
import statistics


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--hybrid", action="append", default=None, help="a hybrid side's properties, k=v,k=v")
    parser.add_argument("-D", dest="defines", action="append", default=[])
    args = parser.parse_args()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("cuda_ad_rgb")
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    sys.path.insert(0, str(Path(__file__).parent))
    from loop_variants import apply  # the trace loop's variants named by STOP48_LOOP (default: none)
    loop = apply()

    scene, name = load_bench_scene(args.scene, dict(d.split("=", 1) for d in args.defines))
    width = dr.prod(scene.sensors()[0].film().size())
    integrator = mi.load_dict({"type": "path", "max_depth": -1})  # the hybrid's default (and the bench's)

    def path() -> float:
        with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
            dr.kernel_history_clear()
            dr.eval(mi.render(scene, integrator=integrator, spp=1, seed=1))
            dr.sync_thread()
            return max(float(e["execution_time"]) for e in dr.kernel_history()
                       if str(e["type"]).endswith("JIT") and e.get("size") == width)

    sides = {spec: dict(kv.split("=", 1) for kv in spec.split(",") if kv) for spec in (args.hybrid or [""])}

    def hybrid(props: dict) -> float:
        return hi.render(scene, layers=False, denoise=False, **props).stats.times_ms["trace"]

    path(), path()
    for r in range(args.rounds):
        p = statistics.median(path() for _ in range(args.frames))
        times = []
        for spec, props in sides.items():
            if r == 0:
                hybrid(props), hybrid(props)
            times.append(f"hybrid [{spec}] trace {statistics.median(hybrid(props) for _ in range(args.frames)):.3f} ms")
        p2 = statistics.median(path() for _ in range(args.frames))
        print(f"{name} loop {loop} round {r}: path {p:.3f} ms, {', '.join(times)}, path after {p2:.3f} ms", flush=True)


if __name__ == "__main__":
    main()
