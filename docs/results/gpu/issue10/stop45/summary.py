"""Stop 45's tables from its outputs: python3 docs/results/gpu/issue10/stop45/summary.py"""
import json
import re
import tarfile
from pathlib import Path

HERE = Path(__file__).parent / "outputs"

print("## The compute visibility pass per version (GL ms, median of 21; variants.py)\n")
for run in ("variants", "variants2"):
    text = (HERE / f"{run}.txt").read_text()
    versions = list(dict.fromkeys(re.findall(r"^  (\S+)\s+pass", text, re.M)))
    print(f"{run}.txt\n\n| scene | " + " | ".join(versions) + " | bit for bit |\n|---|" + "---|" * (len(versions) + 1))
    for block in re.split(r"\n(?=\S)", text.strip()):
        scene = block.split(":")[0]
        times = dict(re.findall(r"^  (\S+)\s+pass (\S+) ms", block, re.M))
        same = all(s == "True" for s in re.findall(r"as new: (\w+)", block))
        print(f"| {scene} | " + " | ".join(times.get(v, "") for v in versions) + f" | {same} |")
    print()

print("## The timing bench (bench.json of each round and side)\n")
print("| round | side | scene | DR | GL pass | Hybrid | RT | paired Gain [quartiles] | hybrid@50% (RT / it) | `path` 1 spp | 2 in flight |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
for run, sides in ((1, ("new", "old")), (2, ("old", "new")), (3, ("new", "old"))):
    archive = tarfile.open(HERE / f"s45_{run}.tar.xz")
    for side in sides:
        for r in json.load(archive.extractfile(f"s45_{run}/bench_{side}/bench.json")):
            g, f = r["gain_paired"], r["gain_in_flight"]
            half = next(m["time_ms"] for m in r["methods"] if m["method"] == "hybrid@50%")
            print(f"| {run} | {side} | {r['name']} | {r['dr_ms']:.2f} | {r['gl_ms']:.2f} | {r['hybrid_ms']:.2f} | "
                  f"{r['rt_ms']:.2f} | {g['median']:.3f} [{g['q25']:.3f}, {g['q75']:.3f}] | {half:.2f} ({r['rt_ms'] / half:.2f}×) | "
                  f"{r['path_1spp_ms']:.2f} | {f['median']:.3f} |")

items = tarfile.open(HERE / "items.tar.xz")
trace = json.load(items.extractfile("items/trace_overhead.json"))
print("\n## Item 3: trace_overhead.py (many_objects)\n")
print("| pixels | wall ms | device ms |\n|---|---|---|")
print(f"| 0 | {trace['no_pixel']['wall_ms']:.3f} | {trace['no_pixel']['device_ms']:.3f} |")
for row in trace["rows"]:
    print(f"| {row['pixels']:,} | {row['wall_ms']:.3f} | {row['device_ms']:.3f} |")
for clock in ("wall_ms", "device_ms"):
    line, log = trace["fit"][clock], trace["fit_with_log_term"][clock]
    print(f"\n{clock}: line {line['fixed_ms']:.3f} + {line['ms_per_1000_pixels']:.4f} per 1000 pixels; "
          f"c0 + c1 ln N + c2 N: {log['fixed_ms']:.3f}, {log['ms_per_ln_pixels']:.4f}, {log['ms_per_1000_pixels']:.4f}")

budget = json.load(items.extractfile("items/budget.json"))
print("\n## Item 4: budget_benchmark.py (camera path, default selection `nested`)\n")
print("| run | frames that trace | within budget + 10 % | median frame ms |\n|---|---|---|---|")
for name, s in budget["summaries"].items():
    if name.startswith(("nested", "all", "RT")):
        within = "–" if s["within_budget_plus_10"] is None else f"{100 * s['within_budget_plus_10']:.0f} %"
        print(f"| {name} | {100 * s['frames_tracing']:.0f} % | {within} | {s['median_frame_ms']:.2f} |")

scaling = json.load(items.extractfile("items/scaling_triangles.json"))
print("\n## Item 2: --scaling triangles\n\n| triangles | DR ms | hybrid ms | RT ms |\n|---|---|---|---|")
for p in scaling["points"]:
    print(f"| {p['triangles']:,} | {p['dr_ms']:.2f} | {p['hybrid_ms']:.2f} | {p['rt_ms']:.2f} |")

print("\n## Sponza alone, rounds 4-11 (SCENES=scenes/sponza_mirror.xml; even rounds \"new old\", odd \"old new\")\n")
print("| round | paired Gain new | paired Gain old |\n|---|---|---|")
gains = {"new": [], "old": []}
for run in range(1, 12):
    archive = tarfile.open(HERE / f"s45_{run}.tar.xz")
    row = {}
    for side in ("new", "old"):
        r = next(r for r in json.load(archive.extractfile(f"s45_{run}/bench_{side}/bench.json")) if r["name"] == "sponza_mirror")
        row[side] = r["gain_paired"]["median"]
        gains[side].append(row[side])
    if run > 3:
        print(f"| {run} | {row['new']:.3f} | {row['old']:.3f} |")
for side, values in gains.items():
    values = sorted(values)
    print(f"\n{side}, rounds 1-11: median {values[len(values) // 2]:.3f}, {values[0]:.3f}-{values[-1]:.3f}, "
          f"below 1.0 in {sum(v < 1.0 for v in values)} of {len(values)}")
