"""The ``hybrid`` command line.

    hybrid gbuffer SCENE.xml -o gbuffer.exr [--aovs all]
    hybrid render  SCENE.xml -o out.exr [--spp N] [--primary raytrace] [--effects ...]
    hybrid compare SCENE.xml [-o out/compare] [--spp N] [--gt-spp N]
    hybrid bench   SCENE.xml [SCENE.xml | procedural:TRIANGLES ...] [-o out/bench] [--frames N]
    hybrid bench   SCENE.xml ... --ray [ADDRESS]       (scenes as Ray tasks, one GPU each with cuda_ad_rgb)
    hybrid bench   --scaling triangles --values 10000 100000 ... | --scaling resolution --values 640x360 ...
    hybrid sequence SCENE.xml --camera-path '[[[0,0,4],[0,0,0]],[[1,0,3],[0,0,0]]]' --frames 60 -o DIR [--workers N]

Every command takes ``-D name=value`` (the scene's ``$name`` parameters, as Mitsuba's own command
line) and ``--variant``. Errors the package raises on purpose are printed as one line,
``hybrid: error: ...``, with exit status 2; anything else is a bug and keeps its traceback.
"""
from __future__ import annotations

import argparse
import json
import shlex
import sys
import time
from pathlib import Path

DEFAULT_VARIANT = "llvm_ad_rgb"


def _define(text: str) -> tuple[str, str]:
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got '{text}'")
    name, value = text.split("=", 1)
    return name, value


def typed_property(text: str) -> tuple[str, object]:
    """``NAME=VALUE`` as an integrator property (the probes' ``--property``): the value a boolean,
    an integer, a float or the text itself, as Mitsuba's typed properties take it."""
    name, value = _define(text)
    if value.lower() in ("true", "false"):
        return name, value.lower() == "true"
    for kind in (int, float):
        try:
            return name, kind(value)
        except ValueError:
            pass
    return name, value


def _integrator_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("hybrid integrator properties (default: the integrator's own)")
    g.add_argument("--primary", choices=("raster", "raytrace"), help="where primary hits come from")
    g.add_argument("--raster", choices=("auto", "draw", "compute"),
                   help="how the raster pass rasterizes: OpenGL's draw or compute shaders (default: auto, compute on CUDA)")
    g.add_argument("--refine", choices=("auto", "primary", "trace"),
                   help="where the raster's refined pixels (silhouettes, proxies, misses) are traced "
                        "(default: auto, the trace stage's launch on CUDA)")
    g.add_argument("--outline", choices=("auto", "ties", "silhouettes"),
                   help="which outline pixels of the raster are re-traced: where its answer may differ from the "
                        "ray's (ties) or every pixel next to another object (silhouettes); default: auto, ties "
                        "with the compute raster pass")
    g.add_argument("--effects", help="comma list of shadow, reflection, refraction, indirect")
    g.add_argument("--candidates", help="comma list of shape ids to ray trace ('' for none)")
    g.add_argument("--blend", type=float, help="composition weight of the ray-traced layer, in [0, 1]")
    g.add_argument("--max-depth", dest="max_depth", type=int, help="as Mitsuba's path (-1: unlimited)")
    g.add_argument("--rr-depth", dest="rr_depth", type=int, help="as Mitsuba's path: the depth where Russian roulette starts")
    g.add_argument("--rr-tail-depth", dest="rr_tail_depth", type=int,
                   help="from this depth on, Russian roulette continues a path with probability at most "
                        "--rr-tail-prob (default: 16 in a denoised frame, -1 without the denoiser; -1: never, as path)")
    g.add_argument("--rr-tail-prob", dest="rr_tail_prob", type=float, help="that probability (default 0.5)")
    g.add_argument("--secondary-spp", dest="secondary_spp", type=int,
                   help="paths traced from each traced pixel's primary hit, in one launch (default: 1)")
    g.add_argument("--budget-ms", dest="budget_ms", type=float, help="frame-time budget for ray tracing (0: unlimited)")
    g.add_argument("--hide-emitters", dest="hide_emitters", action="store_true", default=None)
    g.add_argument("--denoise", action=argparse.BooleanOptionalAction, default=None,
                   help="Open Image Denoise with the G-buffer's albedo and normal (default: on)")
    g.add_argument("--denoise-quality", dest="denoise_quality", choices=("fast", "balanced", "high"))
    g.add_argument("--learn-ambient", dest="learn_ambient", action=argparse.BooleanOptionalAction, default=None,
                   help="add each object's ambient light learnt from its traced pixels to the raster layer (default: on)")
    g.add_argument("--shadow-tier", dest="shadow_tier", action=argparse.BooleanOptionalAction, default=None,
                   help="with a budget, diffuse objects may be traced by their shadow rays alone (default: on)")
    g.add_argument("--partial-objects", dest="partial_objects", action=argparse.BooleanOptionalAction, default=None,
                   help="with a budget, what the selection leaves buys a part of one more object's pixels "
                        "(default: on)")
    g.add_argument("--raster-ahead", dest="raster_ahead", choices=("auto", "on", "off"),
                   help="a still camera's frame draws the next frame's visibility buffer at its end, run by OpenGL "
                        "once the frame's CUDA work is done (default: auto, on with CUDA-OpenGL interop)")
    g.add_argument("--stage-times", dest="stage_times", action=argparse.BooleanOptionalAction, default=None,
                   help="time each stage on the device from Dr.Jit's kernel history (default: on; off, a frame "
                        "reports only its total, gl and denoise times, and is shorter; a budgeted one is timed "
                        "every --timing-interval frames)")
    g.add_argument("--timing-interval", dest="timing_interval", type=int,
                   help="with a budget and --no-stage-times, time every N-th frame's trace (default: 4)")


def _properties(args) -> dict:
    names = ("primary", "raster", "refine", "outline", "effects", "candidates", "blend", "max_depth", "rr_depth", "rr_tail_depth", "rr_tail_prob", "secondary_spp", "budget_ms", "hide_emitters", "denoise",
             "denoise_quality", "learn_ambient", "shadow_tier", "partial_objects", "raster_ahead", "stage_times", "timing_interval")
    return {n: getattr(args, n) for n in names if getattr(args, n, None) is not None}


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="hybrid", description="Hybrid rasterized + ray-traced rendering on Mitsuba 3.")
    sub = parser.add_subparsers(dest="command", required=True)

    gbuffer = sub.add_parser("gbuffer", help="rasterize a scene's visibility buffer / G-buffer into a multi-layer EXR")
    gbuffer.add_argument("-o", "--output", type=Path, default=Path("gbuffer.exr"), help="EXR to write (a PNG contact sheet is written beside it)")
    gbuffer.add_argument("--aovs", nargs="*", default=["all"], help="G-buffer targets: position normal albedo specular optical emission, or all (default)")
    gbuffer.add_argument("--offset", nargs=2, type=float, default=(0.5, 0.5), metavar=("X", "Y"), help="sub-pixel sample position in [0,1)")

    render = sub.add_parser("render", help="render a hybrid frame: EXR (image + layers), PNG preview, stats JSON")
    render.add_argument("-o", "--output", type=Path, default=Path("render.exr"))
    render.add_argument("--spp", type=int, default=0, help="samples per pixel (default: the scene's sampler)")
    render.add_argument("--seed", type=int, default=0)
    _integrator_options(render)

    compare = sub.add_parser("compare", help="hybrid vs pure ray tracing vs ground truth: time and error table")
    compare.add_argument("-o", "--output", type=Path, default=Path("out/compare"), help="folder for images and report")
    compare.add_argument("--spp", type=int, default=1, help="samples per pixel of every method (default 1: one real-time frame)")
    compare.add_argument("--gt-spp", dest="gt_spp", type=int, default=512, help="samples per pixel of the ground truth")
    compare.add_argument("--seed", type=int, default=0)
    _integrator_options(compare)

    bench = sub.add_parser("bench", help="the paper's Tables 3 and 4 with accuracy: time and error per method, "
                                         "charts, scaling curves (bench.py)")
    bench.add_argument("scenes", nargs="*", help="scene XMLs, or procedural:TRIANGLES")
    bench.add_argument("-o", "--output", type=Path, default=Path("out/bench"),
                       help="folder for the JSON, tables and charts (with --scaling: the file stem)")
    bench.add_argument("--frames", type=int, default=5, help="measured frames per method (medians)")
    bench.add_argument("--spp", type=int, default=1, help="samples per pixel of each hybrid frame")
    bench.add_argument("--gt-spp", dest="gt_spp", type=int, default=1024, help="samples per pixel of the ground truth")
    bench.add_argument("--max-path-spp", dest="max_path_spp", type=int, default=64, help="path's curve: 1, 2, 4 … this")
    bench.add_argument("--budgets", nargs="*", type=float, default=[0.0, 0.25, 0.5, 0.75],
                       help="budgets as fractions of the all-candidates trace time")
    bench.add_argument("--freeze", action=argparse.BooleanOptionalAction, default=True,
                       help="replay the device pass's recorded kernels (the integrator's freeze property)")
    bench.add_argument("--accuracy", action=argparse.BooleanOptionalAction, default=True,
                       help="measure every image against a ground truth (off: times only, no ground truth rendered)")
    bench.add_argument("--scaling", choices=("triangles", "resolution"), help="time against triangles or resolution")
    bench.add_argument("--values", nargs="*", default=[], help="triangle counts, or WxH resolutions, for --scaling")
    bench.add_argument("--ray", nargs="?", const="auto", default=None, metavar="ADDRESS",
                       help="run the scenes (or scaling points) as Ray tasks: a local Ray instance, or a cluster's "
                            "ADDRESS; ground truths are shared through the disk cache ($HYBRID_CACHE)")
    bench.add_argument("--gpus-per-worker", dest="gpus_per_worker", type=float, default=None,
                       help="GPUs per Ray task (default: 1 with a CUDA variant, else 0: one CPU each)")
    bench.add_argument("--single", type=Path, help=argparse.SUPPRESS)  # child process: one scene, JSON here
    bench.add_argument("--scaling-point", dest="scaling_point", action="store_true", help=argparse.SUPPRESS)
    _integrator_options(bench)
    bench.add_argument("-D", dest="defines", action="append", type=_define, default=[], metavar="NAME=VALUE",
                       help="scene parameter ($NAME in the XML), e.g. -D sponza_dir=/data/sponza")
    bench.add_argument("--variant", default=DEFAULT_VARIANT, help=f"Mitsuba variant (default {DEFAULT_VARIANT})")

    sequence = sub.add_parser("sequence", help="a camera path to disk (EXR, PNG, stats JSON per frame, preview GIF), "
                                               "resumable, in this process or on Ray workers (frames.py)")
    sequence.add_argument("-o", "--output", type=Path, default=Path("out/sequence"), help="folder for the frames")
    sequence.add_argument("--camera-path", dest="camera_path", required=True,
                          help='key frames as JSON [[origin, target], ...] or [[origin, target, up], ...], or a .json file')
    sequence.add_argument("--frames", type=int, default=60, help="frames along the path")
    sequence.add_argument("--spp", type=int, default=1)
    sequence.add_argument("--seed", type=int, default=0, help="frame k uses seed + k")
    sequence.add_argument("--workers", type=int, default=1, help="Ray workers (1: this process, no Ray)")
    sequence.add_argument("--ray", dest="ray_address", default=None, metavar="ADDRESS",
                          help="a Ray cluster's address (default: start a local one)")
    sequence.add_argument("--gpus-per-worker", dest="gpus_per_worker", type=float, default=0.0,
                          help="GPUs per Ray worker (1 with cuda_ad_rgb; 0: CPU workers)")
    _integrator_options(sequence)

    for p in (gbuffer, render, compare, sequence):
        p.add_argument("scene", type=Path, help="Mitsuba scene XML")
        p.add_argument("--sensor", type=int, default=0, help="index of the scene's sensor")
        p.add_argument("-D", dest="defines", action="append", type=_define, default=[], metavar="NAME=VALUE",
                       help="scene parameter ($NAME in the XML), as in Mitsuba's own command line")
        p.add_argument("--variant", default=DEFAULT_VARIANT, help=f"Mitsuba variant (default {DEFAULT_VARIANT})")
    return parser


def _sequence(args) -> dict:
    import hybrid_integrator as hi
    from hybrid_integrator.errors import HybridError
    from hybrid_integrator.frames import render_frames

    text = Path(args.camera_path).read_text() if args.camera_path.endswith(".json") else args.camera_path
    try:
        keys = json.loads(text)
    except json.JSONDecodeError as exc:
        raise HybridError(f"--camera-path is not JSON key frames [[origin, target], ...]: {exc}") from exc
    if not args.scene.is_file():
        raise HybridError(f"scene file not found: {args.scene}")
    return render_frames(args.scene.resolve(), hi.camera_path(keys, args.frames), args.output, spp=args.spp,
                         seed=args.seed, workers=args.workers, params=dict(args.defines), ray_address=args.ray_address,
                         gpus_per_worker=args.gpus_per_worker, **_properties(args))


def _gbuffer(args) -> dict:
    import hybrid_integrator as hi
    from hybrid_integrator.io import contact_sheet, write_gbuffer

    scene = hi.load_scene(args.scene, **dict(args.defines))
    hi.rasterize(scene, sensor=args.sensor, offset=tuple(args.offset))  # uploads geometry, compiles shaders
    start = time.perf_counter()
    vis = hi.rasterize(scene, sensor=args.sensor, offset=tuple(args.offset))
    raster_ms = (time.perf_counter() - start) * 1e3
    gb = hi.rasterize(scene, sensor=args.sensor, offset=tuple(args.offset), aovs=args.aovs)
    exr = write_gbuffer(args.output, gb)
    png = contact_sheet(args.output.with_suffix(".png"), gb)
    h, w = vis.depth.shape
    return {"exr": str(exr), "contact_sheet": str(png), "width": w, "height": h, "raster_ms": round(raster_ms, 3),
            "hit_pixels": int(vis.hit.sum()), "proxy_pixels": int(vis.proxy.sum()), "shapes": len(gb.shape_ids)}


def _render(args) -> dict:
    import hybrid_integrator as hi
    from hybrid_integrator.io import write_result

    scene = hi.load_scene(args.scene, **dict(args.defines))
    result = hi.render(scene, spp=args.spp, seed=args.seed, sensor=args.sensor, **_properties(args))
    return write_result(args.output, result)


def _compare(args) -> dict:
    from hybrid_integrator.compare import compare, table

    report = compare(args.scene, dict(args.defines), spp=args.spp, gt_spp=args.gt_spp, seed=args.seed,
                     out_dir=args.output, **_properties(args))
    print(table(report), file=sys.stderr)
    return {"report": str(args.output / "compare.json"), "table": str(args.output / "compare.md"),
            "errors": str(args.output / "errors.png")}


def _bench_options(args) -> list[str]:
    """The options a child process of ``hybrid bench`` gets (one scene each: bench.py)."""
    options = ["--variant", args.variant, "--frames", str(args.frames), "--spp", str(args.spp),
               "--gt-spp", str(args.gt_spp), "--max-path-spp", str(args.max_path_spp),
               "--budgets", *map(str, args.budgets), "--freeze" if args.freeze else "--no-freeze",
               "--accuracy" if args.accuracy else "--no-accuracy"]
    for name, value in _properties(args).items():
        flag = "--" + name.replace("_", "-")
        if isinstance(value, bool):  # a boolean option takes no value: --flag or --no-flag
            options.append(flag if value else "--no-" + flag[2:])
        else:
            options += [flag, str(value)]
    for name, value in args.defines:
        options += ["-D", f"{name}={value}"]
    return options


def _bench(args) -> dict:
    from hybrid_integrator import bench
    from hybrid_integrator.errors import HybridError

    command = "hybrid bench " + shlex.join(args.argv)
    gpus = args.gpus_per_worker if args.gpus_per_worker is not None else float(args.variant.startswith("cuda"))
    workers = bench.Workers(ray=args.ray, gpus=gpus)
    if args.single is not None:  # a child process: measure one scene
        if len(args.scenes) != 1:
            raise HybridError("bench --single takes one scene")
        budgets = () if args.scaling_point else args.budgets
        report = bench.bench_scene(args.scenes[0], dict(args.defines), frames=args.frames, spp=args.spp,
                                   gt_spp=args.gt_spp, max_path_spp=args.max_path_spp, budgets=budgets,
                                   freeze=args.freeze, accuracy=args.accuracy and not args.scaling_point,
                                   **_properties(args))
        args.single.write_text(json.dumps(report, indent=2))
        return {"report": str(args.single)}
    if args.scaling:
        if not args.values:
            raise HybridError("bench --scaling needs --values (triangle counts, or WxH resolutions)")
        points = bench.scaling(args.scaling, args.values, args.output, _bench_options(args), command, workers)
        return {"json": str(args.output.with_suffix(".json")), "points": len(points)}
    if not args.scenes:
        raise HybridError("bench: give at least one scene (an XML, or procedural:TRIANGLES)")
    args.output.mkdir(parents=True, exist_ok=True)
    reports = bench.run(args.scenes, args.output, _bench_options(args), command, workers)
    print(bench.tables(reports, [command]), file=sys.stderr)
    return {"json": str(args.output / "bench.json"), "tables": str(args.output / "bench.md"),
            "charts": [str(args.output / f"{r['name']}.png") for r in reports]}


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = _parser().parse_args(argv)
    args.argv = argv[1:]
    import mitsuba as mi

    from hybrid_integrator.environment import pin_llvm
    from hybrid_integrator.errors import HybridError

    pin_llvm()
    try:
        try:
            mi.set_variant(args.variant)
        except (AttributeError, ImportError, ValueError) as exc:
            raise HybridError(f"Mitsuba variant '{args.variant}' is not available: {exc}") from exc
        import hybrid_integrator as hi

        hi.register()
        report = {"gbuffer": _gbuffer, "render": _render, "compare": _compare, "bench": _bench,
                  "sequence": _sequence}[args.command](args)
    except HybridError as exc:
        print(f"hybrid: error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:  # an output that cannot be written, a scene path that is a directory, ...
        print(f"hybrid: error: {exc.strerror or exc}: {exc.filename or ''}".rstrip(": "), file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("hybrid: interrupted (no output was left half-written)", file=sys.stderr)
        return 130
    print(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
