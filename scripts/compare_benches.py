"""Two sets of ``hybrid bench`` reports side by side: frame times and stage times before → after.

Each folder holds one JSON report per scene (``hybrid bench -o DIR``, or ``--single`` reports);
scenes are matched by name. Writes a markdown table (DR, RT, Hybrid, Gain, and each stage of the
hybrid frame) to ``-o`` and prints it.

    python scripts/compare_benches.py docs/results/gpu/issue10/before docs/results/gpu/issue10/after \
        -o docs/results/gpu/issue10/before_after.md
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

STAGES = ("raster", "lighting", "select", "trace", "compose")


def load(folder: Path) -> dict[str, dict]:
    reports = {}
    for path in sorted(folder.glob("*.json")):
        report = json.loads(path.read_text())
        if isinstance(report, dict) and "methods" in report:
            reports[report["name"]] = report
    return reports


def method(report: dict, name: str) -> dict:
    return next(m for m in report["methods"] if m["method"] == name)


def table(before: dict[str, dict], after: dict[str, dict]) -> str:
    lines = ["| scene | shapes | DR ms | RT ms | Hybrid ms | Hybrid speed-up | Gain = RT / Hybrid |",
             "|---|---|---|---|---|---|---|"]
    for name in before:
        if name not in after:
            continue
        b, a = before[name], after[name]
        lines.append(f"| {name} | {b['shapes']} → {a['shapes']} | {b['dr_ms']:.2f} → {a['dr_ms']:.2f} | "
                     f"{b['rt_ms']:.2f} → {a['rt_ms']:.2f} | {b['hybrid_ms']:.2f} → {a['hybrid_ms']:.2f} | "
                     f"{b['hybrid_ms'] / a['hybrid_ms']:.2f}× | {b['gain']:.2f} → {a['gain']:.2f} |")
    lines += ["", "Stages of the all-candidates hybrid frame (ms; before: each stage synchronized; after: device "
              "time from CUDA events, one synchronization per frame, and the host's issue time):", "",
              "| scene | " + " | ".join(STAGES) + " | after: GL draw | after: host issue |",
              "|---|" + "---|" * (len(STAGES) + 2)]
    for name in before:
        if name not in after:
            continue
        sb, sa = method(before[name], "hybrid")["stages_ms"], method(after[name], "hybrid")["stages_ms"]
        cells = " | ".join(f"{sb[k]:.2f} → {sa[k]:.2f}" for k in STAGES)
        lines.append(f"| {name} | {cells} | {sa.get('gl', 0.0):.2f} | {sa.get('issue', 0.0):.2f} |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("before", type=Path)
    parser.add_argument("after", type=Path)
    parser.add_argument("-o", "--output", type=Path)
    args = parser.parse_args()
    text = table(load(args.before), load(args.after))
    if args.output:
        args.output.write_text(text + "\n")
    print(text)


if __name__ == "__main__":
    main()
