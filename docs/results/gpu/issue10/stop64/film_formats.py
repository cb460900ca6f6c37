"""Stop 64's device check of pipeline.Development on cuda_ad_rgb: a bench scene's film in each
hdrfilm pixel format (rgb, xyz, luminance, with alpha), the default frame (denoised: Open Image
Denoise's CUDA device) and with temporal accumulation, against the rgb(a) frame converted as the
film converts (mi.srgb_to_xyz, mi.luminance), and the frame's median time per format (20 warm
frames after 5, one synchronization each, ``stage_times=false`` as the bench times a frame), one
format after another: frames of different scenes in turn each re-took the scene's variables
(``frozen.FrozenScene``), 430-480 ms a frame on an H100 (stop 64's first run). A control: the rgb scene loaded
a second time against the first (two loads of one file render the same frame to float rounding,
which the denoiser can make larger: the noise floor of the check).

    python3 docs/results/gpu/issue10/stop64/film_formats.py scenes/showcase.xml -D showcase_dir=... [--variant cuda_ad_rgb]
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT))

FORMATS = ("rgb", "xyz", "luminance", "rgba", "xyza", "luminance_alpha", "rgb (loaded again)")


def main() -> int:
    from hybrid_integrator.cli import typed_property

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("-D", dest="defines", action="append", default=[], type=typed_property)
    parser.add_argument("--variant", default="cuda_ad_rgb")
    parser.add_argument("--frames", type=int, default=20)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    text = args.scene.read_text()
    assert 'name="pixel_format" value="rgb"' in text.replace(" />", "/>").replace('" /', '"/')
    scenes = {}
    for fmt in FORMATS:  # beside the original, so that its relative paths hold
        path = args.scene.with_name(f"_{args.scene.stem}_{fmt.split()[0]}.xml")
        path.write_text(text.replace('value="rgb"', f'value="{fmt.split()[0]}"', 1))
        scenes[fmt] = hi.load_scene(path, **dict(args.defines))
        path.unlink()
    out = {"command": " ".join(sys.argv), "variant": args.variant, "check": {}, "frame_ms": {}}
    for temporal in (False, True):
        images = {fmt: np.array(hi.render(scene, spp=1, seed=7, temporal=temporal, layers=False).image)
                  for fmt, scene in scenes.items()}
        for fmt in FORMATS:
            if fmt in ("rgb", "rgba"):  # the references
                continue
            srgb = images["rgba" if fmt.endswith("a") else "rgb"]
            to_film = {"l": mi.luminance, "x": mi.srgb_to_xyz, "r": lambda c: c}[fmt[0]]
            colour = np.array(dr.ravel(to_film(mi.Color3f(*(srgb[..., k].ravel() for k in range(3)))))).reshape(
                *srgb.shape[:2], -1)
            image = images[fmt]
            n = colour.shape[2]
            out["check"][f"{fmt}, temporal={temporal}"] = {
                "shape": list(image.shape),
                "max_abs_diff_colour": float(np.abs(image[..., :n] - colour).max()),
                "max_abs_diff_alpha": float(np.abs(image[..., -1] - srgb[..., 3]).max()) if fmt.endswith("a") else None}
    times = {fmt: [] for fmt in FORMATS}
    for fmt in FORMATS:
        integrator = hi.api._integrator({"stage_times": False})
        for k in range(args.frames + 5):
            dr.sync_thread()
            start = time.perf_counter()
            image = integrator.render_result(scenes[fmt], seed=k, spp=1, layers=False).image
            dr.eval(image)
            dr.sync_thread()
            if k >= 5:
                times[fmt].append((time.perf_counter() - start) * 1e3)
    out["frame_ms"] = {fmt: statistics.median(v) for fmt, v in times.items()}
    print(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
