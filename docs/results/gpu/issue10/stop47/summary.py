"""The tables of README.md from outputs/: budgets before and after stop 47's selection fix (the old
tree and this one, in turn, per scene, in one device session), and the item-4 camera path.

    python3 docs/results/gpu/issue10/stop47/summary.py
"""
import json
from pathlib import Path

OUT = Path(__file__).parent / "outputs"


def main() -> None:
    rows = [json.loads(line) for line in (OUT / "budget_flip.jsonl").read_text().splitlines()]
    print("| scene | budget | before: frame ms / trace ms / FLIP | after: frame ms / trace ms / FLIP |")
    print("|---|---|---|---|")
    for scene in dict.fromkeys(r["scene"] for r in rows):
        side = {r["label"]: r for r in rows if r["scene"] == scene}
        for key in ("hybrid", "0%", "25%", "50%", "75%"):
            cells = []
            for label in ("old", "new"):
                m = side[label][key]
                cells.append(f"{m['total_ms']:.2f} / {m['trace_ms']:.2f} / {m['flip']:.3f}")
            budget = "all candidates" if key == "hybrid" else f"{key} ({side['new'][key]['budget_ms']:.2f} ms)"
            print(f"| {scene} | {budget} | {cells[0]} | {cells[1]} |")
    print()
    print("| dining room, run | budget | frame ms | trace ms | denoise ms | host issue ms | FLIP |")
    print("|---|---|---|---|---|---|---|")
    for n, row in enumerate(json.loads(line) for line in (OUT / "dining_stages.jsonl").read_text().splitlines()):
        for key in ("hybrid", "25%", "50%"):
            m = row[key]
            print(f"| {n + 1}: {row['label']} | {'all candidates' if key == 'hybrid' else key} | {m['total_ms']:.2f} | "
                  f"{m['trace_ms']:.2f} | {m['stages_ms']['denoise']:.2f} | {m['stages_ms']['issue']:.2f} | {m['flip']:.3f} |")
    print()
    for line in (OUT / "budget.md").read_text().splitlines():
        if line.startswith("| nested") or line.startswith("| run") or line.startswith("|---"):
            print(line)


if __name__ == "__main__":
    main()
