"""Stop 43's tables from its outputs: python3 docs/results/gpu/issue10/stop43/summary.py"""
import json
import re
import tarfile
from pathlib import Path

HERE = Path(__file__).parent / "outputs"
print("| scene | side | run | wall ms/frame, 1 / 2 in flight | change |")
print("|---|---|---|---|---|")
for run in (1, 2):
    for line in (HERE / f"wall_{run}.txt").read_text().splitlines():
        m = re.match(r"\s*(\S+)\s+(raster|raytrace)\s+wall ms/frame 1 / 2 in flight: ([\d.]+) / ([\d.]+)", line)
        if m:
            one, two = float(m[3]), float(m[4])
            side = "hybrid" if m[2] == "raster" else "RT"
            print(f"| {m[1]} | {side} | {run} | {one:.2f} / {two:.2f} | {100 * (two / one - 1):+.1f} % |")
print()
print("| round | side | scene | DR | Hybrid | RT | paired Gain (H / RT ms) | 2 in flight: Gain (H / RT ms) | `path` 1 spp |")
print("|---|---|---|---|---|---|---|---|---|")
for name, member in (("s43_1_new", "s43_1/bench_new"), ("s43_2_old", "s43_2/bench_old"), ("s43_2_new", "s43_2/bench_new")):
    reports = json.load(tarfile.open(HERE / f"{name}.tar.xz").extractfile(f"{member}/bench.json"))
    for r in reports:
        g, f = r["gain_paired"], r.get("gain_in_flight")
        flight = f"{f['median']:.3f} ({f['hybrid_ms']:.2f} / {f['rt_ms']:.2f})" if f else "–"
        print(f"| {name[4]} | {name.split('_')[-1]} | {r['name']} | {r['dr_ms']:.2f} | {r['hybrid_ms']:.2f} | {r['rt_ms']:.2f} | "
              f"{g['median']:.3f} ({g['hybrid_ms']:.2f} / {g['rt_ms']:.2f}) | {flight} | {r['path_1spp_ms']:.2f} |")
