"""The render thread pinned to the CPU that is fast now, against left to the scheduler, in turn (issue 10, stop 58).

The GPU machines' CPUs run at two speeds about 1.7x apart, and which ones are slow changes from one
round of ``core_speed.sh`` to the next, 3 s later; a budgeted frame, bound by its host's work, follows the CPU its thread
runs on. First, how long a CPU keeps its speed: ``--persist`` seconds of back-to-back
``bench.host_loop_ms`` loops on each of ``--cpus`` CPUs at once (one pinned process each), with the
lengths of their runs of fast (within ``bench.FAST_HOST`` × the CPU's fastest loop) and slow loops.
Then the RT baseline and the budgeted hybrid render in turn by blocks of ``--block`` frames
(``bench.frames_in_turn``, the first of each not measured), along the scene's camera path: ``free``
sides leave the rendering thread's affinity to the scheduler (every CPU); a ``pinned`` side, before
the first frame of each of its blocks, times the loop on every CPU and pins the thread
(``os.sched_setaffinity``, the calling thread alone) to the fastest (outside the frames' time).
Prints each side's median frame, its host loop before its frames, and RT / budget both ways.

    python3 docs/results/gpu/issue10/stop58/pin_ab.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 60
"""
from __future__ import annotations

import os
import statistics
import subprocess
import sys
import time

WARM = 3  # rounds not measured: the budget's three probe frames among them


def persistence(cpus: list[int], seconds: float) -> None:
    """Runs of fast and slow loops, per CPU, all CPUs at once (one process each)."""
    code = ("import os, sys, time; from hybrid_integrator.bench import host_loop_ms; "
            "os.sched_setaffinity(0, {int(sys.argv[1])}); end = time.perf_counter() + float(sys.argv[2]); out = []\n"
            "while time.perf_counter() < end: out.append(host_loop_ms())\n"
            "print(' '.join(f'{x:.3f}' for x in out))")
    procs = {c: subprocess.Popen([sys.executable, "-c", code, str(c), str(seconds)], stdout=subprocess.PIPE, text=True)
             for c in cpus}
    from hybrid_integrator.bench import fast_hosts

    for c, proc in procs.items():
        loops = [float(x) for x in proc.communicate()[0].split()]
        each = seconds / max(len(loops), 1)
        fast = fast_hosts([loops])[0][0]
        runs = {True: [], False: []}
        length = 1
        for a, b in zip(fast, fast[1:]):
            if a == b:
                length += 1
            else:
                runs[a].append(length * each * 1e3)
                length = 1
        runs[fast[-1]].append(length * each * 1e3)
        median = lambda v: f"{statistics.median(v):.0f}" if v else "–"
        print(f"CPU {c}: {len(loops)} loops, fastest {min(loops):.3f} ms, fast {sum(fast) / len(fast):.0%}; runs: "
              f"fast {len(runs[True])} (median {median(runs[True])} ms, longest "
              f"{max(runs[True], default=0):.0f}), slow {len(runs[False])} (median {median(runs[False])} ms, longest "
              f"{max(runs[False], default=0):.0f})", flush=True)


def fastest_cpu(cpus: set[int]) -> int:
    """The CPU whose loop (``bench.host_loop_ms``) is fastest now; leaves the thread pinned to it."""
    from hybrid_integrator.bench import host_loop_ms

    best = None
    for c in sorted(cpus):
        os.sched_setaffinity(0, {c})
        ms = host_loop_ms()
        if best is None or ms < best[0]:
            best = (ms, c)
    os.sched_setaffinity(0, {best[1]})
    return best[1]


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, turn_arguments, turn_poses, turn_scene

    parser = turn_arguments(__doc__.splitlines()[0], budgets=(0.5,), block=5)
    parser.add_argument("--persist", type=float, default=10.0, help="seconds of loops per CPU (0: none)")
    parser.add_argument("--cpus", type=int, nargs="*", default=[0, 5, 10, 15])
    args = parser.parse_args()
    if args.persist > 0:
        persistence(args.cpus, args.persist)

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    every = os.sched_getaffinity(0)
    params = dict(args.defines)
    for path in args.scenes:
        ready = turn_scene(str(path), params, turn_poses(args.frames, WARM, args.block))
        for fraction in args.budgets:
            budget = {"budget_ms": fraction * ready.all_candidates_trace_ms}
            sides = {"rt free": {"primary": "raytrace"}, "budget free": budget, "rt pinned": {"primary": "raytrace"},
                     "budget pinned": budget}
            seen = dict.fromkeys(sides, 0)
            chosen: list[int] = []

            def place(name: str) -> None:
                if name.endswith("free"):
                    os.sched_setaffinity(0, every)
                elif seen[name] % args.block == 0:
                    chosen.append(fastest_cpu(every))
                seen[name] += 1

            start = time.perf_counter()
            times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                                   cameras=ready.cameras, before=place, host_speed=True)
            os.sched_setaffinity(0, every)
            print(f"{ready.name} {fraction:.0%} budget ({budget['budget_ms']:.3f} ms), {time.perf_counter() - start:.1f} s; "
                  f"pinned to {len(set(chosen))} different CPUs over {len(chosen)} choices", flush=True)
            for name in sides:
                print(f"  {name:14s} frame {statistics.median(t['total'] for t in times[name]):.3f} ms, host loop "
                      f"{statistics.median(t['host_loop'] for t in times[name]):.3f} ms", flush=True)
            for a, b in (("rt free", "budget free"), ("rt pinned", "budget pinned"), ("budget free", "budget pinned"),
                         ("rt free", "rt pinned")):
                r = paired_ratio(times, a, b, block=args.block)
                print(f"  {a} / {b}: {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} rounds)", flush=True)


if __name__ == "__main__":
    main()
