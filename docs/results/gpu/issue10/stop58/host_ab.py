"""Stop 58's host cuts against stop 57's code, in turn in one process (issue 10, stop 58).

The machines' CPUs run at two speeds that swap within milliseconds to a second (``core_speed.sh``), so two
processes of the same code differ by up to 1.7x in host time: only sides rendered in turn, in one
process, compare host work. Here the two sides are the same integrator with this stop's host code
(``new``) and with stop 57's (``old``, restored before each of its frames through
``frames_in_turn``'s ``before``): ``history._parse`` entry by entry through ctypes, and
``interop._Driver.current`` pushing and popping the context around every group of driver calls.
Per scene and budget (fractions ``--budgets`` of the all-candidates trace time, ``bench.turn_scene``),
the RT baseline and the budgeted hybrid old and new render in turn (rounds of ``--block``
frames, the first of each not measured), along the scene's camera path where it has one. Prints
each side's median frame, the paired ratios old / new (> 1: new is faster) and RT / new, RT / old,
and how often the new driver had to push its context.

    python3 docs/results/gpu/issue10/stop58/host_ab.py scenes/many_objects.xml --variant cuda_ad_rgb --frames 60
"""
from __future__ import annotations

import contextlib
import ctypes

WARM = 3  # rounds not measured: the budget's three probe frames among them


def old_parse(api: tuple, data) -> list[dict]:
    """Stop 57's ``history._parse``: entry by entry through ctypes."""
    import drjit as dr

    from hybrid_integrator.history import _entries

    free = api[1]
    out = []
    if not data:
        return out
    for entry in _entries(data):
        item = {"backend": entry.backend, "type": dr.KernelType(entry.type), "size": entry.size,
                "execution_time": entry.execution_time}
        if item["type"] == dr.KernelType.JIT:
            item.update(hash=f"{entry.hash[1]:016x}{entry.hash[0]:016x}", operation_count=entry.operation_count,
                        uses_optix=entry.uses_optix)
        out.append(item)
        free(entry.ir)
    free(data)
    return out


@contextlib.contextmanager
def old_current(self):
    """Stop 57's ``_Driver.current``: the context pushed and popped every time."""
    self._check(self.lib.cuCtxPushCurrent_v2(self.context), "cuCtxPushCurrent")
    try:
        yield
    finally:
        self.lib.cuCtxPopCurrent_v2(ctypes.byref(ctypes.c_void_p()))


def main() -> None:
    from hybrid_integrator.bench import frames_in_turn, paired_ratio, turn_arguments, turn_poses, turn_scene

    args = turn_arguments(__doc__.splitlines()[0], budgets=(0.25, 0.5), block=5).parse_args()

    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator import history
    from hybrid_integrator.raster import interop

    hi.register()
    versions = {"old": (old_parse, old_current), "new": (history._parse, interop._Driver.current)}

    def use(side: str) -> None:
        """The side's version of the two functions (the history's readers look ``_parse`` up by name)."""
        history._parse, interop._Driver.current = versions["old" if side.endswith("old") else "new"]

    params = dict(args.defines)
    for path in args.scenes:
        ready = turn_scene(str(path), params, turn_poses(args.frames, WARM, args.block))
        print(f"{ready.name}: all-candidates trace {ready.all_candidates_trace_ms:.3f} ms, reader {history.READER}",
              flush=True)
        for fraction in args.budgets:
            budget = fraction * ready.all_candidates_trace_ms
            sides = {"rt new": {"primary": "raytrace"}, "rt old": {"primary": "raytrace"},
                     "budget new": {"budget_ms": budget}, "budget old": {"budget_ms": budget}}
            times = frames_in_turn(ready.scene, sides, args.frames, 1, 0, warmup=WARM, block=args.block,
                                   cameras=ready.cameras, before=use)
            ratios = {f"{a} / {b}": paired_ratio(times, a, b, block=args.block)
                      for a, b in (("budget old", "budget new"), ("rt old", "rt new"), ("rt new", "budget new"),
                                   ("rt old", "budget old"))}
            medians = {s: ratios[k][f"{s}_ms"] for k in ratios for s in k.split(" / ")}
            print(f"{ready.name:16s} {fraction:.0%} budget ({budget:.3f} ms): frame ms "
                  + ", ".join(f"{s} {v:.3f}" for s, v in medians.items()), flush=True)
            for key, r in ratios.items():
                print(f"    {key}: {r['median']:.3f} [{r['q25']:.3f}, {r['q75']:.3f}] ({r['pairs']} rounds)", flush=True)
        use("new")  # then a few frames more, counting the new driver's pushes (apart: the count calls the driver)
        pushes = [0, 0]  # groups of calls with a push, in all
        current = interop._Driver.current

        @contextlib.contextmanager
        def counted(self):
            pushes[0] += self._current() != self.context.value
            pushes[1] += 1
            with current(self):
                yield

        interop._Driver.current = counted
        if ready.cameras:
            hi.render_sequence(ready.scene, ready.cameras[:8], spp=1, layers=False, budget_ms=0.5 * ready.all_candidates_trace_ms)
        else:
            for seed in range(8):
                hi.render(ready.scene, spp=1, seed=seed, layers=False)
        interop._Driver.current = current
        print(f"    the new driver pushed its context in {pushes[0]} of {pushes[1]} groups of calls", flush=True)


if __name__ == "__main__":
    main()
