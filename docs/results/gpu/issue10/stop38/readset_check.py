"""Stop 38: which scene inputs the frozen device pass takes on each scene (the read set, or the
whole snapshot with what Dr.Jit said), after a few all-candidates frames and a budgeted one.

    python3 docs/results/gpu/issue10/stop38/readset_check.py cuda_ad_rgb SCENE... -D name=value ...
"""
import sys

import mitsuba as mi

variant, rest = sys.argv[1], sys.argv[2:]
mi.set_variant(variant)
import hybrid_integrator as hi  # noqa: E402

scenes = [a for a in rest if a.endswith(".xml")]
defines = dict(a.split("=", 1) for a in rest if "=" in a and not a.endswith(".xml"))
for path in scenes:
    text = open(path).read()
    scene = hi.load_scene(path, **{k: v for k, v in defines.items() if f"${k}" in text})
    frames = [hi.render(scene, spp=1, seed=k, layers=False, **({"budget_ms": 1.0} if k >= 4 else {})) for k in range(8)]
    functions = hi.api.renderer(scene)._frozen.values()
    snapshot = hi.api.renderer(scene).frozen.variables
    print(path, "frame inputs:", [f.stats.frozen_inputs for f in frames],
          "snapshot:", None if snapshot is None else len(snapshot.handles),
          "read sets:", [None if f.read is None else len(f.read) for f in functions],
          "missed:", sorted({f.missed[:160] for f in functions if f.missed}), flush=True)
