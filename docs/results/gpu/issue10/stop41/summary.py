"""Stop 41: the bench outputs of outputs/*.tar.xz in a few tables (python3 summary.py, from this folder
or with the folder as its argument): per configuration and scene, the medians over its rounds of
the stages that differ between the hybrid and the RT baseline (device ms; the hybrid's raster stage
includes its OpenGL pass, shown apart too), the sum of each method's stages ("device"), its frame,
the frame's time outside those stages ("rest": host issue the GPU waits for, the frame's end), and
the paired Gain (median of each round's median, with its range)."""
import io
import json
import statistics as st
import sys
import tarfile
from collections import defaultdict
from pathlib import Path

folder = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).parent) / "outputs"
groups: dict[str, dict[str, list[dict]]] = defaultdict(lambda: defaultdict(list))
for archive in sorted(folder.glob("*.tar.xz")):
    with tarfile.open(archive) as tar:
        for member in tar.getmembers():
            if not member.name.endswith(".json") or member.name.endswith("bench.json"):
                continue
            run = json.load(io.TextIOWrapper(tar.extractfile(member)))
            depth = run["ground_truth"]["max_depth"]
            groups[f"max_depth {depth}, refine {run['refine'].split(':')[0]}"][run["name"]].append(run)

COLUMNS = ("H raster", "of it GL", "RT raster", "H trace", "RT trace", "H device", "RT device", "H frame", "RT frame",
           "H rest", "RT rest")
for config, scenes in groups.items():
    print(f"\n{config} (ms, medians over rounds; H = hybrid, all candidates)")
    print("| scene | rounds | " + " | ".join(COLUMNS) + " | paired Gain, median (range) |")
    print("|---" * (len(COLUMNS) + 3) + "|")
    for name, runs in sorted(scenes.items()):
        values = defaultdict(list)
        for run in runs:
            m = {r["method"]: r for r in run["methods"]}
            h, rt = m["hybrid"]["stages_ms"], m["rt-baseline"]["stages_ms"]
            # the stages' sum: "raster" includes "gl" (FrameStats), "issue" and "total" are the host's
            device = lambda s: sum(v for k, v in s.items() if k not in ("gl", "issue", "total"))  # noqa: E731
            hf, rf = m["hybrid"]["time_ms"], m["rt-baseline"]["time_ms"]
            for key, value in zip(COLUMNS, (h["raster"], h["gl"], rt["raster"], h["trace"], rt["trace"], device(h),
                                            device(rt), hf, rf, hf - device(h), rf - device(rt))):
                values[key].append(value)
            values["gain"].append(run["gain_paired"]["median"])
        gains = values["gain"]
        print(f"| {name} | {len(runs)} | " + " | ".join(f"{st.median(values[k]):.2f}" for k in COLUMNS)
              + f" | {st.median(gains):.3f} ({min(gains):.3f}–{max(gains):.3f}) |")
