"""What stop 57's cap on Russian roulette (``rr_tail_depth``: from depth 16 a path goes on with
probability at most ``rr_tail_prob`` = 0.5, and its weight doubles) costs in variance: the
relative MSE and FLIP of all-candidates frames against ``path`` at ``--gt-spp``, over ``--seeds``
seeds, with the cap and without it (``rr_tail_depth=-1``, as ``path``), each undenoised and
denoised; ``path`` at 1 spp beside them. Stop 61's bench saw the undenoised frame's relative MSE
rise from stop 49's 0.117 to 1.50 (Armadillo) at the same FLIP. On the CPU:

    .venv/bin/python docs/results/gpu/issue10/stop61/tail_variance.py scenes/armadillo_glass.xml scenes/showcase.xml \\
        -D resx=320 -D resy=180 -D models_dir=../shared/scenes/models -D showcase_dir=../shared/scenes/cbox
"""
from __future__ import annotations

import numpy as np


def main() -> None:
    from hybrid_integrator.bench import turn_arguments

    parser = turn_arguments(__doc__.splitlines()[0])
    parser.add_argument("--gt-spp", type=int, default=1024)
    parser.add_argument("--seeds", type=int, default=24)
    args = parser.parse_args()
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.bench import load_bench_scene
    from hybrid_integrator.compare import render_path
    from hybrid_integrator.metrics import flip_map, relative_mse

    def summary(label, images, truth):
        rel = [relative_mse(image, truth) for image in images]
        flip = [flip_map(image, truth)[1] for image in images]
        print(f"    {label:28s} rel. MSE median {np.median(rel):.3f}, mean {np.mean(rel):.3f}, max {np.max(rel):.3f}; "
              f"FLIP mean {np.mean(flip):.4f}", flush=True)

    for path in args.scenes:
        scene, name = load_bench_scene(str(path), dict(args.defines))
        truth = np.array(render_path(scene, args.gt_spp, -1, seed=99))[..., :3]
        print(f"{name} ({args.seeds} seeds, against path at {args.gt_spp} spp):", flush=True)
        summary("path 1 spp", [np.array(render_path(scene, 1, -1, seed=s))[..., :3] for s in range(args.seeds)], truth)
        for tail in (-1, 16, None):  # None: the integrator's default (since stop 62: 16 denoised, -1 not)
            for denoise in (False, True):
                images = [np.array(hi.render(scene, spp=1, seed=s, denoise=denoise, layers=False,
                                             rr_tail_depth=tail).image)[..., :3] for s in range(args.seeds)]
                summary(f"rr_tail_depth {'default' if tail is None else tail:>7}, {'denoised' if denoise else 'no denoiser'}",
                        images, truth)


if __name__ == "__main__":
    main()
