"""How many primary hits each outline test leaves wrong, and how many pixels it refines (issue 10).

The raster's refined pixels (``primary.py``: proxies, raster misses, and the outline pixels of
``outline``) are re-traced by their camera rays. On the GPU they cost the trace launch ~0.1 ms
(Sponza, 4.5 % of its pixels at 1280×720 with ``silhouettes``; docs/results/gpu/issue10/stop34).
This probe counts, per scene, rasterizer (``draw``, OpenGL's fixed-function rasterizer, whose
vertices snap to 1/256 pixel; ``compute``, ``raster/compute.py``'s float edge functions) and
sub-pixel offset, the pixels whose primary hit differs from the camera ray's (hit or miss,
object, or distance beyond 1e-4 relative), with the share of refined pixels, for each outline
test (``primary.OUTLINES``: ``ties``, the default, and ``silhouettes``, every pixel next to
another object) and for none (``primary.silhouettes`` replaced by "no pixel", the probe's one
intervention): what each test catches, and at what share of the frame.

    python scripts/refine_need.py --resx 320 --resy 180 -o docs/results/cpu/refine_need.md
"""
from __future__ import annotations

import argparse
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "scenes"
SCENES = {"default": ROOT / "scenes" / "default.xml", "showcase": SHARED / "cbox/showcase_coloured_glass.xml",
          "sponza": SHARED / "sponza-dabrovic/scene.xml", "armadillo": SHARED / "models/armadillo.xml",
          "dining room": SHARED / "dining-room/scene.xml"}
OFFSETS = ((0.5, 0.5), (0.13, 0.77))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import primary
    from hybrid_integrator.raster.camera import RasterCamera
    from hybrid_integrator.scene import load_scene

    silhouettes = primary.silhouettes

    def wrong(ours, theirs) -> int:
        valid = np.array(theirs.valid)
        bad = np.array(ours.valid) != valid
        bad |= valid & (np.array(ours.object) != np.array(theirs.object))
        t_ours, t_theirs = np.array(ours.si.t), np.array(theirs.si.t)
        with np.errstate(invalid="ignore"):
            bad |= valid & np.array(ours.valid) & ~(np.abs(t_ours - t_theirs) <= 1e-4 * np.maximum(t_theirs, 1.0))
        return int(bad.sum())

    lines = [f"# Primary hits each outline test leaves wrong ({args.variant}, {args.resx}×{args.resy})", "",
             f"Command: `python scripts/refine_need.py --resx {args.resx} --resy {args.resy}`", "",
             "Pixels whose primary hit differs from the camera ray's, and the share of refined pixels.", "",
             "| scene | rasterizer | offset | ties: wrong / refined | silhouettes: wrong / refined "
             "| no outline test: wrong / refined |",
             "|---|---|---|---|---|---|"]
    for name, path in SCENES.items():
        scene = load_scene(str(path), resx=args.resx, resy=args.resy)
        sensor = scene.sensors()[0]
        camera = RasterCamera.from_sensor(sensor)
        w, h = camera.width, camera.height
        raster = hi.rasterizer(scene)
        for method in ("draw", "compute"):
            for offset in OFFSETS:
                ray = primary.camera_rays(sensor, w, h, offset, differentials=True)
                ids = raster.device_ids(raster.render(camera, offset, method))
                theirs = primary.traced_hits(scene, ray, raster.tables)
                cells = []
                for outline, test in (("ties", silhouettes), ("silhouettes", silhouettes),
                                      ("silhouettes", lambda label_at, width, height: dr.zeros(mi.Bool, width * height))):
                    primary.silhouettes = test
                    ours = primary.primary_hits(scene, ray, ids, w, h, raster.tables, outline)
                    cells.append(f"{wrong(ours, theirs)} / {(np.array(ours.refined) > 0).mean():.3%}")
                primary.silhouettes = silhouettes
                lines.append(f"| {name} | {method} | {offset} | {' | '.join(cells)} |")
                print(lines[-1], flush=True)
    if args.output:
        args.output.parent.mkdir(parents=True, exist_ok=True)
        args.output.write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
