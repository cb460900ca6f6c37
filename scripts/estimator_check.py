"""The same estimator on every backend: the hybrid's image against Mitsuba ``path`` (issue 10).

Renders the Armadillo-in-glass scene at 320×180 with 8 spp (4 frames of a still camera, the last
kept) frozen, unfrozen, with camera-ray primaries and as the raster layer alone, and prints each
image's mean and its mean absolute error relative to ``path`` at 512 spp, over the image and over
the Armadillo's pixels. Run it on ``llvm_ad_rgb`` and on ``cuda_ad_rgb``: the frozen device pass,
OptiX and the interop copy must not change what is computed.

    python scripts/estimator_check.py --models-dir ../shared/scenes/models
    python3 scripts/estimator_check.py --variant cuda_ad_rgb --models-dir /tmp/scn/models
"""
from __future__ import annotations

import argparse
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--models-dir", type=Path, default=ROOT.parent / "shared/scenes/models")
    args = parser.parse_args()

    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.raster.camera import sensor_to_world

    scene = hi.load_scene(ROOT / "scenes/armadillo_glass.xml", models_dir=str(args.models_dir), resx=320, resy=180)
    reference = np.array(mi.render(scene, integrator=mi.load_dict({"type": "path"}), spp=512, seed=1))
    gb = hi.rasterize(scene)
    armadillo = gb.shape_index == gb.shape_ids.index("armadillo")
    camera = sensor_to_world(scene.sensors()[0])
    for props in ({"freeze": True}, {"freeze": False}, {"freeze": True, "primary": "raytrace"}, {"candidates": ""}):
        frame = hi.render_sequence(scene, [camera] * 4, spp=8, **props)[-1]
        image = np.array(frame.image)[..., :3]
        error = np.abs(image - reference).mean() / reference.mean()
        print(f"{str(props):40s} mean {image.mean():.4f} (path {reference.mean():.4f}), Armadillo pixels "
              f"{image[armadillo].mean():.4f} ({reference[armadillo].mean():.4f}), relative error {error:.4f}, "
              f"rays {frame.stats.rays}")


if __name__ == "__main__":
    main()
