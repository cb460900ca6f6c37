"""The ``hybrid`` command line.

    hybrid gbuffer SCENE.xml -o gbuffer.exr [--aovs all] [-D resx=1280 -D resy=720]

Errors the package raises on purpose are printed as one line, ``hybrid: error: ...``, with exit
status 2; anything else is a bug and keeps its traceback.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

DEFAULT_VARIANT = "llvm_ad_rgb"


def _define(text: str) -> tuple[str, str]:
    if "=" not in text:
        raise argparse.ArgumentTypeError(f"expected NAME=VALUE, got '{text}'")
    name, value = text.split("=", 1)
    return name, value


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="hybrid", description="Hybrid rasterized + ray-traced rendering on Mitsuba 3.")
    sub = parser.add_subparsers(dest="command", required=True)

    gbuffer = sub.add_parser("gbuffer", help="rasterize a scene's visibility buffer / G-buffer into a multi-layer EXR")
    gbuffer.add_argument("scene", type=Path, help="Mitsuba scene XML")
    gbuffer.add_argument("-o", "--output", type=Path, default=Path("gbuffer.exr"), help="EXR to write (a PNG contact sheet is written beside it)")
    gbuffer.add_argument("--aovs", nargs="*", default=["all"], help="G-buffer targets: position normal albedo specular optical, or all (default)")
    gbuffer.add_argument("--offset", nargs=2, type=float, default=(0.5, 0.5), metavar=("X", "Y"), help="sub-pixel sample position in [0,1)")
    gbuffer.add_argument("--sensor", type=int, default=0, help="index of the scene's sensor")
    for p in (gbuffer,):
        p.add_argument("-D", dest="defines", action="append", type=_define, default=[], metavar="NAME=VALUE",
                       help="scene parameter ($NAME in the XML), as in Mitsuba's own command line")
        p.add_argument("--variant", default=DEFAULT_VARIANT, help=f"Mitsuba variant (default {DEFAULT_VARIANT})")
    return parser


def _gbuffer(args) -> dict:
    import hybrid_integrator as hi
    from hybrid_integrator.io import contact_sheet, write_gbuffer
    from hybrid_integrator.scene import load_scene

    scene = load_scene(args.scene, **dict(args.defines))
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


def main(argv: list[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    import mitsuba as mi

    from hybrid_integrator.environment import pin_llvm
    from hybrid_integrator.errors import HybridError

    pin_llvm()
    try:
        try:
            mi.set_variant(args.variant)
        except (AttributeError, ImportError, ValueError) as exc:
            raise HybridError(f"Mitsuba variant '{args.variant}' is not available: {exc}") from exc
        report = {"gbuffer": _gbuffer}[args.command](args)
    except HybridError as exc:
        print(f"hybrid: error: {exc}", file=sys.stderr)
        return 2
    print(json.dumps(report, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
