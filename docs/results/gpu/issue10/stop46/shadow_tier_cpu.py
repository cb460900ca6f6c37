"""The steps of ``tests/test_accuracy.py::test_shadow_tier_traces_shadows_alone_with_the_learnt_indirect_light``
run ``REPEATS`` times in one process on this project's CPU: Sponza at 128×72, a budget of three
quarters of the all-candidates trace time, greedy selection, eight frames to calibrate each run's
cost model, with shadow tiers and without; per run, each of the first four later frames that
trace something: (seed, FLIP against `path` at 128 spp, objects selected, of them by their tier,
quarters of the part traced).
What each run picks follows its own calibration, so the tiers' FLIP moves against the run without
them from calibration to calibration (stop 46: why the test compares means of four frames).

    .venv/bin/python docs/results/gpu/issue10/stop46/shadow_tier_cpu.py > docs/results/gpu/issue10/stop46/outputs/shadow_tier_cpu.txt

``--no-partial-objects`` runs both sides with whole objects only (stop 46 ran before parts existed;
since stop 75 they are on by default, and ``--partial-objects`` says so).
"""
import argparse
import itertools
from pathlib import Path

import mitsuba as mi
import numpy as np

mi.set_variant("llvm_ad_rgb")
import hybrid_integrator as hi  # noqa: E402 - after the variant
from hybrid_integrator.api import renderer  # noqa: E402
from hybrid_integrator.budget import FrameState  # noqa: E402
from hybrid_integrator.metrics import image_error  # noqa: E402
from hybrid_integrator.pipeline import HybridSettings  # noqa: E402
from hybrid_integrator.raster.camera import sensor_to_world  # noqa: E402

ROOT = Path(__file__).resolve().parents[5]
REPEATS = 4


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--partial-objects", action=argparse.BooleanOptionalAction, default=None,
                        help="both sides with partial_objects on / off (default: as it ships)")
    parser.add_argument("--repeats", type=int, default=REPEATS)
    args = parser.parse_args()
    part = {} if args.partial_objects is None else {"partial_objects": args.partial_objects}
    scene = hi.load_scene(ROOT / "scenes/sponza_mirror.xml", resx=128, resy=72,
                          sponza_dir=str(ROOT.parent / "shared/scenes/sponza-dabrovic"))
    truth = np.array(mi.render(scene, integrator=mi.load_dict({"type": "path"}), spp=128, seed=99))

    def flip(image) -> float:
        return image_error(np.array(image)[..., :3], truth)[0].flip

    camera = sensor_to_world(scene.sensors()[0])
    for _ in range(args.repeats):
        warm = hi.render_sequence(scene, [camera] * 6, spp=1, seed=2)[3:]
        budget = 0.75 * float(np.median([f.stats.times_ms["trace"] for f in warm]))
        runs = {}
        for tier in (False, True):
            settings = HybridSettings(budget_ms=budget, shadow_tier=tier, selection="greedy", **part)
            state = FrameState()
            for seed in range(8):
                renderer(scene).render(settings, seed=seed, spp=1, state=state, layers=False)
            frames = ((seed, renderer(scene).render(settings, seed=seed, spp=1, state=state, layers=False))
                      for seed in range(9, 21))
            traced = itertools.islice(((s, f) for s, f in frames if f.stats.selected), 4)
            runs[tier] = [(s, round(flip(f.image), 4), len(f.stats.selected), len(f.stats.shadow_only), f.stats.partial_quarters)
                          for s, f in traced]
        means = {tier: float(np.mean([r[1] for r in rows])) for tier, rows in runs.items()}
        print(f"budget {budget:.1f} ms; without tiers {runs[False]}; with tiers {runs[True]}; "
              f"mean with - without {means[True] - means[False]:+.4f}", flush=True)


if __name__ == "__main__":
    main()
