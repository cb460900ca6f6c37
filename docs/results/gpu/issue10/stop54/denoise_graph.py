"""What issuing the denoiser costs the host, with and without a CUDA graph (issue 10, stop 54).

A budgeted frame is host-bound on the H200: its host issues and learns for longer than the GPU
works (stop 53). Among its host phases, ``post`` (0.55 ms in stop 49's ``host_phases.txt``) is
mostly the denoiser's call (0.45 ms), whose filter Open Image Denoise issues as a few dozen CUDA
launches on Dr.Jit's stream. With the diff below, ``denoise.Denoiser`` captures them once into a CUDA
graph (``interop.StreamGraph``). On random images of the frame's size, two denoisers in turn:
``filter`` (the graph turned off, as before) and ``graph`` (the diff's code). Per side, over
``--repeats`` calls each synchronized: the host's time of ``Denoiser.__call__``, of the filter's
issue alone (``execute_async`` or ``cuGraphLaunch``: the probe times the denoiser's own
``_launch_filter``) and the filter's device time (CUDA events); then whether the two sides'
outputs are equal bit for bit, and ``Denoiser.launch``.

    python3 docs/results/gpu/issue10/stop54/denoise_graph.py --resx 1280 --resy 720

Tried and reverted: the graph is not in the package. Apply the diff first
(``git apply docs/results/gpu/issue10/stop54/diffs/denoise_graph.diff``), as the runs did.
"""
from __future__ import annotations

import argparse
import statistics
import time


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--resx", type=int, default=1280)
    parser.add_argument("--resy", type=int, default=720)
    parser.add_argument("--repeats", type=int, default=50)
    parser.add_argument("--quality", default="fast")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant("cuda_ad_rgb")
    from hybrid_integrator.denoise import Denoiser, Guides

    w, h = args.resx, args.resy
    rng = np.random.default_rng(0)
    color, albedo, normal = (mi.TensorXf(rng.random((h, w, 3), dtype=np.float32)) for _ in range(3))
    guides = Guides(albedo=albedo, normal=normal)
    sides = {"filter": Denoiser(args.quality), "graph": Denoiser(args.quality)}
    sides["filter"]._graphs[(w, h)] = None  # as before this stop: the filter issued every call
    issue = {name: [] for name in sides}
    for name, denoiser in sides.items():  # each side's issue of the filter alone, timed in place
        launch = denoiser._launch_filter

        def timed(*a, _launch=launch, _times=issue[name]):
            start = time.perf_counter()
            _launch(*a)
            _times.append((time.perf_counter() - start) * 1e3)
        denoiser._launch_filter = timed
    outputs = {}
    for name, denoiser in sides.items():
        for _ in range(5):
            outputs[name] = denoiser(color, guides)
        dr.eval(outputs[name])
        issue[name].clear()
    dr.sync_thread()
    calls, device = {n: [] for n in sides}, {n: [] for n in sides}
    for _ in range(args.repeats):
        for name, denoiser in sides.items():
            dr.sync_thread()
            start = time.perf_counter()
            out = denoiser(color, guides)
            calls[name].append((time.perf_counter() - start) * 1e3)
            dr.eval(out)
            dr.sync_thread()
            device[name].append(denoiser.elapsed_ms())
    for name, denoiser in sides.items():
        print(f"{name:6s} ({denoiser.launch}): Denoiser.__call__ host {statistics.median(calls[name]):.3f} ms, "
              f"the filter's issue {statistics.median(issue[name]):.3f} ms, device {statistics.median(device[name]):.3f} ms")
    same = np.array_equal(np.array(outputs["filter"]).view(np.uint32), np.array(outputs["graph"]).view(np.uint32))
    print(f"outputs equal bit for bit: {same}")


if __name__ == "__main__":
    main()
