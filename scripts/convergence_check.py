"""CPU checks behind two statements in docs/results (issue 11): the hybrid's FLIP falls with spp
per frame (the per-pass random streams are independent), and with a still camera the denoised
history and the plain mean of the frames meet as they converge.

    .venv/bin/python scripts/convergence_check.py [--scene ../shared/scenes/models/armadillo.xml]
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scene", default=str(ROOT.parent / "shared" / "scenes" / "models" / "armadillo.xml"))
    parser.add_argument("--frames", type=int, default=32)
    args = parser.parse_args()

    import mitsuba as mi
    import numpy as np

    mi.set_variant("llvm_ad_rgb")
    import hybrid_integrator as hi
    from hybrid_integrator.raster.camera import sensor_to_world
    from hybrid_integrator.metrics import image_error

    def flip(image, ref) -> float:
        return image_error(np.array(image), ref)[0].flip

    scene = hi.load_scene(args.scene, resx=320, resy=180)
    ref = np.array(mi.render(scene, integrator=mi.load_dict({"type": "path"}), spp=512))
    for spp in (1, 2, 4, 8):
        r = hi.render(scene, spp=spp, seed=0, layers=False)
        print(f"320x180, {spp} spp: FLIP denoised {flip(r.image, ref):.4f}, before the denoiser {flip(r.composed, ref):.4f}")
    scene = hi.load_scene(args.scene, resx=192, resy=108)
    ref = np.array(mi.render(scene, integrator=mi.load_dict({"type": "path"}), spp=1024))
    camera = sensor_to_world(scene.sensors()[0])
    for denoise in (True, False):
        frames = hi.render_sequence(scene, [camera] * args.frames, spp=1, temporal=True, denoise=denoise, layers=False)
        errors = [flip(f.image, ref) for f in frames]
        print(f"192x108 still-camera history, denoise={denoise}: FLIP at frames 1/8/{args.frames}: "
              f"{errors[0]:.4f} / {errors[7]:.4f} / {errors[-1]:.4f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
