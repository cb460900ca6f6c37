"""Dr.Jit's kernel history, read without its copies of the kernels' source (issue 10).

A frame's device time per stage comes from Dr.Jit's kernel history (``JitFlag.KernelHistory``:
``pipeline.StageClock``), read once after the frame's synchronization. Dr.Jit 1.5's
``drjit.kernel_history()`` gives every JIT kernel's entry its intermediate representation as an
``io.StringIO``, decoded from the C string that Dr.Jit keeps of the kernel's source: about 1.1 ms
of host time per MB of source on this project's CPU (``docs/results/gpu/issue10/stop48``). The
frame's megakernel is the bulk of it, so every frame paid in proportion to the scene's code (on
the H200, 0.39 ms of host time per frame on the showcase, 0.78 on Sponza, 1.05 on the dining room,
whose megakernel has 11,738 operations), for text no stage time reads.

:func:`reader` reads the same entries through Dr.Jit's C API, ``jit_kernel_history``
(whose entry layout, ``KernelHistoryEntry``, is in the ``drjit-core/jit.h`` that Dr.Jit's wheel
ships), takes the fields the stage times and the profiles read, and frees the source strings
unread, as ``drjit.kernel_history`` does after copying them (0.19-0.36 ms per frame on the H200).
It checks the layout once, on a kernel of its own (so it must not be called while a frame's
history is being kept); where the symbol is missing or the check fails, it gives
``drjit.kernel_history`` instead (the same entries, with ``ir``), and :data:`READER` says which.

:func:`read_ahead` makes the same read from a thread that issues no Dr.Jit work, so that it waits
for nothing (issue 10, stop 51): a denoised frame reads its device passes' history while the GPU
denoises it, not after its synchronization.
"""
from __future__ import annotations

import ctypes
import itertools
import math
import os
from collections.abc import Callable, Iterator
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import drjit as dr
import numpy as np


class _Entry(ctypes.Structure):
    """``KernelHistoryEntry`` of Dr.Jit 1.5's ``drjit-core/jit.h`` (natural C alignment)."""

    _fields_ = [("backend", ctypes.c_uint32), ("type", ctypes.c_uint32), ("recording_mode", ctypes.c_uint32),
                ("hash", ctypes.c_uint64 * 2), ("ir", ctypes.c_void_p), ("uses_optix", ctypes.c_int),
                ("cache_hit", ctypes.c_int), ("cache_disk", ctypes.c_int), ("size", ctypes.c_uint32),
                ("input_count", ctypes.c_uint32), ("output_count", ctypes.c_uint32),
                ("operation_count", ctypes.c_uint32), ("codegen_time", ctypes.c_float),
                ("backend_time", ctypes.c_float), ("execution_time", ctypes.c_float),
                ("event_start", ctypes.c_void_p), ("event_end", ctypes.c_void_p), ("task", ctypes.c_void_p)]


_SIZE = ctypes.sizeof(_Entry)
#: the same layout for NumPy (which reads a ctypes structure's fields, offsets and alignment)
_DTYPE = np.dtype(_Entry)
_JIT = dr.KernelType.JIT.value
_KERNEL_TYPES = {kind.value: kind for kind in dr.KernelType}

#: the reader :func:`reader` gives, once checked
_READER: Callable[[], list[dict]] | None = None
_API: tuple | None = None  # Dr.Jit's C API functions (``_load``), once checked
_WORKER: ThreadPoolExecutor | None = None  # the thread of :func:`read_ahead`'s reads


def _forget_worker() -> None:
    """In a forked child the worker's thread is gone (fork copies the calling thread alone) while its
    executor would still count it, and wait for it forever: a new one is made on first use."""
    global _WORKER
    _WORKER = None


os.register_at_fork(after_in_child=_forget_worker)
#: "C API" or "drjit.kernel_history" (a fallback: the symbol is missing or its layout check failed)
READER = "drjit.kernel_history"


def _load() -> tuple | None:
    try:
        core = ctypes.CDLL(str(Path(dr.__file__).parent / "libdrjit-core.so"))
        history = core["_Z18jit_kernel_historyv"]
        libc = ctypes.CDLL(None)
    except (OSError, AttributeError):
        return None
    history.restype, history.argtypes = ctypes.POINTER(_Entry), []
    libc.free.restype, libc.free.argtypes = None, [ctypes.c_void_p]
    return history, libc.free


def _entries(data) -> Iterator[_Entry]:
    """The entries of the array ``jit_kernel_history`` returned, up to the one of backend 0 that
    ends it."""
    base = ctypes.cast(data, ctypes.c_void_p).value
    for k in range(_count(base)):
        yield _Entry.from_address(base + k * _SIZE)


def _count(base: int) -> int:
    """How many entries the array at ``base`` holds before the one of backend 0 that ends it."""
    n = 0
    while ctypes.c_uint32.from_address(base + n * _SIZE).value:
        n += 1
    return n


def _parse(api: tuple, data) -> list[dict]:
    """The entries of what ``jit_kernel_history`` returned, freed. The array is read at once as
    a NumPy record array (:data:`_DTYPE`) and each column converted once, not entry by entry through
    ctypes: 0.05-0.09 ms against 0.08-0.14 for a frame's ~30 entries on this project's CPU
    (docs/results/gpu/issue10/stop58/parse_ab.py)."""
    free = api[1]
    if not data:
        return []
    base = ctypes.cast(data, ctypes.c_void_p).value
    table = np.frombuffer((ctypes.c_char * (_count(base) * _SIZE)).from_address(base), dtype=_DTYPE)
    out = []
    columns = (table[name].tolist() for name in ("backend", "type", "size", "execution_time", "hash",
                                                 "operation_count", "uses_optix"))
    for backend, kind, size, ms, (low, high), operations, optix in zip(*columns):
        item = {"backend": backend, "type": _KERNEL_TYPES[kind], "size": size, "execution_time": ms}
        if kind == _JIT:
            item.update(hash=f"{high:016x}{low:016x}", operation_count=operations, uses_optix=optix)
        out.append(item)
    for ir in table["ir"].tolist():
        free(ir)
    free(data)
    return out


def _check(api: tuple) -> bool:
    """The layout read right: one kernel of a known width, on the active variant's backend, read
    back before anything is freed (a failed check leaves its entry unfreed rather than free what it
    may have misread)."""
    import mitsuba as mi

    history, free = api
    width = 7919
    with dr.scoped_set_flag(dr.JitFlag.KernelHistory, True):
        dr.kernel_history_clear()
        dr.eval(dr.arange(mi.UInt32, width) * 3 + 1)
        data = history()
    if not data:
        return False
    entries = list(itertools.islice(_entries(data), 2))
    entry = entries[0] if entries else None
    ok = (len(entries) == 1 and entry.backend in (1, 2) and entry.type == dr.KernelType.JIT.value
          and entry.size == width and 0 < entry.operation_count < 100 and bool(entry.ir)
          and math.isfinite(entry.execution_time) and entry.execution_time >= 0.0)
    if ok:
        free(entry.ir)
        free(data)
    return ok


def read_ahead() -> Callable[[], list[dict]]:
    """Start reading the kernel history (:func:`reader`) on a thread of its own, which never issues
    Dr.Jit work; returns a function that waits for the entries. ``jit_kernel_history``
    synchronizes the stream of the thread that calls it (``jitc_sync_thread``, on Dr.Jit's
    thread-local state, of which that thread has none) before it reads the history's CUDA events:
    on the thread that issued a frame it would also wait for the work issued after the entries
    (the frame's development and denoiser, ~1.2 ms on the H200), here it waits for nothing, and it
    runs while the caller goes on. So it is only for entries known to be complete, with nothing
    recorded after them (the pipeline starts it once a frame's device passes are done, their counts
    copied to the host behind them, with the history off since): the time of an entry whose end
    event the GPU has not reached is not measured (Dr.Jit's ``cuEventElapsedTime`` fails quietly;
    it would read 0) and the read consumes it. On the LLVM backend a worker's read would not wait
    for the kernels' tasks either: CUDA only."""
    global _WORKER
    read = reader()  # on the calling thread: the first call checks the layout with a kernel of its own
    if _WORKER is None:
        _WORKER = ThreadPoolExecutor(max_workers=1, thread_name_prefix="kernel-history")
    if _API is None:  # drjit.kernel_history: the whole read on the worker
        return _WORKER.submit(read).result
    # the worker makes the C call alone (ctypes lets go of Python's lock during it); the entries are
    # parsed by the caller, so the two threads do not take turns at Python's lock meanwhile
    fetched = _WORKER.submit(_API[0])
    return lambda: _parse(_API, fetched.result())


def reader() -> Callable[[], list[dict]]:
    """A function that returns the kernel history since it was last read or cleared, and clears
    it (as ``drjit.kernel_history()``): per launch ``backend``, ``type``, ``size`` and
    ``execution_time`` (ms), and for JIT kernels ``hash``, ``operation_count`` and ``uses_optix``,
    without ``ir``. The first call checks the layout (it launches a kernel and clears the history)."""
    global _READER, READER, _API
    if _READER is None:
        api = _load()
        if api is not None and _check(api):
            _READER, READER, _API = (lambda: _parse(api, api[0]())), "C API", api
        else:
            _READER, READER = dr.kernel_history, "drjit.kernel_history"
    return _READER
