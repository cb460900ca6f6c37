"""Prints stop 49's tables from outputs/: the time–FLIP plane of the four bench scenes (the bench
with path's curve frozen) and the still-camera histories against path with and without the
denoiser (history_rivals.py).

    python3 docs/results/gpu/issue10/stop49/summary.py
"""
import json
from pathlib import Path

OUT = Path(__file__).resolve().parent / "outputs"
SCENES = ("armadillo_glass", "showcase", "sponza_mirror", "dining_room")
COLUMNS = ("hybrid", "hybrid, no denoiser", "hybrid@25%", "hybrid@50%", "hybrid@75%", "path@1spp",
           "path@1spp, mi.render", "path+denoiser 'fast'@1spp", "path+denoiser@1spp")


def main() -> None:
    print("| scene | " + " | ".join(f"`{c}`" for c in COLUMNS) + " | paired Gain |")
    print("|---|" + "---|" * (len(COLUMNS) + 1))
    for scene in SCENES:
        (report,) = json.loads((OUT / scene / "bench.json").read_text())
        rows = {m["method"]: m for m in report["methods"]}
        cells = [f"{rows[c]['time_ms']:.2f} / {rows[c]['flip']:.4f}" for c in COLUMNS]
        print(f"| {scene} | " + " | ".join(cells) + f" | {report['gain_paired']['median']:.3f} |")
    print()
    print("| scene | history | frames, total ms | history FLIP / rel. MSE | `path` spp | `path` FLIP / rel. MSE "
          "| `path` + OIDN 'fast' ms | `path` + OIDN 'fast' FLIP / rel. MSE |")
    print("|---|---|---|---|---|---|---|---|")
    for line in (OUT / "history_rivals.txt").read_text().splitlines():
        if not line.startswith("{"):
            continue
        r = json.loads(line)
        print(f"| {r['scene']} | {r['history'].removeprefix('hybrid+history').lstrip(', ') or '1 path/hit'} | "
              f"{r['frames']}, {r['history_total_ms']:.0f} | {r['history_flip']:.4f} / {r['history_rel_mse']:.4f} | "
              f"{r['spp']} | {r['path_flip']:.4f} / {r['path_rel_mse']:.4f} | {r['path_denoised_ms']:.0f} | "
              f"{r['path_denoised_flip']:.4f} / {r['path_denoised_rel_mse']:.4f} |")


if __name__ == "__main__":
    main()
