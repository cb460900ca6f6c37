"""What a frozen function's replay walks: every shape alive in the process (issue 10, item 3).

A trace call's fixed wall time is mostly Dr.Jit 1.5's frozen-function replay walking its inputs
before it launches anything (``scripts/trace_overhead.py``: a frozen ``lambda scene, x: x + 1``
replays in ~0.6-0.7 ms on the H100's host for the 18-shape many-object scene, 0.02 ms without the
scene). This probe shows what that walk covers: the replay of the same frozen function on a scene
of one sphere, while N more objects of one kind are alive in the process but in no scene. Extra
shapes (with their BSDFs) lengthen every replay, ~10 µs each on this machine's CPU (200 spheres:
0.02 → 2.04 ms); 200 BSDFs, emitters, sensors, textures or integrators alone leave it at 0.08–0.12
ms, about where it stays once the spheres are freed again (0.11 ms).
So the walk follows Dr.Jit's registry of live shapes, whichever scene holds them. Beside it, the
same function frozen as the device pass now is (``frozen.FrozenScene``: the scene's variables,
taken once, in the scene's place): no registry walk, so the objects alive elsewhere change nothing
(docs/results/cpu/frozen_walk.txt).

    python scripts/frozen_walk.py -o docs/results/cpu/frozen_walk.txt
"""
from __future__ import annotations

import argparse
import gc
from pathlib import Path

from trace_overhead import timed  # scripts/ is on sys.path when a script runs


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--count", type=int, default=200, help="extra objects of each kind")
    parser.add_argument("--repeats", type=int, default=301)
    parser.add_argument("-o", "--output", type=Path, default=None)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)

    def replay_ms(fn) -> float:
        return timed(fn, args.repeats)[0]  # the median wall time, one synchronization per call

    from hybrid_integrator.frozen import FrozenScene

    x = dr.arange(mi.Float, 10)
    frozen = dr.freeze(lambda scene, x: x + 1)
    scene = mi.load_dict({"type": "scene", "s": {"type": "sphere"}})
    snapshot = FrozenScene(scene).freeze(lambda scene, x: x + 1)

    def both() -> str:
        return f"{replay_ms(lambda: frozen(scene, x)):.3f} ms (its variables: {replay_ms(lambda: snapshot(x)):.3f} ms)"

    kinds = {"sphere (shape + its BSDF)": {"type": "sphere"}, "diffuse BSDF": {"type": "diffuse"},
             "point emitter": {"type": "point"}, "perspective sensor": {"type": "perspective"},
             "checkerboard texture": {"type": "checkerboard"}, "path integrator": {"type": "path"}}
    lines = [f"{args.variant}: median replay of a frozen `lambda scene, x: x + 1` on a one-sphere scene, "
             f"{args.repeats} calls, one sync each; in brackets the same given the scene's variables (frozen.py)",
             f"nothing else alive: {both()}"]
    for name, spec in kinds.items():
        extra = [mi.load_dict(spec) for _ in range(args.count)]
        lines.append(f"+{args.count} {name} alive (in no scene): {both()}")
        del extra
        gc.collect()
    lines.append(f"all freed again: {both()}")
    text = "\n".join(lines)
    print(text)
    if args.output:
        args.output.parent.mkdir(parents=True, exist_ok=True)
        args.output.write_text(f"python scripts/frozen_walk.py --variant {args.variant} --count {args.count}\n{text}\n")


if __name__ == "__main__":
    main()
