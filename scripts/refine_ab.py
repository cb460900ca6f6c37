"""Probe: where the raster's refined pixels are traced (``refine``: ``primary`` or ``trace``),
against each other and the RT baseline, in one process: per scene, the three integrators render
``--repeats`` frames in turn after three warm-up rounds (``bench.frames_in_turn``), and the
medians of their frame times, of the paired ratios ``primary / trace`` and ``RT / hybrid``
(Gain), and of the device time per stage are printed as a Markdown table.

    python3 scripts/refine_ab.py --variant cuda_ad_rgb --repeats 21 SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

import statistics

from raster_cull_probe import arguments

SIDES = {"primary": dict(refine="primary"), "trace": dict(refine="trace"), "rt": dict(primary="raytrace")}
STAGES = ("raster", "lighting", "trace")


def main() -> None:
    import mitsuba as mi
    import numpy as np

    args = arguments(__doc__)
    mi.set_variant(args.variant)
    from hybrid_integrator.bench import frames_in_turn, load_bench_scene

    print(f"| scene | frame, primary | frame, trace | RT | primary / trace | Gain, primary | Gain, trace "
          f"| {' | '.join(f'{s}: primary / trace' for s in STAGES)} |")
    print("|---" * (6 + len(STAGES)) + "|---|")
    for spec in args.scenes:
        scene, name = load_bench_scene(spec, dict(d.split("=", 1) for d in args.defines))
        frames = frames_in_turn(scene, SIDES, args.repeats, 1, 0)
        total = {side: np.array([t["total"] for t in frames[side]]) for side in SIDES}

        def median(side, key):
            return statistics.median(t[key] for t in frames[side])

        ratios = [np.median(total["primary"] / total["trace"]), np.median(total["rt"] / total["primary"]),
                  np.median(total["rt"] / total["trace"])]
        stages = " | ".join(f"{median('primary', s):.3f} / {median('trace', s):.3f}" for s in STAGES)
        print(f"| {name} | {np.median(total['primary']):.2f} | {np.median(total['trace']):.2f} | "
              f"{np.median(total['rt']):.2f} | {ratios[0]:.3f} | {ratios[1]:.3f} | {ratios[2]:.3f} | {stages} |",
              flush=True)


if __name__ == "__main__":
    main()
