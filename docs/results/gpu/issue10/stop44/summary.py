"""Stop 44's tables from its outputs: python3 docs/results/gpu/issue10/stop44/summary.py"""
import json
import tarfile
from pathlib import Path

HERE = Path(__file__).parent / "outputs"
print("| round | side | scene | DR | GL pass | Hybrid | RT | paired Gain (H / RT ms) | 2 in flight: Gain (H / RT ms) |")
print("|---|---|---|---|---|---|---|---|---|")
for run, sides in ((1, ("old", "shared", "late")), (2, ("shared", "old"))):
    archive = tarfile.open(HERE / f"s44_{run}.tar.xz")
    for side in sides:
        for r in json.load(archive.extractfile(f"s44_{run}/bench_{side}/bench.json")):
            g, f = r["gain_paired"], r["gain_in_flight"]
            print(f"| {run} | {side} | {r['name']} | {r['dr_ms']:.2f} | {r['gl_ms']:.2f} | {r['hybrid_ms']:.2f} | {r['rt_ms']:.2f} | "
                  f"{g['median']:.3f} ({g['hybrid_ms']:.2f} / {g['rt_ms']:.2f}) | {f['median']:.3f} ({f['hybrid_ms']:.2f} / {f['rt_ms']:.2f}) |")
