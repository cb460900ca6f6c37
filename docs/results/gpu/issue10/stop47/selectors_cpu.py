"""Budgets on this project's CPU (llvm_ad_rgb, 320×180): a scene's all-candidates trace time T, then
per budget (fractions of T) 14 frames from a fresh state with the selector given, the last 6
measured: the plan's predicted and the measured trace (the last frame's) and the median FLIP
against `path` at 512 spp (denoiser on, as by default). With `--alone ID…`: instead, frames with
only those candidates and no budget (`candidates=ID`), FLIP and trace.

    .venv/bin/python docs/results/gpu/issue10/stop47/selectors_cpu.py sponza_mirror 0.25 0.5 0.75 --selection nested
    .venv/bin/python docs/results/gpu/issue10/stop47/selectors_cpu.py armadillo_glass --alone armadillo floor
"""
import argparse
import statistics
from pathlib import Path

import mitsuba as mi
import numpy as np

mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi  # noqa: E402 - after the variant
from hybrid_integrator.api import renderer  # noqa: E402
from hybrid_integrator.budget import FrameState  # noqa: E402
from hybrid_integrator.compare import ground_truth  # noqa: E402
from hybrid_integrator.metrics import flip_map  # noqa: E402
from hybrid_integrator.pipeline import HybridSettings  # noqa: E402

ROOT = Path(__file__).resolve().parents[5]
DIRS = {"models_dir": "models", "sponza_dir": "sponza-dabrovic", "showcase_dir": "cbox", "dining_dir": "dining-room"}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("fractions", nargs="*", type=float)
    parser.add_argument("--selection", default="nested")
    parser.add_argument("--alone", nargs="*", default=None)
    args = parser.parse_args()
    path = ROOT / f"scenes/{args.scene}.xml"
    params = {"resx": 320, "resy": 180} | {k: str(ROOT.parent / "shared/scenes" / v) for k, v in DIRS.items()
                                           if f"${k}" in path.read_text()}
    scene = hi.load_scene(path, **params)
    truth = ground_truth(path, scene, params, 512, -1)[0]
    frames = renderer(scene)

    def flip(frame) -> float:
        return flip_map(np.array(frame.image)[..., :3], truth)[1]

    if args.alone is not None:
        for ids in [None] + args.alone:
            settings = HybridSettings(candidates=ids)
            state, rows = FrameState(), []
            for seed in range(6):
                f = frames.render(settings, seed=seed, spp=1, state=state, layers=False)
                rows.append((flip(f), f.stats.times_ms["trace"]))
            print(ids or "every candidate", "FLIP", round(statistics.median(r[0] for r in rows[1:]), 4),
                  "trace ms", round(statistics.median(r[1] for r in rows[1:]), 2), flush=True)
        return
    state, trace = FrameState(), []
    for seed in range(6):
        trace.append(frames.render(HybridSettings(), seed=seed, spp=1, state=state, layers=False).stats.times_ms["trace"])
    everything = statistics.median(trace[2:])
    print(args.scene, args.selection, "all candidates: trace ms", round(everything, 2), flush=True)
    for fraction in args.fractions:
        settings = HybridSettings(budget_ms=fraction * everything, selection=args.selection)
        state, flips = FrameState(), []
        for seed in range(14):
            f = frames.render(settings, seed=seed, spp=1, state=state, layers=False)
            if seed >= 8:
                flips.append(flip(f))
        print(f"  {fraction:.0%}: budget {fraction * everything:.2f} predicted {f.stats.predicted_trace_ms:.2f} "
              f"trace {f.stats.times_ms['trace']:.2f} FLIP {statistics.median(flips):.4f}", flush=True)


if __name__ == "__main__":
    main()
