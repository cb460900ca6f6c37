"""The budget path of ``budget_benchmark.py``, reduced to what an A/B of two versions needs.

On the 226-object camera path: the RT baseline, every candidate traced, then ``--selection``
(default greedy) at each of ``--fractions`` (default 50 %) of the all-candidates trace time; prints
each run's median frame and trace time, the fraction of budgeted frames within budget + 10 %, the
relevance captured (mean), the median pixels and secondary rays traced, how the budgeted frames'
rays compare with their plans' (median ratio, frames over 1.5×), the median host time by phase,
and RT baseline / budgeted frame. Run it
from each version's checkout in turn, several times, alternating (hosts of the lent GPU machines
drift by ~1 ms per frame between processes):

    for r in 1 2 3; do for v in old new; do (cd $v && python3 scripts/budget_ab.py --variant cuda_ad_rgb --label $v$r); done; done
"""
from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from budget_benchmark import PROBES, path_scene, rays_predicted, run, summary  # scripts/ is on sys.path when a script runs

ROOT = Path(__file__).resolve().parents[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--label", default="")
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--fractions", type=float, nargs="+", default=[0.5],
                        help="the budgets, of the all-candidates trace time")
    parser.add_argument("--selection", default="greedy", help="the selector (the integrator's default: nested)")
    parser.add_argument("--resx", type=int, help="default: 1280 on CUDA, 320 on the CPU")
    parser.add_argument("--resy", type=int, help="default: 720 on CUDA, 180 on the CPU")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    size = (1280, 720) if args.variant.startswith("cuda") else (320, 180)
    size = (args.resx or size[0], args.resy or size[1])
    scene, cameras = path_scene(hi, ROOT / "scenes/many_objects.xml", args.frames, resx=size[0], resy=size[1])
    run(hi, scene, cameras[:2])  # warm-up: kernels, geometry upload, frozen recordings
    run(hi, scene, cameras[:2], primary="raytrace")
    runs = {"RT": run(hi, scene, cameras, primary="raytrace"), "all": run(hi, scene, cameras)}
    trace_all = statistics.median(f["trace_ms"] for f in runs["all"])
    budgets = {f"{fraction:.0%}": fraction * trace_all for fraction in args.fractions}
    for budgeted, budget in budgets.items():
        runs[budgeted] = run(hi, scene, cameras, budget_ms=budget, selection=args.selection)
    medians = {}
    for name, frames in runs.items():
        budget = budgets.get(name, 0.0)
        s = summary(frames, budget)  # a budgeted run after its probes
        medians[name] = s["median_frame_ms"]
        within = s["within_budget_plus_10"] if budget else float("nan")
        measured = frames[PROBES:] if budget else frames
        host = {k: round(statistics.median(f["host_ms"][k] for f in measured), 2) for k in measured[0]["host_ms"]}
        traced = {k: int(statistics.median(f[k] for f in measured)) for k in ("pixels_traced", "secondary_rays")}
        rays = rays_predicted(measured) if budget else {}
        rays = (f" rays/predicted {rays['median_rays_over_predicted']:.2f}, over 1.5x {rays['frames_rays_over_1_5']:.2f}"
                if rays else "")
        print(f"{args.label} {name:4s} frame {medians[name]:.3f} trace {s['median_trace_ms']:.3f} within {within:.2f}"
              f" relevance {s['mean_relevance_captured']:.3f}{rays} {traced} host {host}")
    for budgeted, budget in budgets.items():
        print(f"{args.label} RT/{budgeted} = {medians['RT'] / medians[budgeted]:.3f}  budget {budget:.2f} ms ({args.selection})")


if __name__ == "__main__":
    main()
