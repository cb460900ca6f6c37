"""Probe: the raster's refined pixels, two ways against each other and the RT baseline.

``--compare refine`` (the default): where they are traced (``refine``: ``primary`` or ``trace``);
``--compare outline``: which outline pixels are refined (``outline``: ``silhouettes`` or ``ties``,
``primary.OUTLINES``). Per scene, in a process of its own, the three integrators render
``--repeats`` frames in turn after three warm-up rounds (``bench.frames_in_turn``), and the medians
of their frame times, of the paired ratios ``A / B`` and ``RT / hybrid`` (Gain), and of the device
time per stage are printed as a Markdown table. (Five scenes in one process made the later scenes'
frames slower for all three integrators alike on the H200: the dining room's RT frame
20.2–20.6 ms after four other scenes, 16.7–17.5 in a process of its own,
``docs/results/gpu/issue10/stop33``; the bench too runs each scene in its own process.)

    python3 scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 SCENE... -D resx=1280 -D resy=720
    python3 scripts/refine_ab.py --compare outline --variant cuda_ad_rgb --repeats 21 SCENE... $D
"""
from __future__ import annotations

import statistics

from raster_cull_probe import each_scene_alone, parser  # scripts/ is on sys.path when a script runs

HEADER = 2  # the table's header lines, printed once

#: per comparison, its two hybrid sides (name → the integrator's properties)
COMPARISONS = {"refine": {"primary": dict(refine="primary"), "trace": dict(refine="trace")},
               "outline": {"silhouettes": dict(outline="silhouettes"), "ties": dict(outline="ties")}}
STAGES = ("raster", "lighting", "trace")


def main() -> None:
    import mitsuba as mi
    import numpy as np

    p = parser(__doc__)
    p.add_argument("--compare", choices=list(COMPARISONS), default="refine")
    args = p.parse_args()
    if each_scene_alone(__file__, args, ["--compare", args.compare], HEADER):
        return
    mi.set_variant(args.variant)
    from hybrid_integrator.bench import frames_in_turn, load_bench_scene

    sides = dict(COMPARISONS[args.compare], rt=dict(primary="raytrace"))
    a, b = list(COMPARISONS[args.compare])
    print(f"| scene | frame, {a} | frame, {b} | RT | {a} / {b} | Gain, {a} | Gain, {b} "
          f"| {' | '.join(f'{s}: {a} / {b}' for s in STAGES)} |")
    print("|---" * (6 + len(STAGES)) + "|---|")
    for spec in args.scenes:
        scene, name = load_bench_scene(spec, dict(d.split("=", 1) for d in args.defines))
        frames = frames_in_turn(scene, sides, args.repeats, 1, 0)
        total = {side: np.array([t["total"] for t in frames[side]]) for side in sides}

        def median(side, key):
            return statistics.median(t[key] for t in frames[side])

        ratios = [np.median(total[a] / total[b]), np.median(total["rt"] / total[a]), np.median(total["rt"] / total[b])]
        stages = " | ".join(f"{median(a, s):.3f} / {median(b, s):.3f}" for s in STAGES)
        print(f"| {name} | {np.median(total[a]):.2f} | {np.median(total[b]):.2f} | "
              f"{np.median(total['rt']):.2f} | {ratios[0]:.3f} | {ratios[1]:.3f} | {ratios[2]:.3f} | {stages} |",
              flush=True)


if __name__ == "__main__":
    main()
