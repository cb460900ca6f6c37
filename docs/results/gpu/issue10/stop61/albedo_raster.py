"""The raster layer alone (nothing traced, no learnt term, no denoiser) against ``path``, with the
G-buffer's albedo as Mitsuba gives it (before stop 61) and as now (0 where the BSDF has no diffuse
lobe, never above 1: ``raster.gbuffer.aov_values``), and the objects whose pixels err most with
each, with their largest albedo. First, what Mitsuba's ``eval_diffuse_reflectance`` gives for a few
BSDFs seen at 0, 0.5 and 1.2 rad from the normal. On the CPU:

    .venv/bin/python docs/results/gpu/issue10/stop61/albedo_raster.py scenes/dining_room.xml \\
        -D resx=320 -D resy=180 -D dining_dir=../shared/scenes/dining-room
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "stop60"))
from turn_error import albedo_as  # noqa: E402


BSDFS = {"diffuse": {"type": "diffuse"},
         "roughconductor (Cu, alpha 0.2)": {"type": "roughconductor", "material": "Cu", "alpha": 0.2},
         "roughdielectric (alpha 0.2)": {"type": "roughdielectric", "alpha": 0.2},
         "blendbsdf (diffuse, roughconductor alpha 0.1)": {"type": "blendbsdf", "weight": 0.5, "a": {"type": "diffuse"},
                                                           "b": {"type": "roughconductor", "alpha": 0.1}},
         "pplastic": {"type": "pplastic"}}


def mitsuba_albedos() -> None:
    """Print ``eval_diffuse_reflectance`` (its first channel) of each of :data:`BSDFS` at three
    viewing angles, and whether the BSDF has a diffuse lobe."""
    import drjit as dr
    import mitsuba as mi

    angles = np.array([0.0, 0.5, 1.2])
    si = dr.zeros(mi.SurfaceInteraction3f, len(angles))
    si.sh_frame = mi.Frame3f(mi.Vector3f(0, 0, 1))
    si.wi = mi.Vector3f(mi.Float(np.sin(angles)), 0, mi.Float(np.cos(angles)))
    for label, spec in BSDFS.items():
        bsdf = mi.load_dict(spec)
        value = np.array(bsdf.eval_diffuse_reflectance(si))[0]
        print(f"{label}: diffuse lobe {mi.has_flag(bsdf.flags(), mi.BSDFFlags.DiffuseReflection)}, "
              f"eval_diffuse_reflectance at {', '.join(f'{a} rad' for a in angles)}: {', '.join(f'{v:.3f}' for v in value)}")


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

    mitsuba_albedos()
    settings = HybridSettings(candidates="", learn_ambient=False, denoise=False)
    for path in args.scenes:
        scene, name = load_bench_scene(str(path), dict(args.defines))
        truth = np.array(render_path(scene, args.gt_spp, -1, seed=99))[..., :3]
        shown = hi.rasterize(scene).shape_index.ravel()
        names = hi.scene_objects(scene).names
        hit = shown >= 0
        made, recorded = renderer(scene), {}
        for raw in (True, False):
            albedo_as(made, recorded, raw)
            frame = made.render(settings, seed=3, spp=1, aovs=("albedo",))
            image = np.array(frame.image)[..., :3]
            print(f"{name} albedo {'as Mitsuba gives it' if raw else 'now'}: FLIP {flip_map(image, truth)[1]:.4f}, "
                  f"rel. MSE {relative_mse(image, truth):.4f}, largest albedo {frame.layers['albedo'].max():.1f}", flush=True)
            pixels = [image.reshape(-1, 3)[hit].mean(axis=1), truth.reshape(-1, 3)[hit].mean(axis=1),
                      ((image - truth) ** 2).mean(axis=2).ravel()[hit], frame.layers["albedo"].reshape(-1, 3)[hit].max(axis=1)]
            count = np.bincount(shown[hit], minlength=len(names))
            mean, path_mean, square = (np.bincount(shown[hit], weights=v, minlength=len(names)) for v in pixels[:3])
            largest = np.zeros(len(names))
            np.maximum.at(largest, shown[hit], pixels[3])
            for k in np.argsort(-square)[:5]:
                print(f"    {names[k]}: {count[k]} px, squared error {square[k]:.1f}, mean {mean[k] / count[k]:.3f} "
                      f"against path's {path_mean[k] / count[k]:.3f}, largest albedo {largest[k]:.1f}")
        albedo_as(made, recorded, False)


if __name__ == "__main__":
    main()
