"""Stop 57's probe (issue 10): Russian roulette's continuation cap against trace time and error.

Mitsuba's ``path``, and the hybrid's trace like it, continue a path past ``rr_depth`` with
probability min(max throughput · η², 0.95). Through glass the throughput stays near 1, so a path
survives each bounce with probability 0.95: its length past ``rr_depth`` is geometric with mean
20, and the longest of N such paths grows with 20 · ln N. On a GPU a launch lasts until its
slowest lanes are done, so a frame's trace ends in a tail of few lanes bouncing on through glass
while the rest of the GPU idles. A lower cap shortens that tail; the estimator stays unbiased,
its variance grows.

Since this stop the integrator caps it at 0.5 from depth 16 on (``rr_tail_depth``,
``rr_tail_prob``: ``trace.RouletteCap``); this probe compares caps (``--caps``, ``side_properties``).

Per scene: the ground truth (``path`` at ``--gt-spp``, unlimited depth, as the bench's), then one
all-candidates hybrid per cap (the default frame: denoised, 1 spp), rendered in turn frame by
frame (``bench.frames_in_turn``, ``--frames`` each, along the scene's camera path where it has
one): the median frame and trace times and, per cap, the median of the pairs' ratios against the
cap 0.95 (> 1: faster); then ``--images`` frames per cap (seeds 1000…, the sensor's own pose)
against the ground truth: mean FLIP and relative MSE.

    python3 docs/results/gpu/issue10/stop57/rr_cap.py scenes/showcase.xml --variant cuda_ad_rgb $D

Since stop 62, ``--property NAME=VALUE`` adds an integrator property to every side: with
``denoise=false``, the undenoised frame, whose default became ``path``'s roulette then.
"""
from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[5]))
from hybrid_integrator.cli import typed_property  # NAME=VALUE, or argparse's error  # noqa: E402


def side_properties(cap: str) -> dict:
    """The integrator properties of a ``--caps`` entry: ``0.95``, ``path``'s roulette
    (``rr_tail_depth=-1``); another CAP, that cap at every depth (``rr_tail_depth=0``,
    ``rr_tail_prob`` CAP); ``0.95@DEPTH:TAIL``, ``rr_tail_depth`` DEPTH and ``rr_tail_prob`` TAIL.
    (The stop's first run named the cap at every depth ``rr_max_prob``, a property of its own then.)"""
    prob, _, tail = cap.partition("@")
    depth, _, tail_prob = tail.partition(":")
    if tail:
        return {"rr_tail_depth": int(depth), "rr_tail_prob": float(tail_prob)}
    return {"rr_tail_depth": -1} if float(prob) >= 0.95 else {"rr_tail_depth": 0, "rr_tail_prob": float(prob)}


def main() -> None:
    from hybrid_integrator.bench import turn_arguments

    parser = turn_arguments(__doc__.splitlines()[0])
    parser.add_argument("--caps", nargs="+", default=["0.95", "0.95@16:0.5", "0.95@12:0.5", "0.8"],
                        help="CAP (at every depth), or 0.95@DEPTH:TAIL (side_properties); the first is the one the "
                             "others are compared with")
    parser.add_argument("--gt-spp", type=int, default=512)
    parser.add_argument("--images", type=int, default=6)
    parser.add_argument("-o", "--output", type=Path, default=None, help="JSON of every scene's rows")
    parser.add_argument("--property", dest="properties", action="append", default=[], metavar="NAME=VALUE", type=typed_property,
                        help="a property of every side's frames (true / false, a number or text), e.g. denoise=false")
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import _integrator
    from hybrid_integrator.bench import frames_in_turn, load_bench_scene, paired_ratio, path_cameras, turn_poses
    from hybrid_integrator.compare import ground_truth
    from hybrid_integrator.metrics import errors_in_parallel

    hi.register()
    params = dict(args.defines)
    report = {}
    for spec in args.scenes:
        scene, name = load_bench_scene(str(spec), params)
        reference, _, _ = ground_truth(str(spec), scene, params, args.gt_spp, -1)
        sides = {cap: {**dict(args.properties), **side_properties(cap)} for cap in args.caps}
        times = frames_in_turn(scene, sides, args.frames, 1, 0, warmup=3,
                               cameras=path_cameras(spec, turn_poses(args.frames, 3)))
        base = args.caps[0]
        images, owners = [], []
        for side, props in sides.items():
            integrator = _integrator(dict(props))
            for k in range(args.images):
                images.append(np.array(integrator.render_result(scene, seed=1000 + k, spp=1, layers=False).image)[..., :3])
                owners.append(side)
        errors = errors_in_parallel(images, [reference] * len(images))
        rows = []
        for side in sides:
            mine = [e for e, o in zip(errors, owners) if o == side]
            rows.append({"cap": side, **sides[side],
                         "frame_ms": statistics.median(t["total"] for t in times[side]),
                         "trace_ms": statistics.median(t["trace"] for t in times[side]),
                         "speedup_vs_first": paired_ratio(times, base, side)["median"] if side != base else 1.0,
                         "flip": float(np.mean([e.flip for e in mine])),
                         "rel_mse": float(np.mean([e.rel_mse for e in mine]))})
            r = rows[-1]
            print(f"{name} cap {side}: frame {r['frame_ms']:.2f} ms, trace {r['trace_ms']:.2f} ms, "
                  f"{base}/this {r['speedup_vs_first']:.3f}, FLIP {r['flip']:.4f}, rel. MSE {r['rel_mse']:.4f}", flush=True)
        report[name] = rows
        hi.forget(scene)
    if args.output:
        args.output.write_text(json.dumps(report, indent=2))


if __name__ == "__main__":
    main()
