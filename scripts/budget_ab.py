"""The budget path of ``budget_benchmark.py``, reduced to what an A/B of two versions needs.

On the 226-object camera path: the RT baseline, every candidate traced, then greedy at 50 % of the
all-candidates trace time; prints each run's median frame and trace time, the fraction of budgeted
frames within budget + 10 %, the median host time by phase, and RT baseline / 50 % frame. Run it
from each version's checkout in turn, several times, alternating (hosts of the lent GPU machines
drift by ~1 ms per frame between processes):

    for r in 1 2 3; do for v in old new; do (cd $v && python3 scripts/budget_ab.py --variant cuda_ad_rgb --label $v$r); done; done
"""
from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--label", default="")
    parser.add_argument("--frames", type=int, default=50)
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    size = (1280, 720) if args.variant.startswith("cuda") else (320, 180)
    path = Path("scenes/many_objects.xml")
    scene = hi.load_scene(path, resx=size[0], resy=size[1])
    cameras = hi.camera_path(json.loads(path.with_name("many_objects_path.json").read_text())["keyframes"], args.frames)

    def sequence(frames=cameras, **props):
        return hi.render_sequence(scene, frames, spp=1, layers=False, **props)

    sequence(cameras[:2])  # warm-up: kernels, geometry upload, frozen recordings
    sequence(cameras[:2], primary="raytrace")
    runs = {"RT": sequence(primary="raytrace"), "all": sequence()}
    budget = 0.5 * statistics.median(f.stats.times_ms["trace"] for f in runs["all"])
    runs["50%"] = sequence(budget_ms=budget, selection="greedy")[3:]  # after the cost model's probes
    medians = {}
    for name, frames in runs.items():
        stats = [f.stats for f in frames]
        medians[name] = statistics.median(s.times_ms["total"] for s in stats)
        within = np.mean([s.times_ms["trace"] <= 1.1 * budget for s in stats]) if name == "50%" else float("nan")
        host = {k: round(statistics.median(s.host_ms[k] for s in stats), 2) for k in stats[0].host_ms}
        print(f"{args.label} {name:4s} frame {medians[name]:.3f} trace "
              f"{statistics.median(s.times_ms['trace'] for s in stats):.3f} within {within:.2f} host {host}")
    print(f"{args.label} RT/50% = {medians['RT'] / medians['50%']:.3f}  budget {budget:.2f} ms")


if __name__ == "__main__":
    main()
