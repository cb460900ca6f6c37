"""A still camera's budgeted frames: what their selection captured (issue 10, stop 53).

Renders a scene from its own sensor: four frames with every candidate (their median trace time is
the all-candidates time), then 40 frames at each of 25 / 50 / 75 % of it, and prints per budget, over
the frames after the cost model's three probes, the mean relevance captured, the median pixels
traced, the fraction within budget + 10 % and the mean selection changes. Run it with each
version's package first on ``PYTHONPATH`` to compare them (stop 53: main before and after the plan
ahead, on the CPU):

    PYTHONPATH=OLD_CHECKOUT python docs/results/gpu/issue10/stop53/still_selection.py scenes/showcase.xml \
        -D showcase_dir=../shared/scenes/cbox
"""
from __future__ import annotations

import argparse
import statistics
from pathlib import Path

PROBES = 3  # the cost model's probe frames (budget.py)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("-D", dest="defines", action="append", default=["resx=160", "resy=90"], metavar="NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene

    scene, _ = load_bench_scene(str(args.scene), dict(d.split("=", 1) for d in args.defines))
    everything = hi.api._integrator({})
    trace_all = statistics.median(everything.render_result(scene, seed=s, spp=1, layers=False).stats.times_ms["trace"]
                                  for s in range(4))
    for fraction in (0.25, 0.5, 0.75):
        integrator = hi.api._integrator({"budget_ms": fraction * trace_all})
        stats = [integrator.render_result(scene, seed=s, spp=1, layers=False).stats for s in range(args.frames)][PROBES:]
        print(f"{Path(hi.__file__).parents[1].name} {fraction:.0%}: relevance captured "
              f"{statistics.mean(s.relevance_captured for s in stats):.3f}, pixels traced "
              f"{int(statistics.median(s.pixels_traced for s in stats))}, within budget + 10 % "
              f"{statistics.mean(s.times_ms['trace'] <= 1.1 * s.budget_ms for s in stats):.2f}, selection changes "
              f"{statistics.mean(s.selection_changes for s in stats):.2f}")


if __name__ == "__main__":
    main()
