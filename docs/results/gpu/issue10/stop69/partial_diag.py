"""Stop 69 diagnosis: why a 25 % budget's frames with ``partial_objects`` trace fewer pixels on
Sponza than without it. Per frame of a still camera: objects traced whole, by their shadow tier
and in part, predicted against measured trace time and rays (a part's rays predicted too low
would raise the cost model's margin, and every object would look dearer).

    python3 docs/results/gpu/issue10/stop69/partial_diag.py --variant cuda_ad_rgb $D scenes/sponza_mirror.xml
"""
import argparse
import statistics

import mitsuba as mi


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("-D", action="append", default=[])
    parser.add_argument("--frames", type=int, default=16)
    parser.add_argument("--fraction", type=float, default=0.25)
    args = parser.parse_args()
    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.raster.camera import sensor_to_world

    scene, name = load_bench_scene(args.scene, dict(d.split("=", 1) for d in args.D))
    camera = sensor_to_world(scene.sensors()[0])
    every = hi.render_sequence(scene, [camera] * 13, layers=False)[3:]
    budget = args.fraction * statistics.median(r.stats.times_ms["trace"] for r in every)
    print(f"== {name}: budget {budget:.3f} ms")
    print("mode | frame | whole | tiers | part | predicted ms | trace ms | predicted rays | rays | pixels")
    for partial in (False, True):
        for k, r in enumerate(hi.render_sequence(scene, [camera] * args.frames, layers=False, stage_times=False,
                                                 budget_ms=budget, partial_objects=partial)):
            s = r.stats
            rays = sum(v for kind, v in s.rays.items() if kind != "camera")
            print(f"{'partial' if partial else 'whole'} | {k} | {len(s.selected) - len(s.shadow_only)} | "
                  f"{len(s.shadow_only)} | {s.partial_object or '-'} {s.partial_quarters} | {s.predicted_trace_ms:.3f} | "
                  f"{s.times_ms['trace']:.3f} | {s.predicted_rays} | {rays} | {s.pixels_traced}", flush=True)


if __name__ == "__main__":
    main()
