"""Budgeted frames with their stage times parsed in the next frame: before and after, in turn (issue 10, stop 55).

A budgeted, denoised frame past the cost model's probes leaves the parsing of its kernel history
to the next frame (``HybridRenderer._reads_late``, ``_read_late``). Per scene and budget (fractions
``--budgets`` of the all-candidates hybrid's median trace time), two integrators of the same
settings render in turn (``bench.frames_in_turn``, rounds of ``--block`` frames per side, the
first of each round not measured: it reads the other side's last frame late): ``before``, whose
frames read their times at once (``_reads_late`` refused in this process), and ``after``, the
package's code. Prints each side's median frame time, the paired ratio before / after (> 1: the
late readout's frames are shorter) and each side's share of frames whose trace took at most the
budget + 10 % (item 4). A scene with a camera path (``NAME_path.json``: the 226 objects) renders
along it.

Tried and reverted: apply ``diffs/late_readout.diff`` first (``git apply``), as the runs did.

    python3 docs/results/gpu/issue10/stop55/late_ab.py SCENE... --variant cuda_ad_rgb $D --frames 80 --budgets 0.25 0.5
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[5]
sys.path.insert(0, str(ROOT / "scripts"))
WARM = 3  # rounds not measured: the budget's three probe frames among them


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+", type=Path)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=40, help="measured frames per side")
    parser.add_argument("--block", type=int, default=3, help="frames per side and round")
    parser.add_argument("--budgets", type=float, nargs="+", default=[0.25, 0.5], help="fractions of the hybrid's trace time")
    parser.add_argument("-D", dest="defines", action="append", default=[], help="scene parameter NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from budget_benchmark import path_cameras
    from hybrid_integrator.bench import frames_in_turn, paired_ratio
    from hybrid_integrator.pipeline import HybridRenderer

    hi.register()
    reads_late, side = HybridRenderer._reads_late, {"late": True}
    HybridRenderer._reads_late = staticmethod(lambda *a: side["late"] and reads_late(*a))

    def before(name: str) -> None:  # the side's frames read their stage times late, or at once
        side["late"] = name == "after"

    params = dict(d.split("=", 1) for d in args.defines)
    rounds = WARM + -(-args.frames // max(args.block - 1, 1))
    for path in args.scenes:
        scene = hi.load_scene(path, **{k: v for k, v in params.items() if f"${k}" in path.read_text()})
        has_path = path.with_name(path.stem + "_path.json").exists()
        cameras = path_cameras(hi, path, rounds) if has_path else None
        frames = (hi.render_sequence(scene, path_cameras(hi, path, 40), spp=1, layers=False) if has_path
                  else [hi.render(scene, spp=1, seed=k, layers=False) for k in range(12)])
        all_ms = statistics.median(f.stats.times_ms["trace"] for f in frames[2:])
        for fraction in args.budgets:
            budget = fraction * all_ms
            times = frames_in_turn(scene, {"before": {"budget_ms": budget}, "after": {"budget_ms": budget}},
                                   args.frames, 1, 0, warmup=WARM, before=before, block=args.block,
                                   cameras=cameras)
            r = paired_ratio(times, "before", "after", block=args.block)
            within = {s: sum(t["trace"] <= 1.1 * budget for t in times[s]) / len(times[s]) for s in times}
            late = sum(t["trace"] != t["trace"] for t in times["after"])  # NaN: never read (must be 0)
            print(f"{path.stem:16s} {fraction:.0%} budget ({budget:.3f} ms): before {r['before_ms']:.3f} ms, "
                  f"after {r['after_ms']:.3f} ms, before / after {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] "
                  f"({r['pairs']} pairs); within budget + 10 %: before {within['before']:.0%}, after "
                  f"{within['after']:.0%}; unread {late}", flush=True)


if __name__ == "__main__":
    main()
