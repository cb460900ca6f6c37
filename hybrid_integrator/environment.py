"""Process set-up that must happen before Dr.Jit's LLVM backend starts.

Dr.Jit loads the newest ``libLLVM`` it finds unless ``DRJIT_LIBLLVM_PATH`` names one. On Debian 12
Mesa pulls in LLVM 15, which crashes Dr.Jit's first kernel ("Cannot select ... fminimum"), so the
project pins LLVM 19 (Debian package ``libllvm19``). The backend is created lazily, on the first
LLVM array, so setting the variable when this package is imported is early enough for the usual
``import mitsuba; mi.set_variant(...); import hybrid_integrator`` order.
"""
from __future__ import annotations

import glob
import os

#: where Debian (and Ubuntu) install LLVM 19's shared library
LLVM19_CANDIDATES = (
    "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1",
    "/usr/lib/x86_64-linux-gnu/libLLVM-19.so",
    "/usr/lib/aarch64-linux-gnu/libLLVM.so.19.1",
    "/usr/lib/aarch64-linux-gnu/libLLVM-19.so",
    "/usr/lib/llvm-19/lib/libLLVM.so.19.1",
)


def pin_llvm() -> str | None:
    """Set ``DRJIT_LIBLLVM_PATH`` to LLVM 19 unless the user already set it.

    Returns the path in force, or ``None`` where no LLVM 19 library exists (Dr.Jit then picks one
    itself; the CUDA backend does not need LLVM at all)."""
    if os.environ.get("DRJIT_LIBLLVM_PATH"):
        return os.environ["DRJIT_LIBLLVM_PATH"]
    found = [p for p in LLVM19_CANDIDATES if os.path.exists(p)]
    found += sorted(glob.glob("/usr/lib/*/libLLVM*.so.19*"))
    if not found:
        return None
    os.environ["DRJIT_LIBLLVM_PATH"] = found[0]
    return found[0]


def require_jit_rgb_variant() -> str:
    """Return the active Mitsuba variant, or raise if it is not a JIT RGB variant.

    The pipeline hands buffers between OpenGL and Dr.Jit arrays and shades traced pixels with
    Mitsuba's RGB BSDFs, so it needs ``llvm_*_rgb`` or ``cuda_*_rgb``."""
    import mitsuba as mi

    from .errors import UnsupportedVariantError

    variant = mi.variant()
    if variant is None:
        raise UnsupportedVariantError(
            "no Mitsuba variant is set: call mi.set_variant('llvm_ad_rgb') (or 'cuda_ad_rgb') first")
    if not (variant.startswith(("llvm_", "cuda_")) and variant.endswith("_rgb")):
        raise UnsupportedVariantError(
            f"Mitsuba variant '{variant}' is not supported: hybrid_integrator needs a JIT RGB variant "
            "such as 'llvm_ad_rgb' or 'cuda_ad_rgb'")
    return variant
