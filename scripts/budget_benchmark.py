"""The frame-time budget on a camera path through the many-object scene (issue 4).

1. Renders the path with every candidate traced (``budget_ms=0``) and takes the median trace time
   per frame: the all-candidates cost.
2. Sets ``budget_ms`` to half of it and renders the path again with each selector (``greedy``,
   ``graph``, ``exact``) and I = 0, and with ``greedy`` and I > 0.
3. Reports per run: the fraction of frames whose measured trace time is within the budget + 20 %,
   the relevance captured (Σ R traced / Σ R of the visible candidates), the selection changes per
   frame; and plots budget against measured trace time per frame, and trace time against the
   pixels traced.

    python scripts/budget_benchmark.py -o docs/results/cpu/budget                         # CPU, 640×360
    python3 scripts/budget_benchmark.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $OUT/budget  # GPU

Each frame is one sample per pixel, as in a real-time setting, with ``freeze=True`` (one scene in
the process) unless ``--no-freeze``. Writes OUT.json, OUT.md, OUT.png.
"""
from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def run(hi, scene, cameras, **props) -> list[dict]:
    frames = hi.render_sequence(scene, cameras, spp=1, **props)
    return [{"frame": i, "trace_ms": f.stats.times_ms["trace"], "total_ms": f.stats.times_ms["total"],
             "predicted_ms": f.stats.predicted_trace_ms, "pixels_traced": f.stats.pixels_traced,
             "selected": len(f.stats.selected), "visible": f.stats.candidates_visible,
             "relevance_captured": f.stats.relevance_captured, "selection_changes": f.stats.selection_changes,
             "secondary_rays": f.stats.secondary_rays, "predicted_rays": f.stats.predicted_rays} for i, f in enumerate(frames)]


def summary(frames: list[dict], budget: float) -> dict:
    trace = np.array([f["trace_ms"] for f in frames])
    return {"frames": len(frames), "within_budget_plus_20": float(np.mean(trace <= 1.2 * budget)) if budget else None,
            "frames_tracing": float(np.mean([f["selected"] > 0 for f in frames])),
            "median_trace_ms": float(np.median(trace)), "max_trace_ms": float(trace.max()),
            "mean_relevance_captured": float(np.mean([f["relevance_captured"] for f in frames])),
            "mean_selection_changes": float(np.mean([f["selection_changes"] for f in frames[1:]])),
            "mean_selected": float(np.mean([f["selected"] for f in frames])),
            "mean_visible": float(np.mean([f["visible"] for f in frames]))}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes/many_objects.xml")
    parser.add_argument("--frames", type=int, default=50)
    parser.add_argument("--resx", type=int, default=640)
    parser.add_argument("--resy", type=int, default=360)
    parser.add_argument("--importance", type=float, default=0.01, help="I > 0 for the hysteresis run")
    parser.add_argument("--freeze", action=argparse.BooleanOptionalAction, default=True,
                        help="replay the path loop's recorded kernels (the integrator's freeze property)")
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs/results/cpu/budget")
    args = parser.parse_args()

    import hybrid_integrator as hi
    import mitsuba as mi

    mi.set_variant(args.variant)
    hi.register()
    scene = hi.load_scene(args.scene, resx=args.resx, resy=args.resy)
    keyframes = json.loads(args.scene.with_name(args.scene.stem + "_path.json").read_text())["keyframes"]
    cameras = hi.camera_path(keyframes, args.frames)
    def sequence(**props):
        return run(hi, scene, cameras, freeze=args.freeze, **props)

    run(hi, scene, cameras[:2], freeze=args.freeze)  # warm-up: kernels, geometry upload, frozen recordings

    runs = {"all candidates": sequence()}
    all_ms = statistics.median(f["trace_ms"] for f in runs["all candidates"])
    budget = all_ms / 2
    for selection in ("greedy", "graph", "exact"):
        runs[f"{selection}, I=0"] = sequence(budget_ms=budget, selection=selection)
        print(selection, summary(runs[f"{selection}, I=0"], budget), flush=True)
    runs[f"greedy, I={args.importance}"] = sequence(budget_ms=budget, selection="greedy", importance=args.importance)
    summaries = {name: summary(frames, 0.0 if name == "all candidates" else budget) for name, frames in runs.items()}

    command = (f"python scripts/budget_benchmark.py --variant {args.variant} --frames {args.frames} "
               f"--resx {args.resx} --resy {args.resy} --importance {args.importance}"
               + ("" if args.freeze else " --no-freeze"))
    from hybrid_integrator.raster.context import machine as machine_of
    machine = machine_of()
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.with_suffix(".json").write_text(json.dumps({"command": command, "machine": machine, "all_candidates_ms": all_ms,
                                                            "budget_ms": budget, "summaries": summaries, "runs": runs}, indent=2))
    md = [f"# Frame-time budget on the many-object scene ({args.variant})", "", f"Command: `{command}`  ",
          f"Machine: {machine}", "",
          f"{len(scene.shapes())} shapes, {args.frames} frames of the camera path, {args.resx}×{args.resy}, 1 spp. "
          f"All-candidates trace time (median): {all_ms:.1f} ms; budget = half: **{budget:.1f} ms**.", "",
          "| run | frames within budget + 20 % | frames that trace | median / max trace ms | relevance captured | selection changes per frame | objects traced / visible |",
          "|---|---|---|---|---|---|---|"]
    for name, s in summaries.items():
        within = "–" if s["within_budget_plus_20"] is None else f"{s['within_budget_plus_20']:.0%}"
        md.append(f"| {name} | {within} | {s['frames_tracing']:.0%} | {s['median_trace_ms']:.1f} / {s['max_trace_ms']:.1f} | {s['mean_relevance_captured']:.3f} | "
                  f"{s['mean_selection_changes']:.2f} | {s['mean_selected']:.1f} / {s['mean_visible']:.1f} |")
    args.output.with_suffix(".md").write_text("\n".join(md) + "\n")
    _plot(args.output.with_suffix(".png"), runs, budget)
    print("\n".join(md))


def _plot(path: Path, runs: dict, budget: float) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 4.5))
    for name, frames in runs.items():
        left.plot([f["trace_ms"] for f in frames], label=name, lw=1.2)
    left.axhline(budget, color="k", ls="--", label="budget")
    left.axhline(1.2 * budget, color="k", ls=":", label="budget + 20 %")
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
