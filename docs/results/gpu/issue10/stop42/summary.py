"""Stop 42: the tables of README.md from outputs/ (python3 summary.py): per experiment (round 1 =
A, 2 = B, 3 = D; new = main with that experiment's diff, old = main), per scene, the hybrid's and
the RT baseline's trace stage and frame (median ms of 20 frames, all candidates, denoised), and
the paired Gain."""
import io
import json
import tarfile
from pathlib import Path

HERE = Path(__file__).parent / "outputs"
EXPERIMENTS = {1: "A: unmap + raster pass issued during the trace", 2: "B: the same, the pass's commands flushed after the counts",
               3: "D: only the unmap issued during the trace"}


def rows(round_: int, side: str) -> dict:
    with tarfile.open(HERE / f"s42_{round_}_{side}.tar.xz") as tar:
        member = tar.getmember(f"s42_{round_}/bench_{side}/bench.json")
        scenes = json.load(io.TextIOWrapper(tar.extractfile(member)))
    out = {}
    for s in scenes:
        stages = {m["method"]: m["stages_ms"] for m in s["methods"]}
        out[s["name"]] = (stages["hybrid"], stages["rt-baseline"], s["gain_paired"]["median"])
    return out


for round_, title in EXPERIMENTS.items():
    new, old = rows(round_, "new"), rows(round_, "old")
    print(f"\n{title} (bench round {round_}; new / old)")
    print("| scene | hybrid trace | RT trace | hybrid frame | RT frame | paired Gain |")
    print("|---|---|---|---|---|---|")
    for name in new:
        (hn, rn, gn), (ho, ro, go) = new[name], old[name]
        print(f"| {name} | {hn['trace']:.2f} / {ho['trace']:.2f} | {rn['trace']:.2f} / {ro['trace']:.2f} | "
              f"{hn['total']:.2f} / {ho['total']:.2f} | {rn['total']:.2f} / {ro['total']:.2f} | {gn:.3f} / {go:.3f} |")
