"""What the two corrected baselines cost on this project's CPU (stop 46), in one process:
1. the path kernels one ``mi.render`` launches (Dr.Jit's kernel history: launches of a frame's
   width, with their ms) for ``path``, ``aov`` alone (albedo, shading normal) and ``aov`` with
   ``path`` nested, on the default scene at 160×120;
2. ``path`` at 1 spp on Sponza at 320×180 as ``mi.render`` calls it and replayed from a recording
   (``compare.path_renders``), median wall ms of 10 frames.

    .venv/bin/python docs/results/gpu/issue10/stop46/baselines_cpu.py > docs/results/gpu/issue10/stop46/outputs/baselines_cpu.txt
"""
import statistics
import time
from pathlib import Path

import drjit as dr
import mitsuba as mi

mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi  # noqa: E402 - after the variant
from hybrid_integrator.compare import path_renders  # noqa: E402

ROOT = Path(__file__).resolve().parents[5]
AOVS = "albedo:albedo,nn:sh_normal"


def kernels(scene, integrator) -> list[float]:
    """ms of each kernel of the frame's width that one mi.render launches (after a warm-up)."""
    width = dr.prod(scene.sensors()[0].film().size())
    mi.render(scene, integrator=integrator, spp=1, seed=1)
    with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
        dr.kernel_history_clear()
        dr.eval(mi.render(scene, integrator=integrator, spp=1, seed=1))
        dr.sync_thread()
        return [round(float(e["execution_time"]), 2) for e in dr.kernel_history()
                if str(e["type"]).endswith("JIT") and e.get("size") == width]


def wall(render, frames: int = 10) -> float:
    render(1)
    times = []
    for seed in range(frames):
        start = time.perf_counter()
        dr.eval(render(seed + 2)[0])
        dr.sync_thread()
        times.append((time.perf_counter() - start) * 1e3)
    return round(statistics.median(times), 1)


def main() -> None:
    scene = hi.load_scene(ROOT / "scenes/default.xml", resx=160, resy=120)
    for name, spec in (("path", {"type": "path"}), ("aov alone", {"type": "aov", "aovs": AOVS}),
                       ("aov with path nested", {"type": "aov", "aovs": AOVS, "integrator": {"type": "path"}})):
        print(f"{name}: kernels of the frame's width, ms: {kernels(scene, mi.load_dict(spec))}")
    scene = hi.load_scene(ROOT / "scenes/sponza_mirror.xml", resx=320, resy=180,
                          sponza_dir=str(ROOT.parent / "shared/scenes/sponza-dabrovic"))
    path = mi.load_dict({"type": "path"})
    sensor = scene.sensors()[0]
    plain, frozen = (path_renders(scene, sensor, [path], 1, frozen=f) for f in (False, True))
    print(f"Sponza 320x180, path 1 spp: mi.render {wall(plain)} ms, frozen {wall(frozen)} ms")


if __name__ == "__main__":
    main()
