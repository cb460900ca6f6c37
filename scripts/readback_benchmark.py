"""How the raster target reaches Dr.Jit: through the host against CUDA–OpenGL interop (issue 5).

For one scene at one resolution, times (medians over ``--repeats``, backend synchronized) the
visibility pass's target (a triangle number per pixel) being read to the host and uploaded
(``Rasterizer.read_ids``) and being copied on the device (``Rasterizer.device_ids``,
``raster/interop.py``), after the raster pass itself has finished. Needs a CUDA variant for interop; elsewhere the second path is the host
one again, and the report says so.

    python3 scripts/readback_benchmark.py --variant cuda_ad_rgb SCENE.xml -o docs/results/gpu/readback
"""
from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", type=Path)
    parser.add_argument("--variant", default="cuda_ad_rgb")
    parser.add_argument("--resx", type=int, default=1280)
    parser.add_argument("--resy", type=int, default=720)
    parser.add_argument("--repeats", type=int, default=20)
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.raster.camera import RasterCamera
    from hybrid_integrator.raster.context import machine

    scene = hi.load_scene(args.scene, resx=args.resx, resy=args.resy)
    raster = hi.rasterizer(scene)
    camera = RasterCamera.from_sensor(scene.sensors()[0])

    def host():
        return mi.UInt32(raster.read_ids(fbo))

    times = {"host_ms": [], "device_ms": []}
    for r in range(args.repeats + 1):  # the first uploads and compiles
        for key, read in (("host_ms", host), ("device_ms", lambda: raster.device_ids(fbo))):
            fbo = raster.render(camera)
            raster.ctx.finish()
            start = time.perf_counter()
            dr.eval(read())
            dr.sync_thread()
            if r:
                times[key].append((time.perf_counter() - start) * 1e3)
    report = {"command": f"python3 scripts/readback_benchmark.py --variant {args.variant} {args.scene} "
                         f"--resx {args.resx} --resy {args.resy} --repeats {args.repeats}",
              "machine": machine(), "readback": raster.readback, "width": args.resx, "height": args.resy,
              **{k: statistics.median(v) for k, v in times.items()}, "frames": times}
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.with_suffix(".json").write_text(json.dumps(report, indent=2))
    print(json.dumps({k: v for k, v in report.items() if k != "frames"}, indent=2))


if __name__ == "__main__":
    main()
