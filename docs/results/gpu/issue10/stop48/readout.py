"""What reading a frame's stage times costs, before and after stop 48 (``history.py``): in one
process, hybrid frames (all candidates, the default denoiser) whose kernel history is read through
``drjit.kernel_history`` (the source of every kernel copied into Python, as before) or through
Dr.Jit's C API (``history.reader``), in blocks of FRAMES, in turn, ROUNDS times. Per side: the
median host time of the readout (``host_ms["timing"]``), of the frame's ``total`` (which now
includes it) and of the wall clock around ``render``, and the frame's largest kernel's operations.

    python3 docs/results/gpu/issue10/stop48/readout.py SCENE.xml --variant cuda_ad_rgb -D …
"""
import argparse
import statistics
import time


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("-D", dest="defines", action="append", default=[])
    args = parser.parse_args()
    import drjit as dr
    import mitsuba as mi
    mi.set_variant(args.variant)
    from hybrid_integrator import history
    from hybrid_integrator.api import renderer
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.budget import FrameState
    from hybrid_integrator.pipeline import HybridSettings

    scene, name = load_bench_scene(args.scene, dict(d.split("=", 1) for d in args.defines))
    frames = renderer(scene)
    readers = {"drjit.kernel_history": dr.kernel_history, "C API": history.reader()}
    settings, state = HybridSettings(), FrameState()
    for seed in range(4):  # compilation, recordings, warm-up
        frames.render(settings, seed=seed, spp=1, state=state, layers=False)
    out = {k: {"timing": [], "total": [], "wall": []} for k in readers}
    for r in range(args.rounds):
        for label, read in readers.items():
            frames.clock.read = read
            for seed in range(args.frames):
                start = time.perf_counter()
                frame = frames.render(settings, seed=seed, spp=1, state=state, layers=False)
                out[label]["wall"].append((time.perf_counter() - start) * 1e3)
                out[label]["timing"].append(frame.stats.host_ms["timing"])
                out[label]["total"].append(frame.stats.times_ms["total"])
    ops = max(e.get("operation_count", 0) for _, e in frames.clock.last)
    for label, v in out.items():
        print(f"{name} [{label}] readout {statistics.median(v['timing']):.3f} ms, total {statistics.median(v['total']):.3f} ms, "
              f"wall {statistics.median(v['wall']):.3f} ms ({len(v['wall'])} frames; largest kernel {ops} operations)", flush=True)


if __name__ == "__main__":
    main()
