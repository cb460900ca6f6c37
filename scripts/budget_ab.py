"""The budget path of ``budget_benchmark.py``, reduced to what an A/B of two versions needs.

On the 226-object camera path: the RT baseline, every candidate traced, then greedy at 50 % of the
all-candidates trace time; prints each run's median frame and trace time, the fraction of budgeted
frames within budget + 10 %, the median pixels and secondary rays traced, the median host time by
phase, and RT baseline / 50 % frame. Run it
from each version's checkout in turn, several times, alternating (hosts of the lent GPU machines
drift by ~1 ms per frame between processes):

    for r in 1 2 3; do for v in old new; do (cd $v && python3 scripts/budget_ab.py --variant cuda_ad_rgb --label $v$r); done; done
"""
from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from budget_benchmark import PROBES, path_scene, run, summary  # scripts/ is on sys.path when a script runs

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
    scene, cameras = path_scene(hi, ROOT / "scenes/many_objects.xml", args.frames, resx=size[0], resy=size[1])
    run(hi, scene, cameras[:2])  # warm-up: kernels, geometry upload, frozen recordings
    run(hi, scene, cameras[:2], primary="raytrace")
    runs = {"RT": run(hi, scene, cameras, primary="raytrace"), "all": run(hi, scene, cameras)}
    budget = 0.5 * statistics.median(f["trace_ms"] for f in runs["all"])
    runs["50%"] = run(hi, scene, cameras, budget_ms=budget, selection="greedy")
    medians = {}
    for name, frames in runs.items():
        s = summary(frames, budget if name == "50%" else 0.0)  # a budgeted run after its probes
        medians[name] = s["median_frame_ms"]
        within = s["within_budget_plus_10"] if name == "50%" else float("nan")
        measured = frames[PROBES:] if name == "50%" else frames
        host = {k: round(statistics.median(f["host_ms"][k] for f in measured), 2) for k in measured[0]["host_ms"]}
        traced = {k: int(statistics.median(f[k] for f in measured)) for k in ("pixels_traced", "secondary_rays")}
        print(f"{args.label} {name:4s} frame {medians[name]:.3f} trace {s['median_trace_ms']:.3f} within {within:.2f} "
              f"{traced} host {host}")
    print(f"{args.label} RT/50% = {medians['RT'] / medians['50%']:.3f}  budget {budget:.2f} ms")


if __name__ == "__main__":
    main()
