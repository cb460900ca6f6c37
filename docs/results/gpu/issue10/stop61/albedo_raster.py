"""The raster layer alone (nothing traced, no learnt term, no denoiser) against ``path``, with the
G-buffer's albedo as Mitsuba gives it (before stop 61) and as now (0 where the BSDF has no diffuse
lobe, never above 1: ``raster.gbuffer.aov_values``), and the objects whose pixels err most with
each. On the CPU:

    .venv/bin/python docs/results/gpu/issue10/stop61/albedo_raster.py scenes/dining_room.xml \\
        -D resx=320 -D resy=180 -D dining_dir=../shared/scenes/dining-room
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "stop60"))
from turn_error import albedo_as  # noqa: E402


def main() -> None:
    from hybrid_integrator.bench import load_bench_scene, turn_arguments

    parser = turn_arguments(__doc__.splitlines()[0])
    parser.add_argument("--gt-spp", type=int, default=256)
    args = parser.parse_args()
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import renderer
    from hybrid_integrator.compare import render_path
    from hybrid_integrator.metrics import flip_map, relative_mse
    from hybrid_integrator.pipeline import HybridSettings

    for path in args.scenes:
        scene, name = load_bench_scene(str(path), dict(args.defines))
        truth = np.array(render_path(scene, args.gt_spp, -1, seed=99))[..., :3]
        shown = hi.rasterize(scene).shape_index
        names = hi.scene_objects(scene).names
        made, recorded = renderer(scene), {}
        for raw in (True, False):
            albedo_as(made, recorded, raw)
            settings = HybridSettings(candidates="", learn_ambient=False, denoise=False)
            image = np.array(made.render(settings, seed=3, spp=1, layers=False).image)[..., :3]
            print(f"{name} albedo {'as Mitsuba gives it' if raw else 'now'}: FLIP {flip_map(image, truth)[1]:.4f}, "
                  f"rel. MSE {relative_mse(image, truth):.4f}", flush=True)
            square = ((image - truth) ** 2).mean(axis=2)
            worst = sorted(np.unique(shown[shown >= 0]), key=lambda k: -square[shown == k].sum())[:5]
            for k in worst:
                m = shown == k
                print(f"    {names[k]}: {m.sum()} px, squared error {square[m].sum():.1f}, mean {image[m].mean():.3f} "
                      f"against path's {truth[m].mean():.3f}")
        albedo_as(made, recorded, False)


if __name__ == "__main__":
    main()
