"""Probe: the next frame's raster pass drawn at the end of a frame, on and off (issue 10, stop 37).

``raster_ahead`` (``pipeline.HybridRenderer._draw_ahead``): where the camera stands still, a frame
issues the next frame's raster pass after its targets are handed back to OpenGL (interop's unmap
on Dr.Jit's stream, which orders OpenGL's later work on the target after the frame's CUDA work):
the host issues it while the GPU still develops and denoises, OpenGL runs it once CUDA is done,
and the next frame starts from its interop copy. Stop 31 drew ahead while the GPU traced, into a
target CUDA did not hold: OpenGL's work then took turns with the trace, and the frames were slower.

Three sides, each in blocks of consecutive frames (or, with ``--path``, each block a camera path) (a buffer drawn ahead serves the side's own next
frame; in the bench's alternating frames an RT frame comes between two hybrid frames), the blocks
rotating from round to round, every frame at the pixel centres (one sub-pixel offset, as
``gain_anatomy.py``), still camera:

- ``rt``: the RT baseline;
- ``off``: the hybrid with ``raster_ahead="off"``;
- ``ahead``: the hybrid with ``raster_ahead="on"``.

Prints per scene each side's median frame time (``times_ms["total"]``, the bench's), its Gain
against the RT blocks of the same rounds (median over the rounds of RT block median / side block
median), the median host time of the frame's raster phase, the median GL time of its pass (its
timer query: for ``ahead`` the draw issued in the frame before), and the passes drawn ahead that
the frames used.

    python3 scripts/ahead_probe.py --variant cuda_ad_rgb --repeats 21 SCENE... -D resx=1280 -D resy=720
"""
from __future__ import annotations

import statistics

from raster_cull_probe import each_scene_alone, parser  # scripts/ is on sys.path when a script runs

SIDES = ("rt", "off", "ahead")
ROUNDS = 4
WARMUP = 3
HEADER = 2


def main() -> None:
    import mitsuba as mi

    cli = parser(__doc__)
    cli.add_argument("--path", action="store_true",
                     help="a moving camera: each block is a camera path (``hi.render_sequence``, which gives "
                          "each frame the next pose), the eye sliding sideways by 2 %% of the scene's size")
    cli.add_argument("--set", action="append", default=[], metavar="NAME=VALUE",
                     help="a hybrid property for both hybrid sides (e.g. budget_ms=2.5; the RT side keeps all candidates)")
    args = cli.parse_args()
    options = (["--path"] if args.path else []) + [f"--set={p}" for p in args.set]
    if each_scene_alone(__file__, args, options, HEADER):
        return
    mi.set_variant(args.variant)
    import drjit as dr

    import hybrid_integrator as hi
    from hybrid_integrator import pipeline
    from hybrid_integrator.api import _integrator
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.raster.camera import sensor_to_world, transform_matrix

    pipeline.subpixel_offsets = lambda spp, seed: [(0.5, 0.5)] * spp
    scene, name = load_bench_scene(args.scenes[0], dict(d.split("=", 1) for d in args.defines))
    extra = {name: float(value) if name == "budget_ms" else value for name, value in (p.split("=", 1) for p in args.set)}
    settings = {"rt": {"primary": "raytrace"}, "off": {**extra, "raster_ahead": "off"}, "ahead": {**extra, "raster_ahead": "on"}}
    integrators = {side: _integrator(settings[side]) for side in SIDES}
    blocks = {side: [] for side in SIDES}
    columns = {side: {"raster": [], "gl": [], "used": 0} for side in SIDES}
    frames = WARMUP + args.repeats
    start = transform_matrix(sensor_to_world(scene.sensors()[0]))
    extent = 0.02 * dr.norm(scene.bbox().extents())
    cameras = [mi.ScalarTransform4f().translate((start[:3, 0] * extent * (k / frames - 0.5)).tolist())
               @ mi.ScalarTransform4f(start) for k in range(frames)]

    def block(side: str, seed: int) -> list:
        """The block's frames' statistics: still frames, or the camera path (``--path``)."""
        if args.path:
            return [r.stats for r in hi.render_sequence(scene, cameras, seed=seed, spp=1, layers=False, **settings[side])]
        return [integrators[side].render_result(scene, seed=seed + k, spp=1, layers=False).stats for k in range(frames)]

    order, seed = list(SIDES), 0
    for _ in range(ROUNDS):
        for side in order:
            totals = []
            for k, stats in enumerate(block(side, seed)):
                if k >= WARMUP:
                    totals.append(stats.times_ms["total"])
                    columns[side]["raster"].append(stats.host_ms["raster"])
                    columns[side]["gl"].append(stats.times_ms["gl"])
                    columns[side]["used"] += stats.raster_ahead
            blocks[side].append(statistics.median(totals))
            seed += frames
        order = order[1:] + order[:1]
    gains = {side: statistics.median(r / s for r, s in zip(blocks["rt"], blocks[side])) for side in SIDES[1:]}
    medians = {key: " / ".join(f"{statistics.median(columns[s][key]):.3f}" for s in SIDES[1:]) for key in ("raster", "gl")}
    print(f"| scene | {' | '.join(f'{s} ms' for s in SIDES)} | {' | '.join(f'Gain, {s}' for s in SIDES[1:])} "
          f"| raster host ms: {' / '.join(SIDES[1:])} | GL ms: {' / '.join(SIDES[1:])} | frames drawn ahead |")
    print("|---" * (1 + len(SIDES) + len(SIDES) - 1 + 3) + "|")
    print(f"| {name} | {' | '.join(f'{statistics.median(blocks[s]):.2f}' for s in SIDES)} | "
          f"{' | '.join(f'{gains[s]:.3f}' for s in SIDES[1:])} | {medians['raster']} | {medians['gl']} | "
          f"{columns['ahead']['used']} of {ROUNDS * args.repeats} |", flush=True)
    print(f"<!-- {name} blocks: " + "; ".join(f"{s} " + ", ".join(f"{b:.2f}" for b in blocks[s]) for s in SIDES)
          + " -->", flush=True)


if __name__ == "__main__":
    main()
