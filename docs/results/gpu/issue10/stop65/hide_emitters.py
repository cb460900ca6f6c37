"""Stop 65's check of ``hide_emitters`` (primary.first_hits): Mitsuba's ``path`` hides area emitters
from camera rays altogether, its camera rays passing through them; the hybrid now does the same.

``check`` (any variant): on ``stability.hidden_emitter_scene`` (64×48), the hybrid frame (64 spp, no
denoiser) with raster primaries (the variant's default ``refine``, and ``refine="primary"``) and
with camera rays, against ``path`` at 1024 spp: image means, the largest difference of 8×8 block
means, the hidden-emitter refinements. Then the panel scene, the ball behind it analytic or a
mesh: over the pixels where the panel is the first hit, the mean of ``path`` and of the hybrid
(``path`` measures the hit past the panel from the panel, and makes its surface interaction
against the camera ray: on the analytic ball that misplaces it).
``time`` (a bench scene): its default frame with ``hide_emitters`` off and on, in turn
(``bench.frames_in_turn``: 20 measured frames each after 5 rounds of warm-up, one synchronization
per frame, ``stage_times=false``), the median frames and the paired ratio on / off.

    python3 docs/results/gpu/issue10/stop65/hide_emitters.py check [--variant cuda_ad_rgb]
    python3 docs/results/gpu/issue10/stop65/hide_emitters.py time scenes/showcase.xml -D showcase_dir=... [--variant ...]
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[5]))


def check(out: dict) -> None:
    import mitsuba as mi
    import numpy as np

    import hybrid_integrator as hi
    from hybrid_integrator.primary import camera_rays
    from hybrid_integrator.stability import hidden_emitter_scene, load

    path = np.array(mi.render(load(dict(hidden_emitter_scene(), integrator={"type": "path", "hide_emitters": True})),
                              spp=1024, seed=3))[..., :3]
    blocks = lambda img: img.reshape(6, 8, 8, 8, 3).mean(axis=(1, 3))  # noqa: E731
    out["path_mean"] = float(path.mean())
    for name, props in {"raster (default refine)": {}, "raster, refine=primary": {"refine": "primary"},
                        "camera rays": {"primary": "raytrace"}}.items():
        result = hi.render(load(hidden_emitter_scene()), spp=64, seed=3, denoise=False, hide_emitters=True, **props)
        image = np.array(result.image)[..., :3]
        out[name] = {"mean": float(image.mean()), "max_block_diff_over_mean": float(np.abs(blocks(image) - blocks(path)).max() / path.mean()),
                     "emitter_refinements": result.stats.emitter_refinements}
    for ball in ("analytic", "mesh"):
        scene_dict = hidden_emitter_scene(ball)
        scene = load(scene_dict)
        si = scene.ray_intersect(camera_rays(scene.sensors()[0], 64, 48, (0.5, 0.5)))
        panel = np.array(si.is_valid()) & (np.abs(np.array(si.p.z) - 1.5) < 1e-3)  # the panel lies in the plane z = 1.5
        truth = np.array(mi.render(load(dict(scene_dict, integrator={"type": "path", "hide_emitters": True})), spp=1024, seed=3))[..., :3]
        ours = np.array(hi.render(load(scene_dict), spp=256, seed=3, denoise=False, hide_emitters=True).image)[..., :3]
        mask = panel.reshape(48, 64)
        out[f"panel pixels, {ball} ball"] = {"pixels": int(mask.sum()), "path": float(truth[mask].mean()), "hybrid": float(ours[mask].mean())}


def timing(out: dict, scene_path: Path, defines: dict, frames: int) -> None:
    import hybrid_integrator as hi
    from hybrid_integrator.bench import frames_in_turn, paired_ratio

    scene = hi.load_scene(scene_path, **defines)
    refinements = {}
    sides = {f"hide_emitters={hide}": {"stage_times": False, "hide_emitters": hide} for hide in (False, True)}
    times = frames_in_turn(scene, sides, frames, spp=1, seed=0, warmup=5,
                           after=lambda name, at, result: refinements.__setitem__(name, result.stats.emitter_refinements))
    for name, entries in times.items():
        out[name] = {"frame_ms": statistics.median(t["total"] for t in entries), "emitter_refinements": refinements[name]}
    out["paired on / off"] = paired_ratio(times, "hide_emitters=True", "hide_emitters=False")


def main() -> int:
    from hybrid_integrator.cli import typed_property

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("mode", choices=("check", "time"))
    parser.add_argument("scene", type=Path, nargs="?")
    parser.add_argument("-D", dest="defines", action="append", default=[], type=typed_property)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=20)
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    out = {"command": " ".join(sys.argv), "variant": args.variant}
    if args.mode == "check":
        check(out)
    else:
        timing(out, args.scene, dict(args.defines), args.frames)
    print(json.dumps(out, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
