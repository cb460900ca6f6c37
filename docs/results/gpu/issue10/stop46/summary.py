"""Stop 46's tables from its outputs: time (ms) and FLIP of the methods that decide where the hybrid
stands, per bench scene (outputs/accuracy/*/bench.json: ``hybrid bench … --gt-spp 1024
--max-path-spp 16``, one process per scene), and the timing bench's Table 3 columns
(outputs/timing/bench.json: ``--no-accuracy``).

    python3 docs/results/gpu/issue10/stop46/summary.py
"""
import json
from pathlib import Path

OUT = Path(__file__).parent / "outputs"
SCENES = ("armadillo_glass", "showcase", "sponza_mirror", "dining_room")
#: (column, method): the default frame, its estimator without the denoiser, the same denoiser as
#: path + denoiser's, half the trace budget; path as mi.render calls it, frozen, and denoised
COLUMNS = (("hybrid", "hybrid"), ("hybrid, no denoiser", "hybrid, no denoiser"),
           ("hybrid, OIDN 'high'", "hybrid, denoiser 'high'"), ("hybrid, 50 % budget", "hybrid@50%"),
           ("`path` 1 spp", "path@1spp"), ("`path` 1 spp, frozen", "path, frozen@1spp"),
           ("`path` + OIDN 'high', frozen", "path+denoiser@1spp"))


def main() -> None:
    print("ms / FLIP against `path` at 1024 spp (H200, 1280×720, 1 spp per frame)\n")
    print("| scene | " + " | ".join(c for c, _ in COLUMNS) + " |")
    print("|---" * (len(COLUMNS) + 1) + "|")
    for scene in SCENES:
        (report,) = json.loads((OUT / "accuracy" / scene / "bench.json").read_text())
        by_name = {m["method"]: m for m in report["methods"]}
        cells = [f"{by_name[m]['time_ms']:.2f} / {by_name[m]['flip']:.3f}" for _, m in COLUMNS]
        print(f"| {scene} | " + " | ".join(cells) + " |")
    print("\nTable 3's columns, ms (paired Gain: RT baseline / hybrid, frames in turn)\n")
    print("| scene | run | DR | RT baseline | hybrid | paired Gain | `path` 1 spp | `path` 1 spp, frozen |")
    print("|---|---|---|---|---|---|---|---|")
    runs = [("accuracy", json.loads((OUT / "accuracy" / s / "bench.json").read_text())[0]) for s in SCENES]
    runs += [("timing", r) for r in json.loads((OUT / "timing" / "bench.json").read_text())]
    for run, r in runs:
        print(f"| {r['name']} | {run} | {r['dr_ms']:.2f} | {r['rt_ms']:.2f} | {r['hybrid_ms']:.2f} | "
              f"{r['gain_paired']['median']:.3f} | {r['path_1spp_ms']:.2f} | {r['path_1spp_frozen_ms']:.2f} |")


if __name__ == "__main__":
    main()
