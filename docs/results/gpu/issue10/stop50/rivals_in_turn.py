"""The hybrid's default frame against ``path``'s real-time rivals, frame by frame (issue 10, stop 50).

Per scene, one process: four frames rendered in turn, round after round (the order rotating), each
timed with the backend synchronized before and after it: the hybrid's default frame with
``stage_times=False`` and with the stage times on, Mitsuba's ``path`` at 1 spp replayed from a
recording (``compare.path_renders``, as the bench times it) and the same + Open Image Denoise at the
hybrid's default quality, 'fast' (``compare.path_denoised_renders``). Prints each side's median
wall ms and the median of the rounds' ratios rival / hybrid (> 1: the hybrid is faster), with
their quartiles.

    python3 docs/results/gpu/issue10/stop50/rivals_in_turn.py --variant cuda_ad_rgb scenes/sponza_mirror.xml $D
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[5]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--rounds", type=int, default=30, help="measured rounds, after three of warm-up")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    from hybrid_integrator.api import _integrator
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.compare import path_denoised_renders, path_renders

    defines = dict(d.split("=", 1) for d in args.defines)
    print(f"{args.variant}: median wall ms per frame, {args.rounds} rounds in turn; rival / hybrid "
          "(stage_times=false): median [quartiles] of the rounds' ratios")
    for path in args.scenes:
        scene, _ = load_bench_scene(str(path), defines)
        hybrids = {on: _integrator({"stage_times": on}) for on in (False, True)}
        path_1spp = path_renders(scene, scene.sensors()[0], [mi.load_dict({"type": "path"})], 1, frozen=True)
        path_oidn = path_denoised_renders(scene, 1, -1, quality="fast")
        sides = {"hybrid": lambda seed: hybrids[False].render_result(scene, seed=seed, spp=1, layers=False).image,
                 "hybrid, stage times": lambda seed: hybrids[True].render_result(scene, seed=seed, spp=1, layers=False).image,
                 "path 1 spp, frozen": lambda seed: path_1spp(seed)[0],
                 "path + OIDN 'fast'": path_oidn}
        times = {name: [] for name in sides}
        order = list(sides)
        for k in range(3 + args.rounds):
            for name in order:
                dr.sync_thread()
                start = time.perf_counter()
                dr.eval(sides[name](k))
                dr.sync_thread()
                if k >= 3:
                    times[name].append((time.perf_counter() - start) * 1e3)
            order = order[1:] + order[:1]
        base = np.asarray(times["hybrid"])
        for name, t in times.items():
            q25, q50, q75 = np.percentile(np.asarray(t) / base, [25, 50, 75])
            print(f"{path.stem:16s} {name:20s} {statistics.median(t):7.3f} ms   / hybrid {q50:.3f} [{q25:.3f}, {q75:.3f}]",
                  flush=True)


if __name__ == "__main__":
    main()
