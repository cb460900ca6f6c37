"""Prints stop 48's tables from outputs/: the stage times' readout before and after (readout.txt),
the timing bench with the new frame total (bench/bench.json) and the budgets (budget_flip.jsonl).

    python3 docs/results/gpu/issue10/stop48/summary.py
"""
import json
import re
from pathlib import Path

OUT = Path(__file__).parent / "outputs"


def main() -> None:
    print("| scene | largest kernel (ops) | readout ms, drjit.kernel_history → C API | wall ms per frame, before → after |")
    print("|---|---|---|---|")
    rows = {}
    for line in (OUT / "readout.txt").read_text().splitlines():
        m = re.match(r"(\S+) \[(.+?)\] readout ([\d.]+) ms, total ([\d.]+) ms, wall ([\d.]+) ms .*largest kernel (\d+)", line)
        if m:
            rows.setdefault(m[1], {})[m[2]] = (float(m[3]), float(m[5]), int(m[6]))
    for scene, r in rows.items():
        a, b = r["drjit.kernel_history"], r["C API"]
        print(f"| {scene} | {a[2]} | {a[0]:.3f} → {b[0]:.3f} | {a[1]:.2f} → {b[1]:.2f} ({b[1] - a[1]:+.2f}) |")
    print()
    print("| scene | DR | hybrid | RT | paired Gain | hybrid @50 % | `path` 1 spp (`mi.render`) | `path` 1 spp, frozen |")
    print("|---|---|---|---|---|---|---|---|")
    for r in json.loads((OUT / "bench" / "bench.json").read_text()):
        half = next(m["time_ms"] for m in r["methods"] if m["method"] == "hybrid@50%")
        g = r["gain_paired"]
        gain = f"{g['median']:.3f}" if isinstance(g, dict) else f"{g:.3f}"
        print(f"| {r['name']} | {r['dr_ms']:.2f} | {r['hybrid_ms']:.2f} | {r['rt_ms']:.2f} | {gain} | {half:.2f} | "
              f"{r['path_1spp_ms']:.2f} | {r['path_1spp_frozen_ms']:.2f} |")
    print()
    print("| scene | budget | frame ms | trace ms (budget) | readout ms | FLIP |")
    print("|---|---|---|---|---|---|")
    for line in (OUT / "budget_flip.jsonl").read_text().splitlines():
        r = json.loads(line)
        for key, v in r.items():
            if isinstance(v, dict):
                budget = f"{v['trace_ms']:.2f} ({v['budget_ms']:.2f})" if "budget_ms" in v else f"{v['trace_ms']:.2f}"
                print(f"| {r['scene']} | {'all candidates' if key == 'hybrid' else key} | {v['total_ms']:.2f} | {budget} | "
                      f"{v['host_ms']['timing']:.3f} | {v['flip']:.3f} |")


if __name__ == "__main__":
    main()
