"""What one launch costs the host in a frozen function's replay (issue 10, stop 60).

A budgeted frame on the lent GPU machines is bound by its host, and the largest host phase is the
device pass's replay (``FrameStats.host_ms['replay']``, 0.45-0.81 ms for its 23 launches). Here a
frozen function chains ``k`` kernels over 1280x720 lanes (each one ``dr.eval`` of a small
arithmetic step on the last), for k in ``--launches``, with Dr.Jit's kernel history off; per k,
the median over ``--calls`` warm calls of the host time until the call returns, and of the wall
time until a synchronization after it. The slope of the host time over k is the replay's cost per
launch.

    python3 docs/results/gpu/issue10/stop60/launch_cost.py --variant cuda_ad_rgb
"""
from __future__ import annotations

import argparse
import statistics
import time

import numpy as np


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--launches", type=int, nargs="*", default=[1, 2, 4, 8, 16, 32])
    parser.add_argument("--calls", type=int, default=60)
    parser.add_argument("--lanes", type=int, default=1280 * 720)
    args = parser.parse_args()
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    rows = []
    for k in args.launches:
        def chain(x, k=k):
            for _ in range(k):
                x = x * 1.0001 + 0.5
                dr.eval(x)
            return x

        frozen = dr.freeze(chain)
        x = dr.arange(mi.Float, args.lanes)
        dr.eval(x)
        host, wall = [], []
        for call in range(args.calls + 5):
            dr.sync_thread()
            t0 = time.perf_counter()
            y = frozen(x)
            t1 = time.perf_counter()
            dr.sync_thread()
            t2 = time.perf_counter()
            if call >= 5:
                host.append((t1 - t0) * 1e3)
                wall.append((t2 - t0) * 1e3)
            del y
        rows.append((k, statistics.median(host), statistics.median(wall)))
        print(f"launches {k:3d}: host {rows[-1][1]:.4f} ms, wall {rows[-1][2]:.4f} ms (median of {args.calls})", flush=True)
    ks, hosts = np.array([r[0] for r in rows], float), np.array([r[1] for r in rows])
    slope, intercept = np.polyfit(ks, hosts, 1)
    print(f"host time = {intercept:.4f} ms + {slope * 1e3:.2f} us per launch (least squares over k)")


if __name__ == "__main__":
    main()
