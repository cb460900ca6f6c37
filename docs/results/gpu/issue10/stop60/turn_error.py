"""Sides rendered in turn, along a scene's camera path or from its sensor: their time, relevance
and image error against Mitsuba's ``path`` (issue 10, stop 60).

Per scene and budget (fractions ``--budgets`` of the all-candidates trace time), the sides render in
turn by rounds of ``--block`` frames (``bench.frames_in_turn``, the first frame of each round not
measured), each carrying its own state. A side is ``--side NAME=JSON``: the integrator's
properties, where ``"budget": true`` stands for the budget's ``budget_ms``, ``"ambient":
"mean"`` renders that side's frames with the learnt ambient table as it was before this stop (an
object never traced took the mean of the learnt terms; now their median, never below zero:
``lighting.ambient_table``), and ``"albedo": "mitsuba"`` with the G-buffer's albedo as before stop
61 (Mitsuba's ``eval_diffuse_reflectance`` as it is, up to 5.9 on a rough conductor:
``raster.gbuffer.aov_values``; the side's device pass recorded apart). Prints each side's median frame, the paired ratios of the first side
to each other and of the second to the third (also by the host's speed before each frame:
``bench.paired_ratio_by_host``), each budgeted side's relevance captured and pixels traced (means
over the measured frames) and its timed frames within budget + 10 %, and the image error of the
third frame of every measured round (every side renders the same pose with the same seed)
against ``path`` at ``--gt-spp`` from that pose: mean FLIP and relative MSE per side, and the
paired FLIP difference of the third side minus the second.

The default sides compare the ambient table's two fallbacks, beside the RT baseline:

    python3 docs/results/gpu/issue10/stop60/turn_error.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 40

A moving camera planned ahead (``diffs/plan_ahead_always.diff`` applied; this stop's runs of it,
``outputs/plan*.txt``, were made by this script's first version, ``plan_ahead_ab.py`` at dbe3b34,
with these sides):

    python3 docs/results/gpu/issue10/stop60/turn_error.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 40 \\
        --side 'rt={"primary": "raytrace", "stage_times": false}' --side 'still={"budget": true, "stage_times": false}' \\
        --side 'always={"budget": true, "stage_times": false, "plan_ahead": "always"}'
"""
from __future__ import annotations

import json
import math
import statistics

import numpy as np

WARM = 3
KEPT = 2  # the frame of each round whose image is measured against the reference
SIDES = {"rt": {"primary": "raytrace", "stage_times": False},
         "mean": {"budget": True, "stage_times": False, "ambient": "mean"},
         "median": {"budget": True, "stage_times": False}}


def fallback_table(statistic):
    """``lighting.ambient_table`` with another fallback for the objects never traced: the rows it
    gives them replaced by ``statistic`` of the learnt rows (``mean_fallback``: before this stop,
    their mean)."""
    from hybrid_integrator.lighting import ambient_table

    def table(learnt: np.ndarray, n_objects: int) -> np.ndarray:
        out = ambient_table(learnt, n_objects)
        known = np.isfinite(learnt[:n_objects]).all(axis=1) if len(learnt) else np.zeros(0, dtype=bool)
        if known.any():
            unknown = np.ones(len(out), dtype=bool)
            unknown[:len(known)] = ~known
            out[unknown] = statistic(learnt[:n_objects][known])
        return out
    return table


mean_fallback = fallback_table(lambda rows: rows.mean(axis=0))


def mitsuba_albedo(scene, hits, aovs, constants):
    """``raster.gbuffer.aov_values`` with the albedo as before stop 61: Mitsuba's
    ``eval_diffuse_reflectance`` as it is, where the BSDF has no diffuse lobe too."""
    import drjit as dr
    from hybrid_integrator.raster.gbuffer import aov_values

    out = aov_values(scene, hits, aovs, constants)
    if "albedo" in out:
        value = hits.si.bsdf(hits.ray).eval_diffuse_reflectance(hits.si, hits.valid)
        out["albedo"] = [dr.select(hits.valid, value[k], 0.0) for k in range(3)]
    return out


def albedo_as(made, recorded: dict, raw: bool) -> None:
    """The renderer ``made`` renders its next frames with the albedo as before stop 61 (``raw``) or
    as now; each kind keeps its own fixed parts and recordings (``recorded``), which are made for
    a setting, not for this stand-in."""
    from hybrid_integrator import pipeline
    from hybrid_integrator.raster.gbuffer import aov_values

    pipeline.aov_values = mitsuba_albedo if raw else aov_values
    made._setups, made._frozen = recorded.setdefault(raw, ({}, {}))


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, paired_ratio_by_host, turn_arguments, turn_budgets

    parser = turn_arguments(__doc__.splitlines()[0], budgets=(0.25, 0.5, 0.75), block=5)
    parser.add_argument("--gt-spp", type=int, default=256)
    parser.add_argument("--side", action="append", default=[], type=lambda s: (s.split("=", 1)[0], json.loads(s.split("=", 1)[1])),
                        help="NAME=JSON: a side's properties (default: rt, mean, median)")
    args = parser.parse_args()
    specs = dict(args.side) or SIDES

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import pipeline
    from hybrid_integrator.api import posed, renderer
    from hybrid_integrator.compare import render_path
    from hybrid_integrator.metrics import ImageError, errors_in_parallel, relative_mse
    from hybrid_integrator.raster.camera import camera_pose

    hi.register()
    shipped = pipeline.ambient_table
    names = list(specs)
    tests, keys = [], []  # images measured, and (scene, budget, side, pose) for each
    truths: dict[tuple, np.ndarray | None] = {}
    for ready, fraction, budget in turn_budgets(args, WARM):
        sides = {name: {k: v for k, v in spec.items() if k not in ("budget", "ambient", "albedo")}
                 | ({"budget_ms": budget} if spec.get("budget") else {}) for name, spec in specs.items()}
        stats: dict[str, list] = {s: [] for s in sides}

        made, recorded = renderer(ready.scene), {}

        def before(name):
            pipeline.ambient_table = mean_fallback if specs[name].get("ambient") == "mean" else shipped
            albedo_as(made, recorded, specs[name].get("albedo") == "mitsuba")

        def after(name, at, result):
            stats[name].append(result.stats)
            if at % args.block == KEPT:
                pose = at if ready.cameras is not None else None
                tests.append(np.array(result.image)[..., :3])
                keys.append((ready.name, fraction, name, at))
                truths.setdefault((ready.name, pose), None)

        times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                               cameras=ready.cameras, before=before, after=after, host_speed=True)
        pipeline.ambient_table = shipped
        albedo_as(made, recorded, False)
        print(f"{ready.name:16s} {fraction:.0%} budget ({budget:.3f} ms): frame ms "
              + ", ".join(f"{s} {statistics.median(t['total'] for t in times[s]):.3f}" for s in sides), flush=True)
        for a, b in [(names[0], n) for n in names[1:]] + ([(names[1], names[2])] if len(names) > 2 else []):
            r, h = paired_ratio(times, a, b, block=args.block), paired_ratio_by_host(times, a, b, block=args.block)
            split = ", ".join(f"{label} {h[label]['median']:.3f} ({h[label]['pairs']})" if h[label] else f"{label} -"
                              for label in ("fast", "slow"))
            print(f"    {a} / {b}: {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} rounds); by host: {split}",
                  flush=True)
        for name in (n for n in names if "budget_ms" in sides[n]):
            s = stats[name]
            traced = [t["trace"] for t in times[name] if not math.isnan(t["trace"])]
            within = statistics.mean(x <= 1.1 * budget for x in traced) if traced else math.nan
            print(f"    {name}: relevance captured {statistics.mean(f.relevance_captured for f in s):.3f}, "
                  f"pixels traced {statistics.mean(f.pixels_traced for f in s):.0f}, "
                  f"within budget + 10 % {within:.2f} of {len(traced)} timed frames", flush=True)
        with posed(ready.scene.sensors()[0]) as place:
            for (scene_name, pose), image in truths.items():
                if scene_name == ready.name and image is None:
                    if pose is not None:
                        place(camera_pose(ready.cameras[pose]))
                    truths[scene_name, pose] = np.array(render_path(ready.scene, args.gt_spp, -1, seed=10_000 + (pose or 0)))[..., :3]
    paths = {k[0]: any(p is not None for s, p in truths if s == k[0]) for k in keys}
    references = [truths[k[0], k[3] if paths[k[0]] else None] for k in keys]
    flips = errors_in_parallel(tests, references, flip_only=True)  # ΔE2000 left out: seconds per image
    by = {k: ImageError(flip=f, rel_mse=relative_mse(t, r), delta_e2000=math.nan)
          for k, f, t, r in zip(keys, flips, tests, references)}
    print(f"image error against path at {args.gt_spp} spp, the third frame of each measured round:")
    for scene_name, fraction in dict.fromkeys((k[0], k[1]) for k in keys):
        row = {side: [e for k, e in by.items() if k[:3] == (scene_name, fraction, side)] for side in names}
        line = (f"    {scene_name:16s} {fraction:.0%}: mean FLIP / rel. MSE "
                + ", ".join(f"{side} {statistics.mean(e.flip for e in v):.4f} / {statistics.mean(e.rel_mse for e in v):.4f}"
                            for side, v in row.items() if v))
        if len(names) > 2:
            poses = sorted(k[3] for k in by if k[:3] == (scene_name, fraction, names[1]))
            diff = [by[scene_name, fraction, names[2], p].flip - by[scene_name, fraction, names[1], p].flip for p in poses
                    if (scene_name, fraction, names[2], p) in by]
            line += (f"; {names[2]} - {names[1]} FLIP per frame: mean {statistics.mean(diff):+.4f}, "
                     f"[{min(diff):+.4f}, {max(diff):+.4f}] ({len(diff)} frames)")
        print(line, flush=True)


if __name__ == "__main__":
    main()
