"""What drawing the next frame's raster pass ahead saves a still view (issue 10).

A hybrid frame's GPU work cannot start before its visibility buffer is drawn and copied, while the
RT baseline's starts with its first kernel: the raster pass's host issue (the draw's GL calls, the
interop copy) and the draw's GPU time lengthen the hybrid's critical path over camera rays. With a
still camera the next frame's draw is known in advance, and the renderer draws it while the GPU
traces the current frame (``raster_ahead``, ``pipeline.HybridRenderer._draw_ahead``).

Per scene, in one process, blocks of ``--frames`` still frames after 3 warm-up frames (each block a
``render_sequence`` of the scene's own view), in turn: the hybrid with ``raster_ahead`` on, off,
and the RT baseline (``primary="raytrace"``), for the default frame and for a frame that traces
nothing (DR, ``candidates=""``); ``--rounds`` rounds, so that a drift of the host's speed reaches
every mode alike. Per block: the median frame time (``FrameStats.times_ms["total"]``), the median
host time of the raster pass and of the draw ahead, and how many passes were drawn ahead.

    python scripts/raster_ahead.py scenes/showcase.xml -D showcase_dir=../shared/scenes/cbox
    python3 scripts/raster_ahead.py --variant cuda_ad_rgb scenes/*.xml $D -o $OUT/raster_ahead.json
"""
from __future__ import annotations

import argparse
import json
import statistics
import sys
from pathlib import Path

MODES = {"ahead": {"raster_ahead": True}, "plain": {"raster_ahead": False}, "rt": {"primary": "raytrace"}}
FRAMES = {"default": {}, "DR": {"candidates": ""}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=20)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("-D", dest="defines", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("-o", "--output", type=Path, default=None, help="also write the rows as JSON")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.raster.camera import sensor_to_world

    defines = {"resx": 1280, "resy": 720, **dict(d.split("=", 1) for d in args.defines)}
    rows = []
    for spec in args.scenes:
        scene, name = load_bench_scene(spec, defines)
        camera = sensor_to_world(scene.sensors()[0])
        for round_ in range(args.rounds):
            for frame_kind, frame_props in FRAMES.items():
                for mode, props in MODES.items():
                    frames = hi.render_sequence(scene, [camera] * (3 + args.frames), spp=1, seed=round_ * 1000,
                                                layers=False, **frame_props, **props)[3:]
                    stats = [f.stats for f in frames]
                    row = {"scene": name, "round": round_, "frame": frame_kind, "mode": mode,
                           "total_ms": statistics.median(s.times_ms["total"] for s in stats),
                           "raster_host_ms": statistics.median(s.host_ms["raster"] for s in stats),
                           "ahead_host_ms": statistics.median(s.host_ms["ahead"] for s in stats),
                           "gl_ms": statistics.median(s.times_ms["gl"] for s in stats),
                           "passes_drawn_ahead": sum(s.raster_ahead for s in stats),
                           "passes_discarded": sum(s.raster_discarded for s in stats)}
                    rows.append(row)
                    print(f"{name:16s} round {round_} {frame_kind:7s} {mode:5s} frame {row['total_ms']:7.3f} ms  "
                          f"host: raster {row['raster_host_ms']:.3f} ahead {row['ahead_host_ms']:.3f}  "
                          f"GL {row['gl_ms']:.3f}  drawn ahead {row['passes_drawn_ahead']}/{len(stats)}, "
                          f"discarded {row['passes_discarded']}", flush=True)
    if args.output:
        args.output.parent.mkdir(parents=True, exist_ok=True)
        command = " ".join(["python3", "scripts/raster_ahead.py", *sys.argv[1:]])
        args.output.write_text(json.dumps({"command": command, "variant": args.variant, "rows": rows}, indent=1))


if __name__ == "__main__":
    main()
