"""Measure the raster stage: agreement with Mitsuba's ray tracer, and time per frame.

For each scene, at several film sizes, fov conventions, principal point offsets and sub-pixel
offsets, the visibility buffer is compared with ``scene.ray_intersect_preliminary`` along Mitsuba's
camera rays (hybrid_integrator.raster.agreement). At 1280×720 it then times, as medians over
repeated frames after a warm-up: the raster pass with read-back to the host, and, for scale, Mitsuba's
camera rays + ``ray_intersect_preliminary`` (what the raster replaces), synchronized.

    python scripts/raster_report.py --variant llvm_ad_rgb -o docs/results/cpu/raster_cpu
    python scripts/raster_report.py --variant cuda_ad_rgb -o docs/results/raster_gpu   # GPU machine

Writes OUT.json and OUT.md.
"""
from __future__ import annotations

import argparse
import json
import platform
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENES = {
    "default": ROOT / "scenes/default.xml",
    "showcase": "cbox/showcase_coloured_glass.xml",
    "armadillo": "models/armadillo.xml",
    "sponza": "sponza-dabrovic/scene.xml",
}
CONFIGS = [  # label, width, height, fov_axis (None: the scene's own sensor), principal point, offset
    ("1280x720", 1280, 720, None, (0.0, 0.0), (0.5, 0.5)),
    ("1280x720 offset (0.13, 0.77)", 1280, 720, None, (0.0, 0.0), (0.13, 0.77)),
    ("512x512 fov x", 512, 512, "x", (0.0, 0.0), (0.5, 0.5)),
    ("360x640 fov y", 360, 640, "y", (0.0, 0.0), (0.9, 0.05)),
    ("1280x720 principal point (0.04, -0.03)", 1280, 720, "x", (0.04, -0.03), (0.5, 0.5)),
]


def median_ms(fn, repeats: int) -> float:
    fn()
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        fn()
        times.append((time.perf_counter() - start) * 1e3)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--shared", type=Path, default=ROOT.parent / "shared/scenes", help="folder of the shared scenes")
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs/results/cpu/raster_cpu")
    args = parser.parse_args()

    import hybrid_integrator as hi
    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    from hybrid_integrator.primary import camera_rays
    from hybrid_integrator.raster.agreement import visibility_agreement
    from hybrid_integrator.raster.camera import RasterCamera, sensor_like
    from hybrid_integrator.raster.context import machine as machine_of
    from hybrid_integrator.scene import load_scene

    rows, timings = [], []
    for name, rel in SCENES.items():
        path = rel if Path(rel).is_absolute() else args.shared / rel
        scene = load_scene(path, resx=1280, resy=720)
        triangles = sum(s.face_count() for s in scene.shapes() if s.is_mesh())
        for label, w, h, axis, ppo, offset in CONFIGS:
            sensor = scene.sensors()[0] if axis is None else sensor_like(scene.sensors()[0], w, h, axis, ppo)
            gb = hi.rasterize(scene, sensor=sensor, offset=offset)
            rows.append({"scene": name, "config": label, **visibility_agreement(scene, sensor, gb).as_dict()})
        sensor = scene.sensors()[0]
        camera = RasterCamera.from_sensor(sensor)
        raster = hi.rasterizer(scene)

        def trace():
            pi = scene.ray_intersect_preliminary(camera_rays(sensor, camera.width, camera.height, (0.5, 0.5)))
            dr.eval(pi.t, pi.prim_index, pi.shape_index, pi.prim_uv)
            dr.sync_thread()

        def gl_pass():
            raster.render(camera)
            raster.ctx.finish()

        timings.append({"scene": name, "triangles": triangles,
                        "raster_pass_ms": round(median_ms(gl_pass, args.repeats), 3),
                        "raster_with_readback_ms": round(median_ms(lambda: hi.rasterize(scene), args.repeats), 3),
                        "mitsuba_primary_rays_ms": round(median_ms(trace, args.repeats), 3)})
        print(name, timings[-1], flush=True)

    machine = {**machine_of(), "python": platform.python_version(), "mitsuba": mi.__version__}
    command = f"python scripts/raster_report.py --variant {args.variant} -o {args.output.relative_to(ROOT) if args.output.is_relative_to(ROOT) else args.output}"
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.with_suffix(".json").write_text(json.dumps({"command": command, "machine": machine, "agreement": rows, "timing_1280x720": timings}, indent=2))
    md = [f"# Raster stage: agreement and time ({args.variant})", "",
          f"Command: `{command}`  ", f"Machine: {machine}", "",
          "## Agreement with `scene.ray_intersect_preliminary` (same sub-pixel positions)", "",
          "| scene | configuration | hit/miss | shape and triangle | median rel. depth error | p99 rel. depth error |",
          "|---|---|---|---|---|---|"]
    md += [f"| {r['scene']} | {r['config']} | {r['hit_miss']:.5%} | {r['shape_and_triangle']:.5%} | "
           f"{r['median_relative_depth_error']:.2e} | {r['p99_relative_depth_error']:.2e} |" for r in rows]
    md += ["", f"## Time per frame at 1280×720 (median of {args.repeats}, after warm-up)", "",
           "| scene | triangles | raster pass (ms) | raster pass + read-back + resolve on the host (`hi.rasterize`, ms) | Mitsuba camera rays + ray_intersect_preliminary (ms) |",
           "|---|---|---|---|---|"]
    md += [f"| {t['scene']} | {t['triangles']:,} | {t['raster_pass_ms']} | {t['raster_with_readback_ms']} | {t['mitsuba_primary_rays_ms']} |" for t in timings]
    args.output.with_suffix(".md").write_text("\n".join(md) + "\n")
    print(f"wrote {args.output.with_suffix('.md')}")


if __name__ == "__main__":
    main()
