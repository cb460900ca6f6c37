"""What Dr.Jit's kernel history costs a frame's host, in turn in one process (issue 10, stop 59).

A budgeted frame keeps the kernel history on (``JitFlag.KernelHistory``: its cost model learns the
trace stage's device time from it). Per scene, the all-candidates frame and a frame that traces
nothing (DR) render with ``stage_times`` on and off, in turn frame by frame, the sensor's pose
(``bench.frames_in_turn``, the host's speed taken before each frame); prints per side the median
frame and the median host ms of each phase (``FrameStats.host_ms``: ``replay`` is the frozen
device pass's issue, before which the GPU waits for the host), and the paired ratio on / off.

    python3 docs/results/gpu/issue10/stop59/history_cost.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 40
"""
from __future__ import annotations

import statistics


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, turn_arguments, turn_scene

    args = turn_arguments(__doc__.splitlines()[0]).parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi

    hi.register()
    params = dict(args.defines)
    for path in args.scenes:
        ready = turn_scene(str(path), params, 2)  # its path unused: the sensor's pose
        renderer = hi.api.renderer(ready.scene)
        render, side, host = type(renderer).render, [""], {}

        def recorded(*a, **k):
            result = render(renderer, *a, **k)
            host.setdefault(side[0], []).append(result.stats.host_ms)
            return result

        renderer.render = recorded
        sides = {"all on": {"stage_times": True}, "all off": {"stage_times": False},
                 "DR on": {"stage_times": True, "candidates": ""}, "DR off": {"stage_times": False, "candidates": ""}}
        times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, before=lambda name: side.__setitem__(0, name),
                               host_speed=True)
        loops = [t["host_loop"] for v in times.values() for t in v]
        print(f"{ready.name}: host loop {min(loops):.3f} / {statistics.median(loops):.3f} ms (fastest / median)")
        for name in sides:
            phases = host[name][-args.frames:]
            print(f"  {name:8s} frame {statistics.median(t['total'] for t in times[name]):.3f} ms; host ms "
                  + ", ".join(f"{k} {statistics.median(p[k] for p in phases):.3f}" for k in phases[0]))
        for a, b in (("all on", "all off"), ("DR on", "DR off")):
            r = paired_ratio(times, a, b)
            print(f"  {a} / {b}: {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} pairs)")
        del renderer.render


if __name__ == "__main__":
    main()
