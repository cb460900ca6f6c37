"""Stop 71 probe: which left-out pixels of an object traced in part should be filled.

For each object named, a still camera's frames (``hi.render_sequence``, 1 spp, denoised as by
default) with a plan forced on every frame: nothing traced, 1, 2 or 3 quarters of the object
(``selection.QUAD_KEPT``), or the object whole. ``--fill`` sets which left-out pixels are filled
from their traced neighbours (``selection.FILL_LOBES``): ``delta`` (the default: a mirror's, a
glass's), ``all`` (stop 69's rule) or ``none`` (every left-out pixel keeps the raster layer). A
frozen pass is recorded once per process, so each ``--fill`` runs in its own process. Prints the
FLIP of the last frame against ``path`` at ``--gt-spp`` (``metrics.py``).

    python3 docs/results/gpu/issue10/stop71/fill_probe.py scenes/armadillo_glass.xml armadillo floor --fill all \\
        -D resx=320 -D resy=180 -D models_dir=../shared/scenes/models
"""
import argparse

import mitsuba as mi
import numpy as np

LOBES = {"delta": "Delta", "all": "All", "none": "Empty"}


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("scene")
    parser.add_argument("objects", nargs="+", help="object names, as FrameStats.selected names them")
    parser.add_argument("--fill", choices=list(LOBES), default="delta")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("-D", action="append", default=[])
    parser.add_argument("--frames", type=int, default=4)
    parser.add_argument("--gt-spp", type=int, default=256)
    args = parser.parse_args()
    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import budget, pipeline, selection
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.compare import ground_truth
    from hybrid_integrator.metrics import errors_in_parallel
    from hybrid_integrator.raster.camera import sensor_to_world

    selection.FILL_LOBES = getattr(mi.BSDFFlags, LOBES[args.fill])
    params = dict(d.split("=", 1) for d in args.D)
    scene, name = load_bench_scene(args.scene, params)
    used = {k: v for k, v in params.items() if f"${k}" in open(args.scene).read()}
    reference, _, _ = ground_truth(args.scene, scene, used, args.gt_spp, -1)
    camera = sensor_to_world(scene.sensors()[0])
    planned = pipeline.HybridRenderer._plan
    force = {}

    def forced(self, settings, frame, state, cov, selected=None):
        """The renderer's plan, its selection replaced by ``force``: the object whole, in part or not."""
        c = planned(self, settings, frame, state, cov, selected).candidates
        rows = np.nonzero((c.index == self.objects.names.index(force["object"])) & ~c.tier)[0]
        quarters = force["quarters"] if len(rows) else 0
        return budget._plan(c, rows[:1] if quarters == 4 else [], float("inf"),
                            partial=(int(rows[0]), quarters) if 0 < quarters < 4 else None)

    pipeline.HybridRenderer._plan = forced
    images, rows = [], []
    for obj in args.objects:
        for quarters in range(5):
            force.update(object=obj, quarters=quarters)
            r = hi.render_sequence(scene, [camera] * args.frames, layers=False, budget_ms=1e3, partial_objects=True)[-1]
            images.append(mi.TensorXf(r.image).numpy()[..., :3])
            rows.append((obj, quarters, r.stats.pixels_traced))
    print(f"== {name}: fill {args.fill} ({args.variant}); FLIP against path at {args.gt_spp} spp")
    print("object | quarters traced | pixels traced | FLIP")
    for (obj, quarters, pixels), flip in zip(rows, errors_in_parallel(images, [reference] * len(images), flip_only=True)):
        print(f"{obj} | {quarters} | {pixels} | {flip:.4f}", flush=True)


if __name__ == "__main__":  # the error workers are spawned: they import this file
    main()
