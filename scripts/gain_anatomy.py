"""Probe: what the raster pass costs an all-candidates hybrid frame against its RT baseline (issue 10).

The hybrid and the RT baseline trace the same rays; they differ in their primary stage alone. The
hybrid's is an OpenGL pass (host issue, GPU time), its interop copy (the map orders CUDA's stream
after OpenGL's work) and a kernel that resolves the raster's hits; the baseline's, a kernel that
traces camera rays. To see which part of the hybrid's costs the frame, four integrators render
in turn (``bench.frames_in_turn``, which rotates them from round to round), every frame at the pixel
centres (one sub-pixel offset, so that one visibility buffer serves every frame):

- ``rt``: the RT baseline (``primary="raytrace"``);
- ``hybrid``: the hybrid as it is;
- ``no-interop``: the OpenGL pass issued as usual, but the frame reads a copy of its visibility
  buffer made once (no map, no copy: CUDA's stream waits for nothing of OpenGL's);
- ``no-raster``: no OpenGL work at all, the same copy read.

The last two are stand-ins, not renderers: the frame after them is the hybrid's own, and the
differences between the three hybrid rows bound what the OpenGL pass and the interop cost the
frame. Prints, per scene, the median frame time and Gain (RT / side, median of the paired ratios)
of each side, and each side's device time per stage.

    python3 scripts/gain_anatomy.py --variant cuda_ad_rgb --repeats 21 SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

import statistics

from raster_cull_probe import each_scene_alone, parser  # scripts/ is on sys.path when a script runs

SIDES = ("rt", "hybrid", "no-interop", "no-raster")
STAGES = ("raster", "gl", "lighting", "trace", "compose", "denoise", "issue")
HEADER = 2


def main() -> None:
    import mitsuba as mi
    import numpy as np

    args = parser(__doc__).parse_args()
    if each_scene_alone(__file__, args, [], HEADER):
        return
    mi.set_variant(args.variant)
    import drjit as dr

    import hybrid_integrator as hi
    from hybrid_integrator import pipeline
    from hybrid_integrator.bench import frames_in_turn, load_bench_scene
    from hybrid_integrator.raster.camera import RasterCamera

    pipeline.subpixel_offsets = lambda spp, seed: [(0.5, 0.5)] * spp
    scene, name = load_bench_scene(args.scenes[0], dict(d.split("=", 1) for d in args.defines))
    raster = hi.api.renderer(scene).raster
    render = raster.render
    cached = {}

    def stand_in(side):
        """The rasterizer's methods for ``side`` (on this instance; the class's for the others)."""
        for attribute in ("render", "device_ids"):
            vars(raster).pop(attribute, None)
        if side in ("no-interop", "no-raster"):
            if side == "no-raster":
                raster.render = lambda camera, offset=(0.5, 0.5), method="auto": "no target"
            raster.device_ids = lambda target: cached["ids"]

    camera = RasterCamera.from_sensor(scene.sensors()[0])
    cached["ids"] = mi.UInt32(raster.read_ids(render(camera, (0.5, 0.5))))
    dr.eval(cached["ids"])
    sides = {side: {"primary": "raytrace"} if side == "rt" else {} for side in SIDES}
    times = frames_in_turn(scene, sides, args.repeats, 1, 0, before=stand_in)
    total = {side: np.array([t["total"] for t in times[side]]) for side in SIDES}
    print(f"| scene | {' | '.join(f'{s} ms' for s in SIDES)} | {' | '.join(f'Gain, {s}' for s in SIDES[1:])} "
          f"| {' | '.join(f'{s}: ' + ' / '.join(SIDES) for s in STAGES)} |")
    print("|---" * (1 + 2 * len(SIDES) - 1 + len(STAGES)) + "|")
    gains = " | ".join(f"{np.median(total['rt'] / total[s]):.3f}" for s in SIDES[1:])
    stages = " | ".join(" / ".join(f"{statistics.median(t[stage] for t in times[s]):.3f}" for s in SIDES)
                        for stage in STAGES)
    print(f"| {name} | {' | '.join(f'{np.median(total[s]):.2f}' for s in SIDES)} | {gains} | {stages} |", flush=True)


if __name__ == "__main__":
    main()
