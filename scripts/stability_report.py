"""The stability report (issue 12): every case of ``hybrid_integrator/stability.py``, slow ones
included, with its measured figure, written to ``docs/results/stability.md`` and one image sheet
per group (a row per rendered case: reference, raster layer, hybrid, error map).

    .venv/bin/python scripts/stability_report.py [-o docs/results] [--variant llvm_ad_rgb]
"""
from __future__ import annotations

import argparse
import math
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _sheet(results, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    rows = [r for r in results if len(r.images) == 4]
    if not rows:
        return
    fig, axes = plt.subplots(len(rows), 4, figsize=(8, 1.5 * len(rows)), squeeze=False)
    for row, r in zip(axes, rows):
        for ax, (title, image) in zip(row, r.images.items()):
            shown = image if image.ndim == 2 else np.clip(image, 0, 1) ** (1 / 2.2)
            ax.imshow(shown, cmap="magma" if image.ndim == 2 else None, interpolation="nearest")
            ax.set_xticks([])
            ax.set_yticks([])
            if row is axes[0]:
                ax.set_title(title, fontsize=8)
        row[0].set_ylabel(r.case.name, fontsize=6, rotation=0, ha="right", va="center")
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    plt.close(fig)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", type=Path, default=ROOT / "docs" / "results")
    parser.add_argument("--variant", default="llvm_ad_rgb")
    args = parser.parse_args()

    import mitsuba as mi
    from tqdm import tqdm

    import hybrid_integrator as hi
    from hybrid_integrator.raster.context import machine
    from hybrid_integrator.stability import catalog, run_case

    mi.set_variant(args.variant)
    hi.register()
    results = [run_case(case) for case in tqdm(catalog(), desc="stability cases", unit="case")]
    sheets = args.output / "stability"
    sheets.mkdir(parents=True, exist_ok=True)
    groups = {"raster": "Raster: the visibility buffer against Mitsuba's camera rays",
              "trace": "Ray tracing from the G-buffer",
              "budget": "Heuristic and budget", "use": "Use and misuse"}
    m = machine()
    passed = sum(r.passed for r in results)
    lines = ["# Stability: where each method fails (issue 12)", "",
             f"Command: `.venv/bin/python scripts/stability_report.py --variant {args.variant}`  ",
             f"Machine: {m['cpu']}, GL {m['gl_renderer']}  ",
             f"**{passed} of {len(results)} cases pass.** Outcomes (`hybrid_integrator/stability.py`): *agree*: "
             "the fraction of pixels where the hybrid frame and the pure ray-tracing baseline (same seed, the paper's "
             "effects, no denoiser) differ by ≤ 1 % of the image mean, at least the bound; *flip*: the hybrid's FLIP "
             "(16 spp, every term, no denoiser) minus `path`'s at the same spp, against `path` at 256 spp, at most the "
             "bound; *error*: a `HybridError` whose message names the problem; *stats*: the frame's own figure. "
             "Slow cases (✱) run here, not in the test command.", ""]
    for group, title in groups.items():
        rows = [r for r in results if r.case.group == group]
        lines += [f"## {title}", "", f"![{group}](stability/{group}.png)", "",
                  "| case | outcome | figure | bound | result | s | what happens / should |", "|---|---|---|---|---|---|---|"]
        for r in rows:
            c = r.case
            figure = "–" if math.isnan(r.figure) else f"{r.figure:.4f}"
            bound = "–" if c.outcome == "error" else f"{c.bound:g}"
            detail = re.sub(r"\s+", " ", r.detail).replace("|", "/")[:160]
            what = "; ".join(x for x in (detail if c.outcome in ("error",) or not r.passed else "", c.note) if x)
            lines.append(f"| {c.name}{' ✱' if c.slow else ''} | {c.outcome} | {figure} | {bound} | "
                         f"{'pass' if r.passed else '**FAIL**'} | {r.seconds:.1f} | {what} |")
        lines.append("")
        _sheet(rows, sheets / f"{group}.png")
    lines += ["## Reading", "",
              "- **Raster wins or ties** wherever geometry is ordinary: meshes of every kind, degenerate or not, analytic "
              "shapes from 1e-3 to 1e3 units, extreme fields of view, principal-point shifts and odd film sizes agree "
              "with Mitsuba's camera rays pixel for pixel. Where the raster cannot resolve a pixel (sub-pixel spheres, "
              "wires, silhouettes, analytic proxies), the hybrid re-traces that pixel with a camera ray, which is why "
              "even 0.1-pixel geometry agrees.",
              "- **Far from the origin** the raster draws vertices relative to the eye, so at 1e6 units it finds the "
              "same triangle as the ray tracer on 99.8 % of the pixels (96.5 % when it drew absolute float32 "
              "positions). At 1e7, float32 positions quantize the scene itself to whole units, and both methods "
              "shade from points a float32 step apart, which shadow rays amplify: neither is reliable there. "
              "Coplanar surfaces (z-fighting) are resolved differently by the two; both answers are valid.",
              "- **Orthographic sensors** are rasterized (depth from camera-space z) and agree on every pixel; their "
              "frames run unfrozen, since Mitsuba 3.9's orthographic sensor holds a variable that a frozen "
              "function cannot capture.",
              "- **Not supported, with a clear error**: thin-lens sensors (a raster has one centre of projection: "
              "the error says to use `primary='raytrace'`), crop windows, instances, non-finite vertices.",
              "- **Scenes without shapes** render Mitsuba's own background, recorded in `FrameStats.fallback`.",
              "- **Ray tracing from the G-buffer** is Mitsuba's `path` estimator. Its FLIP stays within 0.01 of "
              "`path`'s at the same spp for every emitter type, every BSDF tried and max_depth 0/1/2/−1.",
              "- **Budgets**: impossible values are errors; 1e-9 ms traces nothing; 1e9 ms traces everything "
              "after the first frame's probe.",
              "- **Outside the catalog** (`tests/stability/test_use.py`): without an EGL driver the user sees one "
              "line naming the Debian packages to install; an interrupted write leaves no file; the same seed gives "
              "the same image; host memory stays within 5 % over 500 CPU frames. On the GPU, 10 000 frames in one "
              "process leave host and GPU memory flat (+0.08 %, +0.00 %) and an 8192×8192 frame renders in 3.1 s "
              "in 26 GB (`scripts/memory_soak.py`, docs/results/gpu/issue12/).",
              ""]
    (args.output / "stability.md").write_text("\n".join(lines))
    print(f"{passed}/{len(results)} cases pass; report: {args.output / 'stability.md'}")
    return 0 if passed == len(results) else 1


if __name__ == "__main__":
    raise SystemExit(main())
