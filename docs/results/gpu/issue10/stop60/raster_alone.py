"""The raster layer alone against Mitsuba's ``path`` (issue 10, stop 60; run on the CPU).

A frame that traces nothing (``candidates=""``, no learnt ambient term, no denoiser) is the
deferred lighting of ``lighting.py`` alone. Per scene (the showcase and Sponza from their sensor,
the 226 objects from poses 5, 19 and 30 of their 40-pose path) prints its FLIP and relative MSE
against ``path`` at ``--gt-spp`` (cached in ``--cache``). Run before and after
``diffs/area_disk.diff`` (each area-light sample as a disk of its share of the area), it measures
what that model changes.

    .venv/bin/python docs/results/gpu/issue10/stop60/raster_alone.py
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[5]
SHARED = ROOT.parent / "shared" / "scenes"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    parser.add_argument("--gt-spp", type=int, default=256)
    parser.add_argument("--cache", type=Path, default=Path("/tmp/raster_alone_gt"))
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import posed
    from hybrid_integrator.bench import load_bench_scene, path_cameras
    from hybrid_integrator.compare import render_path
    from hybrid_integrator.metrics import flip_map, relative_mse
    from hybrid_integrator.raster.camera import camera_pose

    hi.register()
    args.cache.mkdir(parents=True, exist_ok=True)
    params = {"resx": str(args.resx), "resy": str(args.resy), "sponza_dir": str(SHARED / "sponza-dabrovic"),
              "showcase_dir": str(SHARED / "cbox")}
    for spec in ("scenes/showcase.xml", "scenes/sponza_mirror.xml", "scenes/many_objects.xml"):
        scene, name = load_bench_scene(str(ROOT / spec), params)
        cameras = path_cameras(ROOT / spec, 40)
        poses = [None] if cameras is None else [camera_pose(cameras[k]) for k in (5, 19, 30)]
        with posed(scene.sensors()[0]) as place:
            for j, pose in enumerate(poses):
                if pose is not None:
                    place(pose)
                cached = args.cache / f"{name}_{j}_{args.resx}x{args.resy}_{args.gt_spp}.npy"
                if not cached.exists():
                    np.save(cached, np.array(render_path(scene, args.gt_spp, -1, seed=3))[..., :3])
                truth = np.load(cached)
                image = np.array(hi.render(scene, spp=1, candidates="", denoise=False, learn_ambient=False).image)[..., :3]
                print(f"{name} {j}: raster layer FLIP {flip_map(image, truth)[1]:.4f}, relative MSE "
                      f"{relative_mse(image, truth):.4f}", flush=True)


if __name__ == "__main__":
    main()
