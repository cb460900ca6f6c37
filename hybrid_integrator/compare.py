"""Reference comparison: the hybrid against the pure ray-tracing baseline and the ground truth.

For one scene this renders, on the same film and at the same ``spp``:

- ``raster``: the raster layer alone (``candidates=""``: nothing traced), the paper's DR image;
- ``hybrid``: raster primary hits + ray-traced effects (the integrator's settings);
- ``rt-baseline``: the same with ``primary="raytrace"`` (the paper's pure GPU ray tracer, §8);
- ``path``: Mitsuba's own ``path`` integrator at the same ``spp`` and ``max_depth``;

and measures each against the **ground truth**, Mitsuba's ``path`` at high ``spp``, cached on disk
under a key made of the scene file's content (and every file it references), the scene
parameters, ``spp``, ``max_depth``, the variant and Mitsuba's version. Times are per frame (all
``spp`` passes), after one warm-up frame that compiles the kernels, with the backend synchronized.
"""
from __future__ import annotations

import hashlib
import json
import os
import re
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import drjit as dr
import mitsuba as mi
import numpy as np

from .cache import disk_cache
from .errors import HybridError, require_counts
from .metrics import image_error
from .scene import load_scene


@dataclass(frozen=True)
class MethodResult:
    method: str
    time_ms: float
    flip: float
    rel_mse: float
    delta_e2000: float
    secondary_rays: int | None = None
    pixels_traced: int | None = None


def cache_dir() -> Path:
    """Where ground-truth images are kept (``cache.disk_cache``)."""
    return disk_cache("ground_truth")


def scene_fingerprint(path: Path, params: dict) -> str:
    """SHA-256 of the scene file, the files it names (meshes, textures, includes) and ``params``."""
    path = Path(path)
    digest = hashlib.sha256(path.read_bytes())
    for name in sorted(set(re.findall(r'(?:value|filename)="([^"$]+\.[A-Za-z0-9]+)"', path.read_text(errors="replace")))):
        ref = path.parent / name
        if ref.is_file():
            digest.update(name.encode())
            digest.update(ref.read_bytes())
            if ref.suffix == ".xml":
                digest.update(scene_fingerprint(ref, {}).encode())
    digest.update(json.dumps(params, sort_keys=True, default=str).encode())
    return digest.hexdigest()


def render_path(scene: mi.Scene, spp: int, max_depth: int, seed: int = 0) -> mi.TensorXf:
    integrator = mi.load_dict({"type": "path", "max_depth": int(max_depth)})
    return mi.render(scene, integrator=integrator, spp=spp, seed=seed)


#: a timed run stops after this many seconds of repeats once it has ``MIN_REPEATS`` of them
TIME_LIMIT_S = 1.0
MIN_REPEATS = 3


def _timed(render, repeats: int) -> tuple[np.ndarray, list[float]]:
    """``render()`` run up to ``repeats`` times after one warm-up run (which compiles), each timed
    with the backend synchronized once: (its last image as (H, W, 3) float32, the times in ms).
    Frames under ``TIME_LIMIT_S / repeats`` all get ``repeats`` runs (20 frames of 50 ms); slower
    ones stop after ``TIME_LIMIT_S`` of repeats, with at least ``MIN_REPEATS``."""
    times, image = [], None
    for r in range(repeats + 1):
        start = time.perf_counter()
        image = render()
        dr.eval(image)
        dr.sync_thread()
        if r:
            times.append((time.perf_counter() - start) * 1e3)
            if len(times) >= MIN_REPEATS and sum(times) > TIME_LIMIT_S * 1e3:
                break
    return np.array(image, dtype=np.float32)[..., :3], times


def path_renders(scene: mi.Scene, sensor: mi.Sensor, integrators: list, spp: int, frozen: bool = False):
    """A function of the seed that renders ``integrators`` in turn through ``sensor`` at ``spp``
    (a tuple of their images). ``frozen``: the renders replayed from one recording (``dr.freeze``,
    through the same snapshot of the scene's variables as the hybrid's device pass,
    ``frozen.FrozenScene``; the sensor and the seed its inputs; recorded here), as a real-time
    frame would call them: the same images (to the order of the film's atomic sums), without the
    host tracing every kernel again on every call (``path`` on this project's CPU, Sponza at
    320×180: 91.2 → 77.7 ms per frame, docs/results/gpu/issue10/stop46/baselines_cpu.py)."""
    def render(scene, sensor, seed):
        return tuple(mi.render(scene, sensor=sensor, integrator=i, spp=spp, seed=seed) for i in integrators)

    if not frozen:
        return lambda seed: render(scene, sensor, seed)
    from .frozen import FrozenScene, require_frozen

    replay = FrozenScene(scene).freeze(render)
    replay(sensor, dr.opaque(mi.UInt32, 0))  # the recording (any seed: the same kernels)
    require_frozen(replay.inputs, "frozen path")
    return lambda seed: replay(sensor, dr.opaque(mi.UInt32, seed))


def timed_path(scene: mi.Scene, spp: int, max_depth: int, seed: int, repeats: int = 1,
               frozen: bool = False) -> tuple[np.ndarray, list[float]]:
    """Mitsuba ``path`` rendered ``repeats`` times after one warm-up render (:func:`_timed`),
    called as ``mi.render`` or ``frozen`` (:func:`path_renders`)."""
    integrator = mi.load_dict({"type": "path", "max_depth": int(max_depth)})
    render = path_renders(scene, scene.sensors()[0], [integrator], spp, frozen)
    return _timed(lambda: render(seed)[0], repeats)


def timed_path_denoised(scene: mi.Scene, spp: int, max_depth: int, seed: int, repeats: int = 1,
                        quality: str = "high", frozen: bool = True) -> tuple[np.ndarray, list[float]]:
    """Mitsuba ``path`` + the hybrid's denoiser, as a real-time path tracer runs it: ``path``, then
    the guides (first-hit albedo and shading normal) from Mitsuba's ``aov`` integrator with no
    integrator of its own, both at the same seed through a copy of the sensor with a ``box``
    filter (the denoiser needs uncorrelated pixels; the same seed gives the same camera rays, so
    the guides are the path's first hits), replayed from one recording (``frozen``, as the
    hybrid's frame is: :func:`path_renders`), then Open Image Denoise (``denoise.py``). Timed as
    :func:`timed_path`, guides and denoiser included. (Given ``path`` as its nested integrator,
    ``aov`` renders it twice: its ``render`` renders the nested integrator, and its own samples
    call the nested integrator again for a copy of the colour that it drops; that doubled the
    baseline's time before stop 46, docs/results/README.md.)"""
    render = path_denoised_renders(scene, spp, max_depth, quality, frozen)
    return _timed(lambda: render(seed), repeats)


def path_denoised_renders(scene: mi.Scene, spp: int, max_depth: int, quality: str = "high", frozen: bool = True):
    """The frame :func:`timed_path_denoised` times, as a function of the seed (recorded here)."""
    from .denoise import Denoiser, Guides
    from .raster.camera import sensor_like

    size = scene.sensors()[0].film().size()
    sensor = sensor_like(scene.sensors()[0], int(size[0]), int(size[1]), rfilter="box")
    integrators = [mi.load_dict({"type": "path", "max_depth": int(max_depth)}),
                   mi.load_dict({"type": "aov", "aovs": "albedo:albedo,nn:sh_normal"})]
    renders = path_renders(scene, sensor, integrators, spp, frozen)
    denoiser = Denoiser(quality)

    def render(seed):
        colour, first = renders(seed)
        return denoiser(colour[..., 0:3], Guides(albedo=first[..., 0:3], normal=first[..., 3:6]))

    return render


def ground_truth(scene_path: Path | str, scene: mi.Scene, params: dict, spp: int, max_depth: int) -> tuple[np.ndarray, Path, bool]:
    """Mitsuba ``path`` at ``spp``, from the cache when the same scene and settings were rendered
    before. Returns (image, file, whether it came from the cache). ``scene_path`` is the scene
    file, or a name for a scene built in code (whose ``params`` then say all that defines it)."""
    settings = {**params, "spp": spp, "max_depth": max_depth, "variant": mi.variant(), "mitsuba": mi.__version__}
    if Path(scene_path).is_file():
        key = scene_fingerprint(Path(scene_path), settings)
    else:
        key = hashlib.sha256(json.dumps([str(scene_path), settings], sort_keys=True, default=str).encode()).hexdigest()
    file = cache_dir() / f"{Path(scene_path).stem}-{key[:16]}.exr"
    if file.is_file():
        return np.array(mi.Bitmap(str(file)), dtype=np.float32)[..., :3], file, True
    image = np.array(render_path(scene, spp, max_depth, seed=0x5EED), dtype=np.float32)[..., :3]
    file.parent.mkdir(parents=True, exist_ok=True)
    tmp = file.with_suffix(f".{os.getpid()}.exr")
    mi.util.write_bitmap(str(tmp), image, write_async=False)
    tmp.replace(file)
    return image, file, False


def require_srgb(command: str, scene: mi.Scene, **properties) -> None:
    """A :class:`HybridError` where ``command`` would measure the error of images that are not
    linear sRGB: FLIP, relative MSE and ΔE2000 (``metrics.py``) read an image's first three
    channels as linear sRGB, and a film of another pixel format (hdrfilm's xyz, luminance)
    develops something else. The film's format is known once it has developed a frame
    (``pipeline.Development``): one raster-layer frame of the hybrid with ``properties``, made
    before the ground truth's render, which the error would waste."""
    import hybrid_integrator as hi
    from .pipeline import SRGB

    pixel_format = hi.render(scene, spp=1, layers=False, **{**properties, "candidates": ""}).pixel_format
    if pixel_format not in SRGB:
        name = {"Y": "luminance", "YA": "luminance_alpha"}.get(pixel_format.name, pixel_format.name.lower())
        raise HybridError(f"{command} measures error on linear sRGB images, and the scene's film develops "
                          f"{name}: give the film pixel_format rgb or rgba")


def compare(scene_path: Path, params: dict, spp: int = 16, gt_spp: int = 1024, seed: int = 0,
            out_dir: Path | None = None, **properties) -> dict:
    """Render every method, measure it against the ground truth; write images and a report to
    ``out_dir`` when given. ``properties`` are the hybrid integrator's. ``path`` is timed frozen,
    as the hybrid's frame is (:func:`timed_path`)."""
    import hybrid_integrator as hi

    require_counts("compare", spp=spp, gt_spp=gt_spp)
    scene_path = Path(scene_path)
    scene = load_scene(scene_path, **params)
    max_depth = int(properties.get("max_depth", -1))
    runs = {
        "raster": lambda: hi.render(scene, spp=spp, seed=seed, **{**properties, "candidates": ""}),
        "hybrid": lambda: hi.render(scene, spp=spp, seed=seed, **properties),
        "rt-baseline": lambda: hi.render(scene, spp=spp, seed=seed, **{**properties, "primary": "raytrace"}),
    }
    require_srgb("compare", scene, **properties)
    reference, gt_file, cached = ground_truth(scene_path, scene, params, gt_spp, max_depth)
    rows, images, maps = [], {}, {}
    for name, run in runs.items():
        run()  # warm-up: kernel compilation, geometry upload
        result = run()
        image = np.array(result.image, dtype=np.float32)[..., :3]
        error, error_maps = image_error(image, reference)
        rows.append(MethodResult(name, result.stats.times_ms["total"], error.flip, error.rel_mse, error.delta_e2000,
                                 result.stats.secondary_rays, result.stats.pixels_traced))
        images[name], maps[name] = image, error_maps
    # replayed from a recording, as the hybrid's frame is (path_renders): mi.render alone would add
    # its host's tracing of the kernel, 1.7-22 ms per frame on an H200 (docs/results, issue 10, stop 46)
    path_image, (path_ms,) = timed_path(scene, spp, max_depth, seed, frozen=True)
    error, maps["path"] = image_error(path_image, reference)
    rows.append(MethodResult("path", path_ms, error.flip, error.rel_mse, error.delta_e2000))
    images["path"] = path_image

    film = scene.sensors()[0].film().size()
    report = {"scene": str(scene_path), "params": params, "width": int(film[0]), "height": int(film[1]), "spp": spp,
              "ground_truth": {"integrator": "path", "spp": gt_spp, "max_depth": max_depth, "file": str(gt_file),
                               "cached": cached},
              "properties": {k: v for k, v in properties.items()}, "variant": mi.variant(),
              "methods": [asdict(r) for r in rows]}
    if out_dir is not None:
        _write(Path(out_dir), report, images, maps, reference)
    return report


def table(report: dict) -> str:
    """The comparison as a markdown table."""
    lines = [f"{report['scene']} at {report['width']}×{report['height']}, {report['spp']} spp, {report['variant']}; "
             f"ground truth: path, {report['ground_truth']['spp']} spp, max_depth {report['ground_truth']['max_depth']}",
             "", "| method | time per frame (ms) | FLIP | rel. MSE | ΔE2000 | secondary rays | pixels traced |",
             "|---|---|---|---|---|---|---|"]
    def count(value):
        return "" if value is None else f"{value:,}"

    for m in report["methods"]:
        lines.append(f"| {m['method']} | {m['time_ms']:.1f} | {m['flip']:.4f} | {m['rel_mse']:.4f} | "
                     f"{m['delta_e2000']:.3f} | {count(m['secondary_rays'])} | {count(m['pixels_traced'])} |")
    return "\n".join(lines)


def _write(out: Path, report: dict, images: dict, maps: dict, reference: np.ndarray) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    (out / "compare.json").write_text(json.dumps(report, indent=2))
    (out / "compare.md").write_text(table(report) + "\n")
    mi.util.write_bitmap(str(out / "ground_truth.png"), reference, write_async=False)
    for name, image in images.items():
        mi.util.write_bitmap(str(out / f"{name}.exr"), image, write_async=False)
        mi.util.write_bitmap(str(out / f"{name}.png"), image, write_async=False)
    fig, axes = plt.subplots(2, len(images), figsize=(4 * len(images), 6.5), squeeze=False)
    for col, name in enumerate(images):
        axes[0, col].imshow(np.clip(images[name], 0, 1) ** (1 / 2.2))
        axes[0, col].set_title(name)
        axes[1, col].imshow(maps[name]["flip"], cmap="magma", vmin=0, vmax=1)
        m = next(r for r in report["methods"] if r["method"] == name)
        axes[1, col].set_title(f"FLIP {m['flip']:.4f}")
        for ax in axes[:, col]:
            ax.axis("off")
    fig.tight_layout()
    fig.savefig(out / "errors.png", dpi=90)
    plt.close(fig)
