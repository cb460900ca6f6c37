"""The denoiser's CUDA graph in whole frames: before and after, frame by frame in turn (issue 10, stop 54).

With the diff below ``denoise.Denoiser`` issues Open Image Denoise's filter as one CUDA graph
(``interop.StreamGraph``; ``denoise_graph.py`` beside this file times the call alone). Per scene
and kind of frame (the hybrid with every candidate, the RT baseline, and budgets of ``--budgets`` of the
hybrid's trace time, 50 % by default), two integrators of the same settings render in turn
(``bench.frames_in_turn``): ``filter``, whose denoiser never captures its graph (the way before,
restored in this process by refusing the capture), and ``graph``, the diff's code. Prints each
side's median frame time and the paired ratio filter / graph (> 1: the graph's frames are shorter).
A scene with a camera path (``NAME_path.json``: the 226 objects) renders along it.

    python3 docs/results/gpu/issue10/stop54/graph_ab.py --variant cuda_ad_rgb $D scenes/showcase.xml ...

Tried and reverted: the graph is not in the package. Apply the diff first
(``git apply docs/results/gpu/issue10/stop54/diffs/denoise_graph.diff``), as the runs did.
"""
from __future__ import annotations

import argparse

WARM = 5  # rounds not measured: the budget's three probe frames among them


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, turn_arguments, turn_poses, turn_scene

    parser = turn_arguments(__doc__.splitlines()[0])
    parser.add_argument("--unbudgeted", action=argparse.BooleanOptionalAction, default=True,
                        help="the hybrid and the RT baseline without a budget too")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import denoise

    hi.register()
    capture, graphs = denoise.Denoiser._capture, {"on": True}
    denoise.Denoiser._capture = lambda self, *a: capture(self, *a) if graphs["on"] else None

    def before(name: str) -> None:  # a side's denoiser captures its graph, or never (the way before)
        graphs["on"] = name == "graph"

    params = dict(args.defines)
    for path in args.scenes:
        ready = turn_scene(str(path), params, turn_poses(args.frames, WARM))
        scene, cameras, all_ms = ready.scene, ready.cameras, ready.all_candidates_trace_ms
        kinds = {"hybrid": {}, "RT baseline": {"primary": "raytrace"}} if args.unbudgeted else {}
        kinds |= {f"{b:.0%} budget": {"budget_ms": b * all_ms} for b in args.budgets}
        for kind, props in kinds.items():
            times = frames_in_turn(scene, {"filter": props, "graph": props}, args.frames, 1, 0, warmup=WARM,
                                   before=before, cameras=cameras)
            r = paired_ratio(times, "filter", "graph")
            print(f"{path.stem:16s} {kind:12s} filter {r['filter_ms']:.3f} ms, graph {r['graph_ms']:.3f} ms, "
                  f"filter / graph {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} pairs)", flush=True)


if __name__ == "__main__":
    main()
