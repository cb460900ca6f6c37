"""The kernel history's parse, stop 57's (entry by entry through ctypes) against this stop's (one
NumPy record array), on the same entries, in turn (issue 10, stop 58).

Launches 33 small kernels with the history on, reads the history through Dr.Jit's C API
(``history._API``) and parses it with each version in turn, ``--repeats`` times; prints the median
host ms of each and whether the two give the same entries (``execution_time`` aside: each read is
a new launch).

    python docs/results/gpu/issue10/stop58/parse_ab.py            # llvm_ad_rgb
"""
from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--repeats", type=int, default=200)
    args = parser.parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import drjit as dr

    from hybrid_integrator import history
    from host_ab import old_parse

    history.reader()
    api = history._API
    if api is None:
        raise SystemExit(f"no C API reader here ({history.READER})")

    def launches() -> None:
        for n in range(33):
            dr.eval(dr.sin(dr.arange(mi.Float, 100 + n)) * n)

    times: dict[str, list[float]] = {"stop 57": [], "stop 58": []}
    out: dict[str, list[dict]] = {}
    for _ in range(args.repeats):
        for name, parse in (("stop 57", old_parse), ("stop 58", history._parse)):
            with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
                dr.kernel_history_clear()
                launches()
                data = api[0]()
            start = time.perf_counter()
            out[name] = parse(api, data)
            times[name].append((time.perf_counter() - start) * 1e3)
    strip = lambda entries: [{k: v for k, v in e.items() if k != "execution_time"} for e in entries]
    print(f"{len(out['stop 58'])} entries; median ms: "
          + ", ".join(f"{name} {statistics.median(v):.4f}" for name, v in times.items())
          + f"; the same entries: {strip(out['stop 57']) == strip(out['stop 58'])}")


if __name__ == "__main__":
    main()
