"""Stop 40's run scripts (trace_ab.sh, depth.sh): one trace_overhead.py JSON in a few lines: the
line's and the log-term fit's coefficients, each N's wall and device ms, the path loop's launch
per N (where the run had --launches) and the no-pixel call (where the script made one).

    python3 docs/results/gpu/issue10/stop40/summary.py OUT/trace_overhead.json
"""
import json
import sys

r = json.load(open(sys.argv[1]))
print("  fit", {k: (round(v["fixed_ms"], 3), round(v["ms_per_1000_pixels"], 4)) for k, v in r["fit"].items()})
print("  log fit", {k: tuple(round(v[f], 4) for f in ("fixed_ms", "ms_per_ln_pixels", "ms_per_1000_pixels"))
                    for k, v in r["fit_with_log_term"].items()})
print("  rows", [(x["pixels"], round(x["wall_ms"], 3), round(x["device_ms"], 3)) for x in r["rows"]])
if all("launches" in x for x in r["rows"]):
    print("  loop", [(x["pixels"], round(max(e["ms"] for e in x["launches"]), 4)) for x in r["rows"]])
if "no_pixel" in r:
    print("  no pixel", {k: round(v, 3) for k, v in r["no_pixel"].items()})
