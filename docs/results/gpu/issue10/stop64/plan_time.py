"""Stop 64's probes behind its CPU numbers (run from the repository root, llvm_ad_rgb):

    .venv/bin/python docs/results/gpu/issue10/stop64/plan_time.py plan   # the 2 000 objects' plan
    .venv/bin/python docs/results/gpu/issue10/stop64/plan_time.py mask   # path / prb / direct / hybrid on a mask BSDF

``plan``: the stability case "2 000 objects: selection time" run once with ``HybridRenderer._plan``
wrapped, printing per plan its wall and thread ms (equal: no contention), and the medians of
eq. 1–3 (``candidates``), the selector (``select_rows``) and ``typical_rays`` called 300 times on
the last plan's own inputs (hot caches), against the same in the frame (cold).
``mask``: a diffuse sphere in a mask BSDF (opacity 0.5) under a point light, max_depth 2 (direct
light at the first vertex), 256 spp: each integrator's image mean.
"""
from __future__ import annotations

import statistics
import sys
import time
import timeit
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[5]))


def plan() -> None:
    import hybrid_integrator.pipeline as P
    from hybrid_integrator.heuristic import typical_rays
    from hybrid_integrator.selection_graph import select_rows
    from hybrid_integrator.stability import catalog, run_case

    calls, inputs, in_frame = [], {}, {"candidates": [], "plan_frame": []}
    plan_method, cand, frame_plan = P.HybridRenderer._plan, P.candidates, P.plan_frame

    def timed(name, fn):
        def call(*a, **k):
            inputs[name] = (a, k)
            start = time.perf_counter()
            out = fn(*a, **k)
            in_frame[name].append((time.perf_counter() - start) * 1e3)
            return out
        return call

    def wrapped(self, *a, **k):
        wall, cpu = time.perf_counter(), time.thread_time()
        out = plan_method(self, *a, **k)
        calls.append(((time.perf_counter() - wall) * 1e3, (time.thread_time() - cpu) * 1e3))
        return out

    P.HybridRenderer._plan, P.candidates, P.plan_frame = wrapped, timed("candidates", cand), timed("plan_frame", frame_plan)
    case = next(c for c in catalog() if c.name.startswith("2 000 objects"))
    print("case figure (median plan ms, frames 5-10):", round(run_case(case).figure, 3))
    print("per plan, wall / thread ms:", [(round(w, 3), round(c, 3)) for w, c in calls])
    (ca, ck), (pa, pk) = inputs["candidates"], inputs["plan_frame"]
    hot = {"candidates": lambda: cand(*ca, **ck), "plan_frame": lambda: frame_plan(*pa, **pk),
           "typical_rays": lambda: typical_rays(ca[4], ca[1])}
    c = cand(*ca, **ck)
    model = pa[4]
    hot["select_rows (budget 1e9)"] = lambda: select_rows("nested", model.extra_rows(c.rays), c.relevance, 1e9)
    for name, fn in hot.items():
        print(f"{name}: {timeit.timeit(fn, number=300) / 300 * 1e3:.3f} ms hot", end="")
        print(f", {statistics.median(in_frame[name][4:]):.3f} ms in the frame" if name in in_frame else "")


def mask() -> None:
    import mitsuba as mi
    import numpy as np

    T = mi.ScalarTransform4f
    for integrator in ("path", "prb", "direct", "hybrid"):
        scene = mi.load_dict({
            "type": "scene",
            "integrator": {"type": integrator, **({} if integrator == "direct" else {"max_depth": 2}),
                           **({"denoise": False} if integrator == "hybrid" else {})},
            "sensor": {"type": "perspective", "fov": 40, "to_world": T().look_at([0, 0, 5], [0, 0, 0], [0, 1, 0]),
                       "film": {"type": "hdrfilm", "width": 32, "height": 24}},
            "ball": {"type": "sphere", "bsdf": {"type": "mask", "opacity": 0.5, "bsdf": {"type": "diffuse"}}},
            "light": {"type": "point", "position": [0, 3, 3], "intensity": {"type": "rgb", "value": 10}}})
        print(integrator, float(np.array(mi.render(scene, spp=256, seed=3)).mean()))


if __name__ == "__main__":
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    import hybrid_integrator as hi

    hi.register()
    {"plan": plan, "mask": mask}[sys.argv[1]]()
