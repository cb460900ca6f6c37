"""Error of an image against a reference: FLIP, relative MSE and CIEDE2000.

- **FLIP** (NVIDIA's perceptual metric, ``flip-evaluator``), HDR mode on linear RGB: the mean of
  the FLIP error map, in [0, 1].
- **relative MSE**: mean over pixels and channels of (test − ref)² / (ref² + ε), ε = 1e-2, the
  rendering literature's usual noise measure (robust where the reference is black).
- **ΔE2000** (colour-science): linear sRGB clipped to [0, 1] → CIE XYZ → CIELAB (D65), then the
  CIEDE2000 difference per pixel; the mean is reported.
"""
from __future__ import annotations

import warnings
from dataclasses import asdict, dataclass

import numpy as np

REL_MSE_EPSILON = 1e-2


@dataclass(frozen=True)
class ImageError:
    flip: float
    rel_mse: float
    delta_e2000: float

    def as_dict(self) -> dict:
        return asdict(self)


def _rgb(image) -> np.ndarray:
    a = np.asarray(image, dtype=np.float32)
    if a.ndim != 3 or a.shape[2] < 3:
        raise ValueError(f"expected an H×W×3 image, got shape {a.shape}")
    return np.nan_to_num(a[..., :3], nan=0.0, posinf=0.0, neginf=0.0)


def relative_mse(test, reference) -> float:
    t, r = _rgb(test), _rgb(reference)
    return float(np.mean((t - r) ** 2 / (r * r + REL_MSE_EPSILON)))


def flip_map(test, reference) -> tuple[np.ndarray, float]:
    """FLIP error map (H×W) and its mean, HDR mode. A reference without a range of luminances (all
    black, or one constant colour) has no exposure range for HDR-FLIP, whose library then aborts
    the process: such a pair is compared with LDR-FLIP, on values clipped to [0, 1]."""
    import flip_evaluator

    ref, img = np.maximum(_rgb(reference), 0), np.maximum(_rgb(test), 0)
    luminance = ref @ np.array([0.2126, 0.7152, 0.0722])
    mode = "HDR" if float(np.ptp(luminance)) > 1e-6 * max(float(luminance.max()), 1e-30) and luminance.max() > 0 else "LDR"
    if mode == "LDR":
        ref, img = np.minimum(ref, 1.0), np.minimum(img, 1.0)
    error, mean, _ = flip_evaluator.evaluate(np.ascontiguousarray(ref, dtype=np.float32),
                                             np.ascontiguousarray(img, dtype=np.float32), mode, applyMagma=False)
    return np.asarray(error).reshape(_rgb(test).shape[:2]), float(mean)


def delta_e2000_map(test, reference) -> np.ndarray:
    """Per-pixel CIEDE2000 between the two images (display-referred: linear sRGB clipped to [0,1])."""
    with warnings.catch_warnings():  # colour-science warns about optional packages on import
        warnings.simplefilter("ignore")
        import colour

    def lab(image):
        xyz = colour.RGB_to_XYZ(np.clip(_rgb(image), 0.0, 1.0), colour.RGB_COLOURSPACES["sRGB"], apply_cctf_decoding=False)
        return colour.XYZ_to_Lab(xyz)

    return np.asarray(colour.delta_E(lab(test), lab(reference), method="CIE 2000"))


def image_error(test, reference) -> tuple[ImageError, dict[str, np.ndarray]]:
    """All three metrics, and the FLIP and ΔE2000 maps."""
    flip_error, flip_mean = flip_map(test, reference)
    de = delta_e2000_map(test, reference)
    return ImageError(flip=flip_mean, rel_mse=relative_mse(test, reference), delta_e2000=float(de.mean())), \
        {"flip": flip_error, "delta_e2000": de}


def _errors_only(test, reference) -> ImageError:
    return image_error(test, reference)[0]


def _flip_only(test, reference) -> float:
    return flip_map(test, reference)[1]


def errors_in_parallel(tests, references, flip_only: bool = False) -> list:
    """:func:`image_error`'s numbers (or, with ``flip_only``, the mean FLIP alone) of each pair,
    in worker processes: HDR-FLIP and ΔE2000 take seconds per 1280×720 image on one core. The
    workers are spawned, not forked, so that a CUDA context in this process is not inherited.
    Call it after any timing: the workers take every core."""
    import multiprocessing
    import os
    from concurrent.futures import ProcessPoolExecutor

    tests, references = list(tests), list(references)
    workers = max(1, min(len(tests), os.cpu_count() or 1))
    with ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context("spawn")) as pool:
        return list(pool.map(_flip_only if flip_only else _errors_only, tests, references))
