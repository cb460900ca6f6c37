"""What the device pass's replay spends its host time on (issue 10, stop 60).

``FrameStats.host_ms['replay']`` is 0.45-0.81 ms of a budgeted frame on the lent H200s, most of
it before the GPU reaches the trace (stop 59's timeline), while a frozen replay's launch costs its
host ~4 us (``launch_cost.py``). Here, per scene, a budgeted hybrid (``--budget`` of the
all-candidates trace time, stage times off) renders ``--warm`` frames from the scene's sensor;
the device pass's last call (its ``frozen.FrozenFunction`` and arguments: the sensor and the
pass's ``PassData``) is kept, then called again ``--calls`` times, and so are frozen functions
that take the same inputs and do almost nothing (one 1-lane kernel), to split the replay's host
time: the read set of scene variables, the pass's data, the sensor, all of them; each call's host
time until it returns (median), with a synchronization after each (not timed).

    python3 docs/results/gpu/issue10/stop60/replay_parts.py scenes/many_objects.xml --variant cuda_ad_rgb
"""
from __future__ import annotations

import statistics
import time


def main() -> None:
    from hybrid_integrator.bench import turn_arguments, turn_budgets

    parser = turn_arguments(__doc__.splitlines()[0], budgets=(0.5,))
    parser.add_argument("--warm", type=int, default=16)
    parser.add_argument("--calls", type=int, default=60)
    args = parser.parse_args()
    args.block = 1

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import frozen as frozen_module
    from hybrid_integrator.api import _integrator

    hi.register()
    kept = {}
    call = frozen_module.FrozenFunction.__call__

    def keep(self, *a):
        kept["fn"], kept["args"] = self, a
        return call(self, *a)

    frozen_module.FrozenFunction.__call__ = keep

    def host_ms(fn, *a) -> float:
        times = []
        for k in range(args.calls + 5):
            dr.sync_thread()
            t0 = time.perf_counter()
            out = fn(*a)
            t1 = time.perf_counter()
            dr.sync_thread()
            del out
            if k >= 5:
                times.append((t1 - t0) * 1e3)
        return statistics.median(times)

    for ready, fraction, budget in turn_budgets(args, 1):
        integrator = _integrator({"budget_ms": budget, "stage_times": False})
        for k in range(args.warm):
            integrator.render_result(ready.scene, seed=k, spp=1, layers=False)
        fn, (sensor, data) = kept["fn"], kept["args"]
        read = fn.read if fn.read is not None else fn.owner.variables.handles
        # one 1-lane kernel (the read set's handles are not read: their variables' own types vary)
        one = lambda x: dr.gather(mi.UInt32, x, 0) + 1  # noqa: E731
        parts = {
            "device pass (FrozenFunction)": (fn, sensor, data),
            "device pass, dr.freeze alone": (fn.by_snapshot, read, sensor, data),
            "all its inputs, nothing done": (dr.freeze(lambda r, s, d: one(d.seed)), read, sensor, data),
            "pass data alone": (dr.freeze(lambda d: one(d.seed)), data),
            "sensor alone": (dr.freeze(lambda s: dr.zeros(mi.UInt32, 1) + dr.width(s.world_transform().matrix)), sensor),
            f"read set alone ({len(read)} variables)": (dr.freeze(lambda r, x: one(x)), read, data.seed),
            "one variable": (dr.freeze(one), data.seed),
        }
        print(f"{ready.name}, {fraction:.0%} budget ({budget:.3f} ms), {fn.inputs}: host ms per call "
              f"(median of {args.calls})", flush=True)
        for name, (f, *a) in parts.items():
            print(f"    {name:36s} {host_ms(f, *a):.4f}", flush=True)


if __name__ == "__main__":
    main()
