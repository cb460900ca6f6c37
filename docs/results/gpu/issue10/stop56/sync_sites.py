"""Where a frame's host waits for the device: a long kernel queued ahead of each frame, and the calls that outlast it (issue 10, stop 56).

Stop 56 found that moving the sensor (Mitsuba's ``params.update()``) waited for all the device's
queued work, which no stage time showed. This probe looks for such waits in a whole frame: before
each measured frame it queues a kernel of about ``--busy`` ms on Dr.Jit's stream, then renders the
frame under ``cProfile``; a call that waits for the device takes about the kernel's time itself
(its ``tottime``: the wait happens inside it, not in what it calls). Per kind of frame (the hybrid
and its RT baseline, one at a time and two in flight, a 50 % budget; a still camera, or the 226
objects' path with ``--path``), it prints each call whose own time per frame was over half the
kernel's. Expected waits: the frame's own counts (``HostCopy.wait`` / ``sync``), the frame before's
span (``FrameSpan.wait``, in flight) and the frame's one synchronization (``sync_thread``, one at a
time). Any other is a wait nobody asked for.

    python3 docs/results/gpu/issue10/stop56/sync_sites.py scenes/many_objects.xml --variant cuda_ad_rgb -D resx=1280 -D resy=720
"""
from __future__ import annotations

import cProfile
import pstats
import time


def main() -> None:
    from hybrid_integrator.bench import turn_arguments

    parser = turn_arguments(__doc__.splitlines()[0], budgets=(0.5,))
    parser.add_argument("--busy", type=float, default=20.0, help="ms of device work queued before each frame")
    parser.add_argument("--path", action="store_true", help="along the scene's camera path")
    parser.add_argument("--top", type=int, default=0, help="print the calls of the N longest own times instead")
    args = parser.parse_args()

    import drjit as dr
    import mitsuba as mi

    mi.set_variant(args.variant)
    import hybrid_integrator as hi
    from hybrid_integrator.api import _integrator, finish, posed
    from hybrid_integrator.bench import turn_scene
    from hybrid_integrator.raster.camera import camera_pose

    hi.register()

    def kernel(loops: int):
        x = dr.arange(mi.Float, 1 << 20)
        i = mi.UInt32(0)
        i, x = dr.while_loop((i, x), lambda i, x: i < loops, lambda i, x: (i + 1, dr.fma(x, 0.999, 1.0)))
        dr.eval(x)
        return x

    def kernel_ms(loops: int) -> float:
        dr.sync_thread()
        start = time.perf_counter()
        kernel(loops)
        dr.sync_thread()
        return (time.perf_counter() - start) * 1e3

    loops = 1000
    kernel_ms(loops)
    while kernel_ms(loops) < args.busy:
        loops *= 2
    busy_ms = kernel_ms(loops)
    for path in args.scenes:
        ready = turn_scene(str(path), dict(args.defines), args.frames + 10)
        kinds = {"hybrid": {}, "RT baseline": {"primary": "raytrace"},
                 "hybrid, 2 in flight": {"frames_in_flight": 2},
                 "RT baseline, 2 in flight": {"primary": "raytrace", "frames_in_flight": 2},
                 **{f"{b:.0%} budget": {"budget_ms": b * ready.all_candidates_trace_ms} for b in args.budgets}}
        print(f"{ready.name}: queued kernel {busy_ms:.2f} ms", flush=True)
        poses = [camera_pose(c) for c in ready.cameras] if args.path and ready.cameras else None
        for kind, props in kinds.items():
            integrator = _integrator(dict(props))
            profile = cProfile.Profile()
            with posed(ready.scene.sensors()[0]) as place:
                for k in range(args.frames + 10):
                    if poses is not None:
                        place(poses[k])
                    nxt = poses[k + 1] if poses is not None and k + 1 < len(poses) else None
                    measured = k >= 10  # the first ten: warm-up and a budget's probes
                    if measured:
                        kernel(loops)
                        profile.enable()
                    integrator.render_result(ready.scene, seed=k, spp=1, layers=False, next_camera=nxt)
                    if measured:
                        profile.disable()
                finish(ready.scene)
            stats = pstats.Stats(profile).stats

            def where(func, callers) -> str:
                """The call, then up to five callers: each the one that spent most time in the last."""
                chain = [func]
                while callers and len(chain) < 6:
                    caller = max(callers.items(), key=lambda c: c[1][3])[0]
                    chain.append(caller)
                    callers = stats[caller][4]
                return " < ".join(f"{f[2]} ({f[0].rsplit('/', 1)[-1]}:{f[1]})" for f in chain)

            waits = sorted(((tt * 1e3 / args.frames, where(func, callers))
                            for func, (cc, nc, tt, ct, callers) in stats.items()
                            if args.top or tt * 1e3 / args.frames > busy_ms / 2), reverse=True)
            waits = waits[:args.top] if args.top else waits
            print(f"  {kind:26s}: " + ("; ".join(f"{name} {ms:.2f} ms" for ms, name in waits) or "none"), flush=True)


if __name__ == "__main__":
    main()
