"""Errors raised by hybrid_integrator.

Every error names the offending thing (the variant, the shape, the sensor, the file, the missing
system package) so that a user can act on it without reading the source.
"""


class HybridError(RuntimeError):
    """Base class of every error this package raises on purpose."""


class UnsupportedVariantError(HybridError):
    """The active Mitsuba variant is not a JIT RGB variant (``llvm_ad_rgb``, ``cuda_ad_rgb``, ...)."""


class UnsupportedSceneError(HybridError):
    """The scene holds something the raster stage cannot draw (shape type, sensor, crop window,
    non-finite geometry)."""


class RasterContextError(HybridError):
    """No headless OpenGL context could be created."""


def require_fractions(command: str, budgets) -> None:
    """A :class:`HybridError` naming each of ``budgets`` (fractions of the all-candidates trace
    time) that is negative or not a number."""
    bad = [f for f in budgets if not 0 <= f < float("inf")]
    if bad:
        raise HybridError(f"{command}: budgets {bad} must be fractions >= 0 of the all-candidates trace time")


def require_counts(command: str, **counts: int) -> None:
    """A :class:`HybridError` naming each of ``counts`` (frames, samples per pixel) below 1."""
    low = [f"{name}={value}" for name, value in counts.items() if value < 1]
    if low:
        raise HybridError(f"{command}: {', '.join(low)} must be >= 1")
