"""Images in and out: multi-layer OpenEXR files and PNG previews.

EXR channels follow the usual ``layer.channel`` naming (``normal.X``, ``albedo.R``,
``optical.ior``), so that EXR viewers group them into layers; integer buffers are stored as
``UINT`` channels, and the shape ids are written in a string attribute (``shape_ids``) so that a
file can be read without the scene.
"""
from __future__ import annotations

import contextlib
import os

from pathlib import Path

import numpy as np
import OpenEXR

from .raster.gbuffer import AOV_CHANNELS, GBuffer


def gbuffer_channels(gb: GBuffer) -> dict[str, np.ndarray]:
    """The G-buffer's layers as named EXR channels (float32, or uint32 for integer buffers)."""
    channels = {
        "shape_index": gb.shape_index.astype(np.float32),  # -1 for background: exact in float32
        "prim_index": gb.prim_index.astype(np.uint32),
        "bary.u": gb.bary[..., 0],
        "bary.v": gb.bary[..., 1],
        "depth.Z": gb.depth,
        "proxy": gb.proxy.astype(np.uint32),
    }
    for name, image in gb.aovs.items():
        for k, channel in enumerate(AOV_CHANNELS[name]):
            channels[f"{name}.{channel}"] = image[..., k]
    return channels


@contextlib.contextmanager
def atomic_path(path: str | Path):
    """A temporary path beside ``path`` to write to; renamed onto ``path`` only when the block
    ends without an exception (an interrupted render leaves no file that looks complete)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.partial{path.suffix}")
    try:
        yield tmp
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def write_text(path: str | Path, text: str) -> Path:
    """``Path.write_text``, atomically (:func:`atomic_path`)."""
    with atomic_path(path) as tmp:
        tmp.write_text(text)
    return Path(path)


def write_exr(path: str | Path, channels: dict[str, np.ndarray], attributes: dict | None = None) -> Path:
    """Write ``channels`` (name → H×W array) as one multi-channel scanline EXR (ZIP compressed),
    atomically (:func:`atomic_path`). OpenEXR compresses on one thread unless told otherwise; its
    global thread pool is set to the machine's cores here (a 1280×720 frame with its layers: ~0.3 s
    on one thread)."""
    if OpenEXR.global_thread_count() == 0:
        OpenEXR.set_global_thread_count(os.cpu_count() or 1)
    header = {"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage, **(attributes or {})}
    data = {name: np.ascontiguousarray(a) for name, a in channels.items()}
    with atomic_path(path) as tmp, OpenEXR.File(header, data) as f:
        f.write(str(tmp))
    return Path(path)


def read_exr(path: str | Path) -> tuple[dict[str, np.ndarray], dict]:
    """Read an EXR written by :func:`write_exr`: (channels by name, header attributes)."""
    with OpenEXR.File(str(path), separate_channels=True) as f:
        channels = {name: np.array(ch.pixels) for name, ch in f.channels().items()}
        return channels, dict(f.header())


def write_gbuffer(path: str | Path, gb: GBuffer) -> Path:
    return write_exr(path, gbuffer_channels(gb), {"shape_ids": ",".join(gb.shape_ids)})


def contact_sheet(path: str | Path, gb: GBuffer) -> Path:
    """A PNG of every layer of ``gb`` side by side, like the paper's Fig. 1."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    hit = gb.hit
    panels: list[tuple[str, np.ndarray, dict]] = [
        ("shape index", np.where(hit, gb.shape_index, np.nan), {"cmap": "tab20"}),
        ("triangle index", np.where(hit, (gb.prim_index * 2654435761 % 4096).astype(float), np.nan), {"cmap": "hsv"}),
        ("barycentrics", np.dstack([gb.bary, np.zeros_like(gb.depth)]), {}),
        ("depth", np.where(hit, gb.depth, np.nan), {"cmap": "viridis_r"}),
    ]
    if gb.proxy.any():
        panels.append(("proxy (analytic)", gb.proxy.astype(float), {"cmap": "gray"}))
    if gb.position is not None:
        lo, hi = gb.position[hit].min(axis=0), gb.position[hit].max(axis=0)
        panels.append(("position", np.clip((gb.position - lo) / np.maximum(hi - lo, 1e-9), 0, 1) * hit[..., None], {}))
    if gb.normal is not None:
        panels.append(("normal", (gb.normal * 0.5 + 0.5) * hit[..., None], {}))
    for name in ("albedo", "specular"):
        if getattr(gb, name) is not None:
            panels.append((name, np.clip(getattr(gb, name), 0, 1) ** (1 / 2.2), {}))
    if gb.optical is not None:
        for k, channel in enumerate(AOV_CHANNELS["optical"]):
            panels.append((f"optical: {channel}", gb.optical[..., k], {"cmap": "magma"}))
    cols = min(4, len(panels))
    rows = -(-len(panels) // cols)
    aspect = gb.depth.shape[0] / gb.depth.shape[1]
    fig, axes = plt.subplots(rows, cols, figsize=(4 * cols, 4 * aspect * rows + 0.4 * rows), squeeze=False)
    for ax in axes.ravel():
        ax.axis("off")
    for ax, (title, image, style) in zip(axes.ravel(), panels):
        if "cmap" in style:  # background (NaN) shows black, as in the RGB panels
            style = {**style, "cmap": plt.get_cmap(style["cmap"]).with_extremes(bad="black")}
        ax.imshow(image, interpolation="nearest", **style)
        ax.set_title(title, fontsize=10)
    fig.tight_layout()
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)
    return path


def write_result(exr: str | Path, result, **extra) -> dict:
    """A rendered frame (``HybridResult``) as files beside each other, each written atomically:
    ``exr`` (the image, its channels named by the film's pixel format: R G B (A), X Y Z (A) or
    Y (A); the ``raster`` and ``rt`` layers, sRGB, and the ``traced`` mask), a PNG of the image
    (converted to sRGB by ``mi.Bitmap``), and a JSON of its statistics (with ``extra`` fields
    first), written last: a frame whose JSON is there is complete. Returns the paths and the
    statistics."""
    import json

    import mitsuba as mi

    exr = Path(exr)
    image = np.array(result.image, dtype=np.float32)
    channels = {c: image[..., k] for k, c in enumerate(result.pixel_format.name)}
    for layer in ("raster", "rt"):
        channels.update({f"{layer}.{c}": result.layers[layer][..., k] for k, c in enumerate("RGB")})
    channels["traced.Y"] = result.layers["traced"].astype(np.float32)
    write_exr(exr, channels)
    png = exr.with_suffix(".png")
    with atomic_path(png) as tmp:
        preview = mi.Bitmap(image, pixel_format=result.pixel_format)
        preview.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.UInt8, srgb_gamma=True).write(str(tmp))
    stats = {**extra, **result.stats.as_dict()}
    write_text(exr.with_suffix(".json"), json.dumps(stats, indent=2))
    return {"exr": str(exr), "png": str(png), "stats": stats}
