"""Stop 50's probes on the GPU (issue 10): the default frame against ``path``'s real-time rivals,
and frames in flight with and without the kernel history they never read.

``rivals``: four frames rendered in turn, round after round (the order rotating), each timed with
the backend synchronized before and after it: the hybrid's default frame with
``stage_times=False`` and with the stage times on, Mitsuba's ``path`` at 1 spp replayed from a
recording (``compare.path_renders``, as the bench times it) and the same + Open Image Denoise at
the hybrid's default quality, 'fast' (``compare.path_denoised_renders``). Prints each side's
median wall ms and the median of the rounds' ratios side / hybrid (> 1: the hybrid is faster),
with their quartiles.

``inflight``: since stop 50 a frame rendered in flight (``frames_in_flight=2``, no budget:
``inflight.py``) keeps no kernel history: Dr.Jit reads it only after a synchronization, which
such a frame does not have, so until then it recorded CUDA events around every launch for
nothing. The hybrid's and the RT baseline's default frames in flight, as the bench's "2 in
flight" column renders them (``bench.frames_in_turn``, turns of five frames, four measured), with
no history (this code) and, by making ``HybridSettings.times_stages`` true for that side's frames
(the probe's one intervention), the history kept as before; prints the median of each side's
``times_ms["total"]`` (the device time from the end of the frame before: CUDA events).

    python3 docs/results/gpu/issue10/stop50/probes.py rivals --variant cuda_ad_rgb scenes/sponza_mirror.xml $D
    python3 docs/results/gpu/issue10/stop50/probes.py inflight --variant cuda_ad_rgb scenes/sponza_mirror.xml $D
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[5]))
from hybrid_integrator.cli import typed_property  # NAME=VALUE, or argparse's error  # noqa: E402


def rivals(scene, rounds: int, properties: dict | None = None) -> dict[str, list[float]]:
    """Wall ms per frame of each side of ``rivals`` (module docstring), ``rounds`` rounds in turn;
    ``properties``: the hybrid's integrator properties beside ``stage_times`` (since stop 52:
    ``--property effects=…``)."""
    import drjit as dr
    import mitsuba as mi

    from hybrid_integrator.api import _integrator
    from hybrid_integrator.compare import path_denoised_renders, path_renders

    hybrids = {on: _integrator({**(properties or {}), "stage_times": on}) for on in (False, True)}
    path_1spp = path_renders(scene, scene.sensors()[0], [mi.load_dict({"type": "path"})], 1, frozen=True)
    sides = {"hybrid": lambda seed: hybrids[False].render_result(scene, seed=seed, spp=1, layers=False).image,
             "hybrid, stage times": lambda seed: hybrids[True].render_result(scene, seed=seed, spp=1, layers=False).image,
             "path 1 spp, frozen": lambda seed: path_1spp(seed)[0],
             "path + OIDN 'fast'": path_denoised_renders(scene, 1, -1, quality="fast")}
    times = {name: [] for name in sides}
    order = list(sides)
    for k in range(3 + rounds):
        for name in order:
            dr.sync_thread()
            start = time.perf_counter()
            dr.eval(sides[name](k))
            dr.sync_thread()
            if k >= 3:
                times[name].append((time.perf_counter() - start) * 1e3)
        order = order[1:] + order[:1]
    return times


def inflight(scene, frames: int) -> dict[str, dict[str, list[float]]]:
    """``times_ms["total"]`` of each side of ``inflight`` (module docstring), per primary source."""
    from hybrid_integrator import pipeline
    from hybrid_integrator.bench import frames_in_turn

    kept = {"on": False}
    own = pipeline.HybridSettings.times_stages
    pipeline.HybridSettings.times_stages = property(lambda self: kept["on"] or own.fget(self))
    out = {}
    try:
        for primary in ("raster", "raytrace"):
            props = {"primary": primary, "frames_in_flight": 2}
            times = frames_in_turn(scene, {"no history": props, "history kept": dict(props)}, frames, 1, 0, block=5,
                                   before=lambda name: kept.update(on=name == "history kept"))
            out[primary] = {name: [t["total"] for t in v] for name, v in times.items()}
    finally:
        pipeline.HybridSettings.times_stages = own
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("probe", choices=("rivals", "inflight"))
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--rounds", type=int, default=30, help="rivals: measured rounds, after three of warm-up")
    parser.add_argument("--frames", type=int, default=40, help="inflight: measured frames per side")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--property", dest="properties", action="append", default=[], metavar="NAME=VALUE", type=typed_property,
                        help="rivals: a property of the hybrid's frames (true / false, a number or text), e.g. "
                             "effects=shadow,reflection,refraction or denoise=false")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    from hybrid_integrator.bench import load_bench_scene

    defines = dict(d.split("=", 1) for d in args.defines)
    properties = dict(args.properties)
    if args.probe == "rivals":
        print(f"{args.variant}: median wall ms per frame, {args.rounds} rounds in turn; rival / hybrid "
              f"(stage_times=false, {properties or 'the default properties'}): median [quartiles] of the rounds' ratios")
    else:
        print(f"{args.variant}: frames in flight, median times_ms['total'] (device span), {args.frames} frames per "
              "side, turns of five frames (four measured)")
    for path in args.scenes:
        scene, _ = load_bench_scene(str(path), defines)
        if args.probe == "rivals":
            times = rivals(scene, args.rounds, properties)
            base = np.asarray(times["hybrid"])
            for name, t in times.items():
                q25, q50, q75 = np.percentile(np.asarray(t) / base, [25, 50, 75])
                print(f"{path.stem:16s} {name:20s} {statistics.median(t):7.3f} ms   / hybrid {q50:.3f} "
                      f"[{q25:.3f}, {q75:.3f}]", flush=True)
            continue
        for primary, times in inflight(scene, args.frames).items():
            med = {name: statistics.median(v) for name, v in times.items()}
            print(f"{path.stem:16s} {primary:9s} no history {med['no history']:7.3f}  history kept "
                  f"{med['history kept']:7.3f}  difference {med['history kept'] - med['no history']:+.3f} ms", flush=True)


if __name__ == "__main__":
    main()
