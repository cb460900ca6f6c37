"""What a ray-tracing call costs: a fixed part plus a part linear in the pixels it traces (issue 10).

On the many-object scene (loaded as the renderer loads it: meshes batched by material,
``objects.py``), the camera rays' primary hits are computed once; then ``trace.trace_effects``
(the shadow, reflection and refraction paths of the selected pixels, with the device-side
compaction of ``selection.compact``, glass pixels first on CUDA) is frozen as the frame's device
pass is (``frozen.py``: the scene's variables, taken once, in the scene's place; the hits as flat
handles of their variables and their shape pointers as ids, since the device pass, which computes
its hits itself, walks neither), and called for N = 1, 10, 100 … pixels and for every hit pixel.
Per N: the median wall time of a call with the backend synchronized once (Dr.Jit's kernel history
off), and the device time of its kernels (a second call with the history on: CUDA events on the
GPU), every N (and a call that traces nothing) called in turn, round after round
(``timed_in_turn``; one N after another until stop 57). A least-squares line through (N, time)
gives the fixed part and the cost per pixel, and by wall time also apart for the calls made on a
fast host and on a slow one (the host's speed taken before each call, ``calls_in_turn``: the GPU
machines' CPUs run at two speeds, stop 58); the chart draws both, and beside them a call that
traces no pixel (``no_pixel``: the fixed part measured, not extrapolated). On a GPU a launch lasts
as long as its longest path, while the lanes are too few to fill the GPU: the longest of N paths
grows with ln N (Russian roulette keeps a glass path with probability up to 0.95 per bounce; since
stop 57 0.5 from depth 16 on, the integrator's ``rr_tail_depth``/``rr_tail_prob``, which
``--rr-tail-depth -1`` turns off), and a path's latency depends on its materials (a vertex with a
shadow ray costs several glass bounces; docs/results/gpu/issue10/stop40); so a second fit, c0 + c1
ln N + c2 N, is reported and drawn beside the line (the x axis is logarithmic past 1). Then, for
scale, the replay of a frozen function that does nothing but take the scene (``lambda scene, x: x +
1``), given the scene itself (Dr.Jit walks its objects and its registry), its variables
(``frozen.FrozenScene``'s snapshot), those the trace call's recording reads (its read set, which
the trace call takes) or nothing.

    python scripts/trace_overhead.py -o docs/results/cpu/trace_overhead
    python3 scripts/trace_overhead.py --variant cuda_ad_rgb --resx 1280 --resy 720 -o $OUT/trace_overhead
"""
from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def timed(fn, repeats: int) -> tuple[float, float]:
    """Median wall ms (one synchronization per call) and median device ms of ``fn()``."""
    return timed_in_turn([fn], repeats)[0]


def timed_in_turn(fns, repeats: int) -> list[tuple[float, float]]:
    """:func:`timed` of each of ``fns``, called in turn ``repeats`` times (so that a drift of the
    host's speed reaches all of them alike): the medians of :func:`calls_in_turn`."""
    return [(statistics.median(c["wall_ms"]), statistics.median(c["device_ms"])) for c in calls_in_turn(fns, repeats)]


def calls_in_turn(fns, repeats: int) -> list[dict]:
    """Each of ``fns`` called in turn ``repeats`` times; per function, each call's ``wall_ms``,
    ``device_ms`` and ``host_loop_ms``. Each turn calls a function twice: once with Dr.Jit's
    kernel history off, timed on the host's clock (wall), after the host's speed is taken
    (``bench.host_loop_ms``, outside the time: the GPU machines' CPUs run at two speeds,
    docs/results/gpu/issue10/stop58), and once with the history on, for the device time of its
    kernels (the history's CUDA events, two per launch, cost host time of their own: the 1-pixel
    trace call's wall 0.254 ms without them, 0.279 with, docs/results/gpu/issue10/stop39)."""
    import drjit as dr

    from hybrid_integrator.bench import host_loop_ms

    for fn in fns:
        fn()  # compiles or records
        fn()  # a frozen function may record again with its literals made opaque
    calls = [{"wall_ms": [], "device_ms": [], "host_loop_ms": []} for _ in fns]
    for _ in range(repeats):
        for fn, out in zip(fns, calls):
            dr.sync_thread()
            out["host_loop_ms"].append(host_loop_ms())
            start = time.perf_counter()
            dr.eval(fn())
            dr.sync_thread()
            out["wall_ms"].append((time.perf_counter() - start) * 1e3)
            with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
                dr.kernel_history_clear()
                dr.eval(fn())
                dr.sync_thread()
                out["device_ms"].append(sum(float(e.get("execution_time", 0.0)) for e in dr.kernel_history()))
    return calls


def by_host(calls: list[dict]) -> list[dict]:
    """Per function of :func:`calls_in_turn`, the median wall ms of its calls on a fast host (the
    loop before them within ``bench.FAST_HOST`` × the fastest of all) and on a slow one (None:
    no such call), with the share of fast calls."""
    from hybrid_integrator.bench import fast_hosts

    out = []
    for c, on_fast in zip(calls, fast_hosts([c["host_loop_ms"] for c in calls])[0]):
        fast = [w for w, f in zip(c["wall_ms"], on_fast) if f]
        slow = [w for w, f in zip(c["wall_ms"], on_fast) if not f]
        out.append({"wall_ms_fast_host": statistics.median(fast) if fast else None,
                    "wall_ms_slow_host": statistics.median(slow) if slow else None,
                    "fast_share": len(fast) / len(c["wall_ms"])})
    return out


def launches(fn, repeats: int) -> list[dict]:
    """The launches of one call of ``fn()`` (Dr.Jit's kernel history, in order): their kind,
    lanes and median device ms over ``repeats`` calls."""
    import drjit as dr

    runs = []
    with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
        for _ in range(repeats):
            dr.sync_thread()
            dr.kernel_history_clear()
            dr.eval(fn())
            dr.sync_thread()
            runs.append([(str(e["type"]).split(".")[-1], int(e.get("size", 0)), float(e.get("execution_time", 0.0)))
                         for e in dr.kernel_history()])
    return [{"type": kind, "lanes": lanes, "ms": statistics.median(r[k][2] for r in runs)}
            for k, (kind, lanes, _) in enumerate(runs[-1])]


class TraceCall:
    """The trace call this script times, on a loaded scene: the camera rays' primary hits (computed
    once), ``order`` (the hit pixels' indices), and ``frozen``, ``trace.trace_effects`` frozen as
    the frame's device pass is (module docstring), called by :meth:`__call__` for a mask of the
    pixels to trace."""

    def __init__(self, scene, resx: int, resy: int, max_depth: int, roulette=None):
        import drjit as dr
        import mitsuba as mi
        import numpy as np

        import hybrid_integrator as hi
        from hybrid_integrator.api import rasterizer
        from hybrid_integrator.frozen import FrozenScene, variable_handles
        from hybrid_integrator.primary import camera_rays, traced_hits
        from hybrid_integrator.selection import long_paths, refracts
        from hybrid_integrator.trace import RouletteCap, trace_effects

        self.n_objects = n_objects = len(hi.scene_objects(scene))
        # Russian roulette's cap (trace.RouletteCap; None: the integrator's default)
        self.roulette = roulette = roulette or RouletteCap()
        hits = traced_hits(scene, camera_rays(scene.sensors()[0], resx, resy, (0.5, 0.5)), rasterizer(scene).tables)
        dr.eval(hits.ray, hits.si, hits.valid, hits.object)
        self.hits, self.order = hits, np.nonzero(np.array(hits.valid))[0]
        effects = ("shadow", "reflection", "refraction")
        # the hits as flat handles of their variables, as frozen.FrozenScene passes the scene's: the
        # replay walks a SurfaceInteraction3f's nested arrays at about twice the cost per variable of a
        # flat tuple (docs/results/gpu/issue10/stop39: the 52 variables 0.052 ms), a walk the frame's
        # device pass, whose hits are its own intermediates, never makes; the pointer fields travel
        # as ids (a pointer array among a frozen function's inputs makes Dr.Jit 1.5 walk every
        # registered instance of its class on each call: frozen.py)
        pointers = ("shape", "instance")
        types = {k: type(getattr(hits.si, k)) for k in mi.SurfaceInteraction3f.DRJIT_STRUCT if k not in pointers}
        self.hit_handles = variable_handles(dr.detail.collect_indices((hits.ray, {k: getattr(hits.si, k) for k in types})))
        self.ids = [dr.reinterpret_array(mi.UInt32, getattr(hits.si, k)) for k in pointers]
        # glass first, as the device pass launches its traced pixels on CUDA where a candidate is glass
        # (pipeline.PassStatic.long_first; every object is a candidate here)
        glass_first = refracts(shape.bsdf() for shape in scene.shapes()) and mi.variant().startswith("cuda")
        self.long = long_paths(hits.si.bsdf(hits.ray).flags()) if glass_first else None
        dr.eval(self.long)

        def call(scene, hit_handles, ids, traced, obj, seed, long):
            ray, fields = dr.detail.update_indices((dr.zeros(mi.Ray3f), {k: dr.zeros(t) for k, t in types.items()}),
                                                   [h.index for h in hit_handles])
            si = mi.SurfaceInteraction3f()
            for k, v in [*fields.items(), *((k, dr.reinterpret_array(mi.ShapePtr, i)) for k, i in zip(pointers, ids))]:
                setattr(si, k, v)
            rt, _, counts = trace_effects(scene, ray, si, traced, effects, max_depth, 5, False, seed=seed, obj=obj,
                                          n_objects=n_objects, long=long, roulette=roulette)
            return rt, counts.per_object

        self.frozen = FrozenScene(scene).freeze(call)  # as the device pass is frozen (frozen.py)
        self.seed = dr.opaque(mi.UInt64, 1)

    def mask(self, pixels):
        """A call's argument tracing ``pixels`` (indices; none: a call that traces nothing), an
        evaluated array as every call's: a literal (``dr.zeros``) would be baked into a recording
        of its own, whose kernels know what is traced."""
        import drjit as dr
        import mitsuba as mi
        import numpy as np

        chosen = np.zeros(dr.width(self.hits.valid), dtype=bool)
        chosen[pixels] = True
        mask = mi.Bool(chosen)
        dr.eval(mask)
        return mask

    def __call__(self, traced):
        """One call tracing the pixels of ``traced`` (a ``mi.Bool`` per pixel: :meth:`mask`)."""
        return self.frozen(self.hit_handles, self.ids, traced, self.hits.object, self.seed, self.long)


def add_arguments(parser, repeats: int = 41) -> None:
    """The options of a run of :class:`TraceCall`: variant, resolution, repeats, max_depth."""
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--resx", type=int, default=320)
    parser.add_argument("--resy", type=int, default=180)
    parser.add_argument("--repeats", type=int, default=repeats)
    parser.add_argument("--max-depth", type=int, default=-1,
                        help="the paths' max_depth (default -1: unlimited, the integrator's default; "
                             "many_objects.xml's own integrator says 6)")
    parser.add_argument("--rr-tail-depth", type=int, default=None,
                        help="the integrator's rr_tail_depth (default: its default; -1: path's roulette)")
    parser.add_argument("--rr-tail-prob", type=float, default=None, help="the integrator's rr_tail_prob (default: its default)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_arguments(parser)
    parser.add_argument("--scene", type=Path, default=ROOT / "scenes/many_objects.xml")
    parser.add_argument("--launches", action="store_true",
                        help="also print each launch's device time per number of pixels (what grows with it)")
    parser.add_argument("-o", "--output", type=Path, required=True)
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi
    import numpy as np

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.pipeline import HybridSettings
    from hybrid_integrator.raster.context import machine

    scene = hi.load_scene(args.scene, resx=args.resx, resy=args.resy)
    # the integrator's roulette, with the options given (checked as its properties are)
    roulette = HybridSettings(**{k: v for k, v in (("rr_tail_depth", args.rr_tail_depth),
                                                   ("rr_tail_prob", args.rr_tail_prob)) if v is not None}).roulette
    trace = TraceCall(scene, args.resx, args.resy, args.max_depth, roulette)
    n_objects, order, frozen = trace.n_objects, trace.order, trace.frozen
    counts = [n for n in (1, 10, 100, 1000, 10000, 100000) if n < len(order)] + [len(order)]
    masks = {n: trace.mask(order[:n]) for n in counts}
    # a call that traces no pixel: the fixed part itself (the replay, every launch, the path loop's
    # launch over lanes that all stop at once), measured rather than extrapolated
    nothing = trace.mask([])
    for sweep in ("warm-up", "measured"):  # the first sweep lets clocks and caches settle
        # every N and the call that traces nothing in turn, round after round: a drift of the host's
        # speed, which moved the wall-time line's intercept by 0.1 ms between two runs of the rows
        # one after another (docs/results/gpu/issue10/stop57), reaches every row alike
        calls = calls_in_turn([lambda n=n: trace(masks[n]) for n in counts] + [lambda: trace(nothing)], args.repeats)
        times = [{"wall_ms": statistics.median(c["wall_ms"]), "device_ms": statistics.median(c["device_ms"]),
                  "host_loop_ms": statistics.median(c["host_loop_ms"])} | h for c, h in zip(calls, by_host(calls))]
        rows = [{"pixels": n} | t for n, t in zip(counts, times)]
        empty = times[-1]
        print(sweep, rows, "no pixel:", empty, flush=True)
    if args.launches:
        for row in rows:
            row["launches"] = launches(lambda: trace(masks[row["pixels"]]), args.repeats)
            print(row["pixels"], "pixels:", ", ".join(f"{e['type']}[{e['lanes']}] {e['ms']:.3f}" for e in row["launches"]),
                  flush=True)
    x = np.array([r["pixels"] for r in rows], dtype=np.float64)
    fits, log_fits = {}, {}
    for key in ("wall_ms", "device_ms"):
        y = [r[key] for r in rows]
        slope, intercept = np.polyfit(x, y, 1)
        fits[key] = {"fixed_ms": float(intercept), "ms_per_1000_pixels": float(slope * 1e3)}
        c0, c1, c2 = np.linalg.lstsq(np.c_[np.ones_like(x), np.log(x), x], y, rcond=None)[0]
        log_fits[key] = {"fixed_ms": float(c0), "ms_per_ln_pixels": float(c1), "ms_per_1000_pixels": float(c2 * 1e3)}
    for key in ("wall_ms_fast_host", "wall_ms_slow_host"):  # the wall-time line apart by the host's speed
        if all(r[key] is not None for r in rows):
            slope, intercept = np.polyfit(x, [r[key] for r in rows], 1)
            fits[key] = {"fixed_ms": float(intercept), "ms_per_1000_pixels": float(slope * 1e3)}
    x1 = dr.arange(mi.Float, 10)
    with_scene, given, without = dr.freeze(lambda scene, x: x + 1), dr.freeze(lambda variables, x: x + 1), dr.freeze(lambda x: x + 1)
    snapshot = frozen.owner.variables.handles
    replay = {"with_scene_ms": timed(lambda: with_scene(scene, x1), args.repeats)[0],
              "with_scene_variables_ms": timed(lambda: given(snapshot, x1), args.repeats)[0],
              "with_read_set_ms": timed(lambda: given(frozen.read or (), x1), args.repeats)[0],
              "without_scene_ms": timed(lambda: without(x1), args.repeats)[0]}
    report = {"command": f"python scripts/trace_overhead.py --variant {args.variant} --resx {args.resx} --resy {args.resy} "
                         f"--repeats {args.repeats} --max-depth {args.max_depth} --rr-tail-depth {roulette.tail_depth} "
                         f"--rr-tail-prob {roulette.tail_prob}",
              "machine": machine(), "objects": n_objects, "shapes": len(scene.shapes()),
              "resolution": [args.resx, args.resy], "max_depth": args.max_depth, "roulette": roulette._asdict(), "glass_first": trace.long is not None, "no_pixel": empty, "rows": rows, "fit": fits, "fit_with_log_term": log_fits, "frozen_replay": replay,
              "scene_inputs": {"passed": frozen.inputs, "snapshot": len(snapshot),
                               "read_set": None if frozen.read is None else len(frozen.read),
                               "missed": frozen.missed}}
    args.output.parent.mkdir(parents=True, exist_ok=True)
    args.output.with_suffix(".json").write_text(json.dumps(report, indent=2))
    _chart(args.output.with_suffix(".png"), rows, fits, log_fits, report)
    print(json.dumps({k: report[k] for k in ("no_pixel", "fit", "fit_with_log_term", "frozen_replay", "scene_inputs", "objects", "shapes")}, indent=2))


def _chart(path: Path, rows: list[dict], fits: dict, log_fits: dict, report: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    x = np.array([r["pixels"] for r in rows], dtype=np.float64)
    fig, ax = plt.subplots(figsize=(6.5, 4))
    for key, label in (("wall_ms", "wall, one sync per call"), ("device_ms", "device (kernel history)")):
        line = ax.plot(x, [r[key] for r in rows], "o", label=label)[0]
        ax.plot([0.0], [report["no_pixel"][key]], "s", color=line.get_color(), mfc="none",
                label=f"no pixel: {report['no_pixel'][key]:.3f} ms")
        fit = fits[key]
        xs = np.r_[0.0, np.geomspace(1, x.max(), 100)]
        ax.plot(xs, fit["fixed_ms"] + fit["ms_per_1000_pixels"] * xs / 1e3, "-", color=line.get_color(), alpha=0.6,
                label=f"fit: {fit['fixed_ms']:.3f} ms + {fit['ms_per_1000_pixels']:.4f} ms / 1000 px")
        log_fit, xl = log_fits[key], np.geomspace(1, x.max(), 100)
        ax.plot(xl, log_fit["fixed_ms"] + log_fit["ms_per_ln_pixels"] * np.log(xl) + log_fit["ms_per_1000_pixels"] * xl / 1e3,
                ":", color=line.get_color(), alpha=0.8,
                label=f"{log_fit['fixed_ms']:.3f} + {log_fit['ms_per_ln_pixels']:.3f} ln N + "
                      f"{log_fit['ms_per_1000_pixels']:.4f} ms / 1000 px")
    for key, style in (("wall_ms_fast_host", "--"), ("wall_ms_slow_host", "-.")):  # the wall line by the host's speed
        if key in fits:
            fit, xs = fits[key], np.r_[0.0, np.geomspace(1, x.max(), 100)]
            ax.plot(xs, fit["fixed_ms"] + fit["ms_per_1000_pixels"] * xs / 1e3, style, color="grey", alpha=0.8,
                    label=f"wall, {key.split('_')[2]} host: {fit['fixed_ms']:.3f} ms + {fit['ms_per_1000_pixels']:.4f} ms / 1000 px")
    ax.set_xscale("symlog", linthresh=1)
    ax.set_xlabel("traced pixels N")
    ax.set_ylabel("ms per trace call")
    ax.set_title(f"trace call on {report['objects']} objects ({report['shapes']} shapes), max_depth "
                 f"{report['max_depth']}, roulette {report['roulette']}, {report['machine']['variant']}", fontsize=9)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


if __name__ == "__main__":
    main()
