"""Frames in flight: the host issues a frame while the GPU finishes the one before (issue 10).

A frame rendered one at a time (``frames_in_flight=1``, the default) ends with the backend's one
synchronization, after which Dr.Jit's kernel history gives each stage's device time. Between that
synchronization and the next frame's first kernel the GPU has nothing to do: the host reads the
stage times (0.3–0.5 ms on an H200's host: docs/results/gpu/issue10/stop42, ``host.sh``), returns,
sets up the next frame, copies its visibility buffer and replays its device pass (about 1 ms in
all). Stop 41 measured that gap at 1.1–1.3 ms of an 8–16 ms frame, for the hybrid and its RT
baseline alike (docs/results/gpu/issue10/stop41, ``run1.sh``–``run3.sh``). Stop 43 measured what
frames in flight gain (``docs/results/gpu/issue10/stop43/run.sh wall``): 3–18 % of the wall time
per frame for the hybrid, 4–19 % for the RT baseline, whose frames have no OpenGL handoff between
them (0.41–0.57 ms of GPU time per hybrid frame, ``run.sh timeline``).

With ``frames_in_flight=2`` a frame does not synchronize. Once its device passes are issued it
waits for the frame before (which the GPU finishes ahead of them: the wait costs the GPU nothing),
reads that frame's counts and learns from them (``HybridRenderer._account``), then issues its own
development and denoising and returns. Only the hybrid waits for anything more: for its own trace to
end (its counts' copy), before its visibility target goes back to OpenGL and the next frame's
raster pass is drawn ahead (OpenGL work pending while CUDA traces slows the trace: stop 42). The
next frame's host work then runs while the GPU develops and denoises, and its kernels queue behind
them, so the GPU goes from one frame to the next without waiting for the host. This is how a
real-time renderer runs (two frames in flight), and what its frame rate measures.

What a frame in flight gives up:

- Dr.Jit 1.5 synchronizes the thread to read its kernel history (``jit_kernel_history`` calls
  ``jitc_sync_thread``), so a frame in flight has no per-stage device times (NaN in
  ``FrameStats.times_ms``), and keeps no history (until stop 50 it recorded one, CUDA events around
  every launch, that nothing read), only what CUDA events and OpenGL timer queries give without a
  synchronization: ``total``, the device time from the end of the frame before (if it was still
  in flight when this one started: in a sequence, the GPU's period from one frame's end to the
  next's, time the GPU waited for the host included) or else from this frame's first work on
  the GPU, to its last (:class:`FrameSpan`), ``gl`` (its raster pass) and ``denoise``. They, and its statistics from its counts, are filled in
  by the next frame or by :meth:`HybridRenderer.finish` (``hi.render_sequence`` and ``hi.render``
  call it after their last frame).
- What a frame learns reaches the frame after next: the ambient light learnt from frame N's traced
  pixels (``lighting.learn_ambient``) shades frame N + 2's raster layer, not N + 1's. Where every
  visible candidate is traced (no budget, the default candidates) the images are the same as one
  frame at a time; the objects' order by relevance in ``FrameStats.selected`` may differ.
- A frame with a budget plans from the last frame's coverage and learns the trace's time from the
  kernel history, so it is rendered one at a time whatever ``frames_in_flight`` says
  (``FrameStats.in_flight`` says how each frame ran).

On the LLVM backend reading the frame's counts waits for all its work (the CPU runs kernels on a
thread pool that the read synchronizes), so nothing overlaps there: its frames in flight end with a
synchronization as before, and their times are kept the same way as on the GPU.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import drjit as dr
import mitsuba as mi

from .raster.interop import StreamTimer

#: ``frames_in_flight`` values: one frame at a time, or two (module docstring)
FRAMES_IN_FLIGHT = (1, 2)


class FrameSpan:
    """A frame's device time, from the first work it gives the GPU to its last, read without
    synchronizing the backend: two CUDA events on Dr.Jit's stream (``interop.StreamTimer``), or, on
    the LLVM backend, the host's clock from the frame's start to a synchronization at its end."""

    def __init__(self):
        self.cuda = mi.variant().startswith("cuda")
        self._events = StreamTimer() if self.cuda else None
        self._start = self._end = 0.0

    def start(self) -> None:
        """Mark the frame's start (before any of its work is issued)."""
        if self._events is not None:
            self._events.start()
        else:
            self._start = time.perf_counter()

    def stop(self) -> None:
        """Mark the frame's end (after its last work is issued); on the CPU, wait for it."""
        if self._events is not None:
            self._events.stop()
        else:
            dr.sync_thread()
            self._end = time.perf_counter()

    def wait(self) -> None:
        """Wait for the frame's work to be done (not for what was issued after it)."""
        if self._events is not None:
            self._events.wait()

    def elapsed_ms(self, after: "FrameSpan | None" = None) -> float:
        """The span's time in ms (after :meth:`wait`): from its start, or from the end of the span
        ``after`` (the frame before, still in flight when this one started)."""
        if self._events is None:
            return (self._end - (self._start if after is None else after._end)) * 1e3
        return self._events.elapsed_ms() if after is None else self._events.elapsed_ms(since=after._events)


@dataclass
class InFlight:
    """A frame whose work may still run on the GPU, its counts and times to be read once it is
    done (``HybridRenderer.finish``)."""

    frame: object  # pipeline._Frame: its statistics, GL timer queries and denoiser
    span: FrameSpan
    after: FrameSpan | None  # the frame before's, if it was still in flight when this one started
    settings: object  # pipeline.HybridSettings it was rendered with
    state: object  # budget.FrameState it learns into
    copy: object  # interop.HostCopy its counts are copied into (None on the CPU)
    counts: list  # its passes' count arrays (read from these on the CPU)
