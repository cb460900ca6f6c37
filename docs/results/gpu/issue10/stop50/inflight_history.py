"""What the kernel history cost a frame in flight, which never reads it (issue 10, stop 50).

Since stop 50 a frame rendered in flight (``frames_in_flight=2``, no budget: ``inflight.py``)
keeps no kernel history: Dr.Jit reads it only after a synchronization, which such a frame does
not have, so until then it recorded CUDA events around every launch for nothing. This probe
renders the hybrid's and the RT baseline's default frames in flight, as the bench's "2 in
flight" column does (``bench.frames_in_turn``, turns of five frames, four measured), with the
history as this code keeps it (none) and, by making ``HybridSettings.times_stages`` true for
that side's frames (the probe's one intervention), as before; prints the median of each side's
``times_ms["total"]`` (the device time from the end of the frame before: CUDA events).

    python3 docs/results/gpu/issue10/stop50/inflight_history.py --variant cuda_ad_rgb scenes/sponza_mirror.xml $D
"""
from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[5]))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", type=Path, nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=40, help="measured frames per side")
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    from hybrid_integrator import pipeline
    from hybrid_integrator.bench import frames_in_turn, load_bench_scene

    kept = {"on": False}
    own = pipeline.HybridSettings.times_stages
    pipeline.HybridSettings.times_stages = property(lambda self: kept["on"] or own.fget(self))
    defines = dict(d.split("=", 1) for d in args.defines)
    print(f"{args.variant}: frames in flight, median times_ms['total'] (device span), {args.frames} frames per side, "
          "turns of five frames (four measured)")
    for path in args.scenes:
        scene, _ = load_bench_scene(str(path), defines)
        for primary in ("raster", "raytrace"):
            props = {"primary": primary, "frames_in_flight": 2}
            sides = {"no history": props, "history kept": dict(props)}
            times = frames_in_turn(scene, sides, args.frames, 1, 0, block=5,
                                   before=lambda name: kept.update(on=name == "history kept"))
            med = {name: statistics.median(t["total"] for t in v) for name, v in times.items()}
            print(f"{path.stem:16s} {primary:9s} no history {med['no history']:7.3f}  history kept "
                  f"{med['history kept']:7.3f}  difference {med['history kept'] - med['no history']:+.3f} ms", flush=True)


if __name__ == "__main__":
    main()
