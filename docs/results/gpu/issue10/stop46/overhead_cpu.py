"""The full-quality frame against frozen `path`, on this project's CPU, in one process: the hybrid
and the RT baseline (every object traced, no denoiser) and Mitsuba's `path` at 1 spp replayed from a
recording (`compare.path_renders`), in turn, 15 frames each after warm-up; wall ms per frame
(median) and the last frame's stage times. Sponza at 320×180 (the GPU's numbers: README.md).

    .venv/bin/python docs/results/gpu/issue10/stop46/overhead_cpu.py > docs/results/gpu/issue10/stop46/outputs/overhead_cpu.txt
"""
import statistics
import time
from pathlib import Path

import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi  # noqa: E402 - after the variant
from hybrid_integrator.api import renderer  # noqa: E402
from hybrid_integrator.budget import FrameState  # noqa: E402
from hybrid_integrator.compare import path_renders  # noqa: E402
from hybrid_integrator.pipeline import HybridSettings  # noqa: E402

ROOT = Path(__file__).resolve().parents[5]


def main() -> None:
    scene = hi.load_scene(ROOT / "scenes/sponza_mirror.xml", resx=320, resy=180,
                          sponza_dir=str(ROOT.parent / "shared/scenes/sponza-dabrovic"))
    frames = renderer(scene)
    path = path_renders(scene, scene.sensors()[0], [mi.load_dict({"type": "path"})], 1, frozen=True)
    path(99), path(98)  # warm-up (path_renders made the first recording; Dr.Jit may record once more)
    sides = {"hybrid": HybridSettings(denoise=False), "rt": HybridSettings(denoise=False, primary="raytrace")}
    states = {k: FrameState() for k in sides}
    for k, settings in sides.items():  # warm-up: compilation, recordings, the cost model
        for seed in range(4):
            frames.render(settings, seed=seed, spp=1, state=states[k], layers=False)
    wall, stages = {k: [] for k in [*sides, "path"]}, {}
    for seed in range(15):
        for k, settings in sides.items():
            start = time.perf_counter()
            frame = frames.render(settings, seed=seed, spp=1, state=states[k], layers=False)
            dr.sync_thread()
            wall[k].append((time.perf_counter() - start) * 1e3)
            stages[k] = frame.stats.times_ms
        start = time.perf_counter()
        dr.eval(path(seed)[0])
        dr.sync_thread()
        wall["path"].append((time.perf_counter() - start) * 1e3)
    for k, times in wall.items():
        print(k, round(statistics.median(times), 2))
    for k, times in stages.items():
        print(k, {stage: round(ms, 2) for stage, ms in times.items()})


if __name__ == "__main__":
    main()
