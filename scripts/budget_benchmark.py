"""The frame-time budget on a camera path through the many-object scene (issues 4, 10).

1. Renders the path with every candidate traced (``budget_ms=0``) and takes the median trace time
   per frame (device time of the trace stage): the all-candidates cost.
2. Renders the path again with budgets of 25, 50 and 75 % of it (greedy, I = 0; and ``nested``, the
   integrator's default, which stops at the first object that does not fit and so leaves more of
   the budget unused), and at 50 % with the other selectors (``graph``, ``exact``) and with greedy
   and I > 0.
3. Reports per run, over the frames after the cost model's three probe frames: the fraction of
   frames that trace something, of frames whose trace time is within the budget + 10 %, the
   relevance captured (Σ R traced / Σ R of the visible candidates), the selection changes per
   frame and the frame time; the RT baseline's frame time beside them; and plots budget against
   measured trace time per frame, and trace time against the pixels traced.
4. Renders the RT baseline and the 50 % frame (nested) frame by frame in turn along the path
   (``bench.frames_in_turn``) and reports the median ratio of the pairs: a budgeted frame is
   host-bound, and its runs above move with the process's host by up to 1.2 ms (issue 10, stop 53).
5. The same two in turn by blocks of ``bench.TURN_BLOCK`` frames along the path, the first of
   each not measured: it pays for the switch from the other side, which cost a budgeted frame
   0.34-0.39 ms alternating frame by frame (stop 54), while a round's frames still share the
   host's speed (stop 56).
6. Both in-turn ratios also apart for the pairs rendered on a fast host and on a slow one: the GPU
   machines' CPUs run at two speeds about 1.7x apart, each CPU slow for runs of a few ms to a
   second, and the budgeted frame, host-bound, follows them (``bench.paired_ratio_by_host``;
   stop 58).
7. The RT baseline and the 50 % frame in turn once more as a renderer ships them
   (``stage_times=False``, as ``hybrid bench`` times its frames): the budget then times its trace
   every ``timing_interval``-th frame, and learns from those alone (stop 59); frames within budget
   + 10 % are counted over those timed frames.

``--partial-objects`` / ``--no-partial-objects`` runs every budgeted side with the integrator's
``partial_objects`` on / off (what the selection leaves buys a part of one more object; default:
as it ships, on since stop 75); the table counts the frames that bought one.

    python scripts/budget_benchmark.py -o docs/results/cpu/budget                         # CPU, 640×360
    python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $OUT/budget  # GPU

Each frame is one sample per pixel, as in a real-time setting. Writes OUT.json, OUT.md, OUT.png.
"""
from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


PROBES = 3  # the cost model's probe frames at the start of every budgeted run (budget.py)


def path_scene(hi, scene: Path, frames: int, **params) -> tuple:
    """``scene`` loaded with ``params`` and ``frames`` cameras along its path (``bench.path_cameras``)."""
    from hybrid_integrator.bench import path_cameras

    return hi.load_scene(scene, **params), path_cameras(scene, frames)


def run(hi, scene, cameras, **props) -> list[dict]:
    frames = hi.render_sequence(scene, cameras, spp=1, layers=False, **props)
    return [{"frame": i, "trace_ms": f.stats.times_ms["trace"], "total_ms": f.stats.times_ms["total"],
             "host_ms": f.stats.host_ms,
             "predicted_ms": f.stats.predicted_trace_ms, "pixels_traced": f.stats.pixels_traced,
             "selected": len(f.stats.selected), "visible": f.stats.candidates_visible,
             "relevance_captured": f.stats.relevance_captured, "selection_changes": f.stats.selection_changes,
             "secondary_rays": f.stats.secondary_rays, "predicted_rays": f.stats.predicted_rays,
             "partial_quarters": f.stats.partial_quarters} for i, f in enumerate(frames)]


def summary(frames: list[dict], budget: float) -> dict:
    measured = frames[PROBES:] if budget else frames
    trace = np.array([f["trace_ms"] for f in measured])
    return {"frames": len(measured), "within_budget_plus_10": float(np.mean(trace <= 1.1 * budget)) if budget else None,
            "frames_tracing": float(np.mean([f["selected"] > 0 for f in measured])),
            "median_trace_ms": float(np.median(trace)), "max_trace_ms": float(trace.max()),
            "median_frame_ms": float(np.median([f["total_ms"] for f in measured])),
            "mean_relevance_captured": float(np.mean([f["relevance_captured"] for f in measured])),
            "mean_selection_changes": float(np.mean([f["selection_changes"] for f in measured[1:]])),
            "mean_selected": float(np.mean([f["selected"] for f in measured])),
            "mean_visible": float(np.mean([f["visible"] for f in measured])),
            "frames_with_part": float(np.mean([f["partial_quarters"] > 0 for f in measured])),
            **rays_predicted(measured)}


def rays_predicted(frames: list[dict]) -> dict:
    """How the secondary rays a frame traced compare with those its plan expected (the frames
    that expected some): the median ratio and the fraction of frames over 1.5×."""
    ratio = np.array([f["secondary_rays"] / f["predicted_rays"] for f in frames if f["predicted_rays"] > 0])
    return {"median_rays_over_predicted": float(np.median(ratio)) if len(ratio) else float("nan"),
            "frames_rays_over_1_5": float(np.mean(ratio > 1.5)) if len(ratio) else float("nan")}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes/many_objects.xml")
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--resx", type=int, default=640)
    parser.add_argument("--resy", type=int, default=360)
    parser.add_argument("--importance", type=float, default=0.01, help="I > 0 for the hysteresis run")
    parser.add_argument("--partial-objects", action=argparse.BooleanOptionalAction, default=None,
                        help="every budgeted run with the integrator's partial_objects on / off (default: as it ships, on)")
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs/results/cpu/budget")
    args = parser.parse_args()

    import hybrid_integrator as hi
    import mitsuba as mi

    mi.set_variant(args.variant)
    hi.register()
    scene, cameras = path_scene(hi, args.scene, args.frames, resx=args.resx, resy=args.resy)

    part = {} if args.partial_objects is None else {"partial_objects": args.partial_objects}

    def budgeted(props: dict) -> dict:
        """A side's integrator properties, with ``--[no-]partial-objects`` where it has a budget."""
        return props | part if "budget_ms" in props else props

    def sequence(**props):
        return run(hi, scene, cameras, **budgeted(props))

    run(hi, scene, cameras[:2])  # warm-up: kernels, geometry upload, frozen recordings
    run(hi, scene, cameras[:2], primary="raytrace")
    runs = {"all candidates": sequence(), "RT baseline (all candidates)": sequence(primary="raytrace")}
    all_ms = statistics.median(f["trace_ms"] for f in runs["all candidates"])
    budgets = {}
    for selection in ("greedy", "nested"):  # nested: the integrator's default selection
        for fraction in (0.25, 0.5, 0.75):
            name = f"{selection}, I=0, {fraction:.0%}"
            budgets[name] = fraction * all_ms
            runs[name] = sequence(budget_ms=budgets[name], selection=selection)
            print(name, summary(runs[name], budgets[name]), flush=True)
    for selection, importance in (("graph", 0.0), ("exact", 0.0), ("greedy", args.importance)):
        name = f"{selection}, I={importance:g}, 50%"
        budgets[name] = 0.5 * all_ms
        runs[name] = sequence(budget_ms=budgets[name], selection=selection, importance=importance)
        print(name, summary(runs[name], budgets[name]), flush=True)
    summaries = {name: summary(frames, budgets.get(name, 0.0)) for name, frames in runs.items()}
    # the RT baseline and the 50 % frame (nested) frame by frame in turn along the path: a pair's two
    # frames share the host's speed, which moves a budgeted frame, host-bound, by up to 1.2 ms
    # between processes (docs/results/gpu/issue10/stop53)
    from hybrid_integrator.bench import (FAST_HOST, TURN_BLOCK, frames_in_turn, paired_ratio, paired_ratio_by_host,
                                         path_cameras, turn_poses)
    warm = PROBES + 2  # the budget's probe frames, then two to settle
    sides = {"rt": {"primary": "raytrace"}, "budget": budgeted({"budget_ms": 0.5 * all_ms})}

    def in_turn(label: str, turn_sides: dict, warmup: int, block: int = 1) -> tuple[dict, dict, dict]:
        """The two sides in turn along the path (the host's speed taken before each frame): their
        times, RT / 50 % of the pairs, and the same by the host's speed."""
        times = frames_in_turn(scene, turn_sides, args.frames, 1, 0, warmup=warmup, block=block, host_speed=True,
                               cameras=path_cameras(args.scene, turn_poses(args.frames, warmup, block)))
        ratio, split = paired_ratio(times, "rt", "budget", block), paired_ratio_by_host(times, "rt", "budget", block)
        print(f"RT / 50 % in turn{label}", ratio, split, flush=True)
        return times, ratio, split

    _, paired, by_host = in_turn("", sides, warm)
    # by blocks (5.); two warm-up rounds: the probes and more
    _, paired_blocks, blocks_by_host = in_turn(" by blocks", sides, 2, TURN_BLOCK)
    # (7.) as shipped: no stage times but what the budget needs
    shipped, paired_shipped, shipped_by_host = in_turn(
        ", as shipped", {name: dict(props, stage_times=False) for name, props in sides.items()}, warm)
    timed = np.array([t["trace"] for t in shipped["budget"] if np.isfinite(t["trace"])])
    shipped_within = {"timed_frames": int(len(timed)), "frames": len(shipped["budget"]),
                      "within_budget_plus_10": float(np.mean(timed <= 1.1 * sides["budget"]["budget_ms"]))}
    print("frames of the 50 % side as shipped", shipped_within, flush=True)

    command = (f"python scripts/budget_benchmark.py --variant {args.variant} --frames {args.frames} "
               f"--resx {args.resx} --resy {args.resy} --importance {args.importance}"
               + {None: "", True: " --partial-objects", False: " --no-partial-objects"}[args.partial_objects])
    from hybrid_integrator.raster.context import machine as machine_of
    machine = machine_of()
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.with_suffix(".json").write_text(json.dumps({"command": command, "machine": machine, "all_candidates_ms": all_ms,
                                                            "budgets_ms": budgets, "summaries": summaries,
                                                            "paired_rt_over_50": paired,
                                                            "paired_rt_over_50_blocks": paired_blocks,
                                                            "paired_rt_over_50_by_host": by_host,
                                                            "paired_rt_over_50_blocks_by_host": blocks_by_host,
                                                            "paired_rt_over_50_shipped": paired_shipped,
                                                            "paired_rt_over_50_shipped_by_host": shipped_by_host,
                                                            "shipped_budget_frames": shipped_within,
                                                            "runs": runs}, indent=2))
    rt_ms = summaries["RT baseline (all candidates)"]["median_frame_ms"]
    md = [f"# Frame-time budget on the many-object scene ({args.variant})", "", f"Command: `{command}`  ",
          f"Machine: {machine}", "",
          f"{len(hi.scene_objects(scene))} objects ({len(scene.shapes())} shapes after batching by material), "
          f"{args.frames} frames of the camera path, {args.resx}×{args.resy}, 1 spp. All-candidates trace time "
          f"(median, device): **{all_ms:.2f} ms**; RT baseline frame: {rt_ms:.2f} ms. Budgeted runs are "
          f"measured after their {PROBES} probe frames.", "",
          f"RT baseline / 50 % frame (nested), frame by frame in turn along the path (`bench.frames_in_turn`, "
          f"{warm} warm-up rounds, {paired['pairs']} pairs): {_ratio(paired)}.", "",
          f"The same by blocks of {TURN_BLOCK} frames along the path, the first of each not measured "
          f"({paired_blocks['pairs']} rounds): {_ratio(paired_blocks)}.", "",
          "By the host's speed before each frame (`bench.paired_ratio_by_host`: a pair is fast where every loop of its "
          f"frames took at most {FAST_HOST} × the fastest): frame by frame {_by_host(by_host)}; by blocks "
          f"{_by_host(blocks_by_host)}.", "",
          "As a renderer ships them (`stage_times=false` on both sides, as `hybrid bench` times its frames: the "
          "budget times its trace every `timing_interval`-th frame and learns from those), frame by frame in turn "
          f"({paired_shipped['pairs']} pairs): {_ratio(paired_shipped)}; "
          f"by the host's speed {_by_host(shipped_by_host)}; within budget + 10 %: "
          f"{shipped_within['within_budget_plus_10']:.0%} of the {shipped_within['timed_frames']} timed frames "
          f"(of {shipped_within['frames']}).", "",
          "| run | budget ms | frames that trace | frames within budget + 10 % | median / max trace ms | median frame ms | RT baseline / frame | relevance captured | selection changes per frame | objects traced / visible | frames with a part | rays / planned (median) | frames over 1.5× the planned rays |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for name, s in summaries.items():
        within = "–" if s["within_budget_plus_10"] is None else f"{s['within_budget_plus_10']:.0%}"
        budget = f"{budgets[name]:.2f}" if name in budgets else "–"
        md.append(f"| {name} | {budget} | {s['frames_tracing']:.0%} | {within} | {s['median_trace_ms']:.2f} / {s['max_trace_ms']:.2f} | "
                  f"{s['median_frame_ms']:.2f} | {rt_ms / s['median_frame_ms']:.2f} | {s['mean_relevance_captured']:.3f} | "
                  f"{s['mean_selection_changes']:.2f} | {s['mean_selected']:.1f} / {s['mean_visible']:.1f} | "
                  f"{s['frames_with_part']:.0%} | "
                  + ("– | – |" if budget == "–" else f"{s['median_rays_over_predicted']:.2f} | {s['frames_rays_over_1_5']:.0%} |"))
    args.output.with_suffix(".md").write_text("\n".join(md) + "\n")
    _plot(args.output.with_suffix(".png"), {k: v for k, v in runs.items() if not k.startswith("RT")}, budgets)
    print("\n".join(md))


def _ratio(r: dict, pairs: bool = False) -> str:
    """A :func:`bench.paired_ratio` result (RT over the 50 % frame) in words."""
    counted = f"{r['pairs']} pairs; " if pairs else ""
    return (f"**{r['median']:.2f}** [{r['q25']:.2f}, {r['q75']:.2f}] "
            f"({counted}RT {r['rt_ms']:.2f} ms, 50 % {r['budget_ms']:.2f} ms)")


def _by_host(split: dict) -> str:
    """A :func:`bench.paired_ratio_by_host` result in words."""
    def side(label: str) -> str:
        r = split[label]
        return f"{label} host –" if r is None else f"{label} host {_ratio(r, pairs=True)}"
    return f"{side('fast')}, {side('slow')} ({split['fast_share']:.0%} of the pairs fast, fastest loop {split['fastest_loop_ms']:.3f} ms)"


def _plot(path: Path, runs: dict, budgets: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 4.5))
    for name, frames in runs.items():
        line = left.plot([f["trace_ms"] for f in frames], label=name, lw=1.2)[0]
        if name in budgets:
            left.axhline(budgets[name], color=line.get_color(), ls="--", lw=0.8)
    left.set_xlabel("frame")
    left.set_ylabel("measured trace time (ms)")
    left.set_title("budget vs measured trace time per frame")
    left.legend(fontsize=8)
    for name, frames in runs.items():
        right.scatter([f["pixels_traced"] for f in frames], [f["trace_ms"] for f in frames], s=10, label=name)
    right.set_xlabel("pixels traced")
    right.set_ylabel("trace time (ms)")
    right.set_title("trace time against the pixels selected")
    right.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    main()
