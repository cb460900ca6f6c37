"""The CPU measurements behind issue 11's notes on 1-spp noise (docs/results/README.md).

- ``error-estimate``: per object of the Armadillo scene, the learnt E of ``relevance="error"``
  after 6 default frames, and over 64 frames without the denoiser the 1-spp mean |τ(traced) −
  τ(raster)| (noise included) and the same for the mean of the traced frames (the bias alone).
  On a commit before a5775a9 the learnt E is the old mean of |d|.
- ``no-denoiser``: FLIP of the hybrid without the denoiser (raster and camera-ray primaries)
  against ``path`` at 1 spp, mean of 6 frames, reference ``path`` at 512 spp.
- ``shadow-tier``: FLIP at budgets of 0, 25, 50 and 75 % of the all-candidates trace time, with
  and without shadow tiers (nested selection, state learnt over 10 frames at 50 %).
- ``rr-depth``: the default frame (denoised) at ``rr_depth`` 5, 3, 2 and 1: mean FLIP over frames
  2-7 (± their standard deviation) and the secondary rays per frame, reference ``path`` 256 spp.

    python scripts/noise_checks.py error-estimate --resx 160 --resy 90
    python scripts/noise_checks.py no-denoiser --resx 320 --resy 180
    python scripts/noise_checks.py shadow-tier scenes/sponza_mirror.xml --resx 320 --resy 180
    python scripts/noise_checks.py rr-depth scenes/sponza_mirror.xml --resx 320 --resy 180
"""
from __future__ import annotations

import argparse
import copy
import statistics
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "scenes"
DIRS = {"models_dir": SHARED / "models", "showcase_dir": SHARED / "cbox",
        "sponza_dir": SHARED / "sponza-dabrovic", "dining_dir": SHARED / "dining-room"}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("check", choices=("error-estimate", "no-denoiser", "shadow-tier", "rr-depth"))
    parser.add_argument("scene", type=Path, nargs="?", default=ROOT / "scenes/armadillo_glass.xml")
    parser.add_argument("--resx", type=int, default=160)
    parser.add_argument("--resy", type=int, default=90)
    args = parser.parse_args()

    import mitsuba as mi
    import numpy as np

    mi.set_variant("llvm_ad_rgb")
    import hybrid_integrator as hi
    from hybrid_integrator.raster.camera import sensor_to_world
    from hybrid_integrator.api import renderer
    from hybrid_integrator.budget import FrameState
    from hybrid_integrator.compare import render_path
    from hybrid_integrator.metrics import flip_map
    from hybrid_integrator.pipeline import HybridSettings

    text = args.scene.read_text()
    params = {"resx": args.resx, "resy": args.resy, **{k: str(v) for k, v in DIRS.items() if "$" + k in text}}
    scene = hi.load_scene(args.scene, **params)
    camera = sensor_to_world(scene.sensors()[0])
    hybrid = renderer(scene)

    def reference(spp: int) -> np.ndarray:
        return np.array(render_path(scene, spp, -1, seed=1))

    if args.check == "error-estimate":
        state = FrameState()
        for seed in range(6):
            hybrid.render(HybridSettings(), seed=seed, spp=1, state=state)
        tone = lambda c: (lambda y: y / (1 + y))(c @ np.array([0.212671, 0.715160, 0.072169]))  # noqa: E731
        frames = [hybrid.render(HybridSettings(denoise=False), seed=s, spp=1, state=FrameState()).layers for s in range(64)]
        obj = hi.rasterize(scene).shape_index
        d1 = tone(frames[0]["rt"]) - tone(frames[0]["raster"])
        dmean = tone(np.mean([f["rt"] for f in frames], axis=0)) - tone(frames[0]["raster"])
        for k, name in enumerate(hybrid.objects.names):
            m = (obj == k) & (frames[0]["traced"] > 0.5)
            print(f"{name}: learnt E {state.error_per_pixel[k]:.3f}; 1 spp mean |d| {np.abs(d1[m]).mean():.3f}, "
                  f"64-frame mean |d| {np.abs(dmean[m]).mean():.3f} ({m.sum()} pixels)")
    elif args.check == "no-denoiser":
        truth = reference(512)
        path = [flip_map(np.array(render_path(scene, 1, -1, seed=s)), truth)[1] for s in range(6)]
        print(f"path 1 spp: FLIP {np.mean(path):.4f}")
        for primary in ("raster", "raytrace"):
            frames = hi.render_sequence(scene, [camera] * 6, spp=1, layers=False, denoise=False, primary=primary)
            print(f"hybrid, no denoiser, {primary} primaries: FLIP {np.mean([flip_map(np.array(f.image), truth)[1] for f in frames]):.4f}")
    elif args.check == "rr-depth":
        truth = reference(256)
        for rr in (5, 3, 2, 1):
            state = FrameState()
            frames = [hybrid.render(HybridSettings(rr_depth=rr), seed=s, spp=1, state=state, layers=False) for s in range(8)][2:]
            flips = [flip_map(np.array(f.image), truth)[1] for f in frames]
            print(f"rr_depth {rr}: FLIP {np.mean(flips):.4f} ± {np.std(flips):.4f}, "
                  f"secondary rays {statistics.median(f.stats.secondary_rays for f in frames):.0f}")
    else:
        truth = reference(256)
        trace_ms = statistics.median(hybrid.render(HybridSettings(), seed=s, spp=1).stats.times_ms["trace"] for s in range(4))
        for tier in (False, True):
            state = FrameState()
            for seed in range(10):
                hybrid.render(HybridSettings(budget_ms=0.5 * trace_ms, shadow_tier=tier), seed=seed, spp=1, state=state, layers=False)
            for fraction in (0.0, 0.25, 0.5, 0.75):
                settings = HybridSettings(budget_ms=max(fraction * trace_ms, 1e-6), shadow_tier=tier)
                learnt = copy.deepcopy(state)
                frame = [hybrid.render(settings, seed=20 + s, spp=1, state=learnt, layers=False) for s in range(3)][-1]
                print(f"shadow tiers {'on ' if tier else 'off'} {fraction:4.0%}: FLIP {flip_map(np.array(frame.image), truth)[1]:.4f}, "
                      f"trace {frame.stats.times_ms['trace']:.1f} ms, {len(frame.stats.selected)} objects traced, "
                      f"{len(frame.stats.shadow_only)} by their shadow tier")


if __name__ == "__main__":
    main()
