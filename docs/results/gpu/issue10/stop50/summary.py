"""Prints stop 50's timing bench tables from outputs/bench/ and outputs/bench2/ (two machines; hybrid frames timed with
``stage_times=false``; stage breakdowns from frames of their own) and the FLIP of each default frame
from stop 49's run (the same images: stage_times changes no pixel, tests/test_integrator.py).

    python3 docs/results/gpu/issue10/stop50/summary.py
"""
import json
from pathlib import Path

HERE = Path(__file__).resolve().parent
OUT = HERE / "outputs"
STOP49 = HERE.parent / "stop49" / "outputs"
SCENES = ("armadillo_glass", "showcase", "sponza_mirror", "dining_room", "many_objects")


def main() -> None:
    for run in ("bench", "bench2"):
        print(f"{run}:")
        table(OUT / run)
        print()


def table(runs: Path) -> None:
    print("| scene | DR | RT | hybrid | paired Gain [quartiles] | 25 % | 50 % | 75 % | 50 % / RT | `path` 1 spp, frozen "
          "| `path` 1 spp, `mi.render` | 2 in flight: hybrid / RT | hybrid's FLIP (stop 49) |")
    print("|---|" + "---|" * 12)
    for scene in SCENES:
        (r,) = json.loads((runs / scene / "bench.json").read_text())
        rows = {m["method"]: m for m in r["methods"]}
        g = r["gain_paired"]
        flip = "–"
        if (STOP49 / scene / "bench.json").exists():
            (old,) = json.loads((STOP49 / scene / "bench.json").read_text())
            flip = f"{next(m['flip'] for m in old['methods'] if m['method'] == 'hybrid'):.4f}"
        budgets = [rows[f"hybrid@{p}%"]["time_ms"] for p in (25, 50, 75)]
        print(f"| {scene} | {r['dr_ms']:.2f} | {r['rt_ms']:.2f} | {r['hybrid_ms']:.2f} | {g['median']:.3f} "
              f"[{g['q25']:.3f}, {g['q75']:.3f}] | " + " | ".join(f"{b:.2f}" for b in budgets)
              + f" | {r['rt_ms'] / budgets[1]:.2f}× | {r['path_1spp_frozen_ms']:.2f} | {r['path_1spp_ms']:.2f} | "
              f"{r['gain_in_flight']['hybrid_ms']:.2f} / {r['gain_in_flight']['rt_ms']:.2f} | {flip} |")


if __name__ == "__main__":
    main()
