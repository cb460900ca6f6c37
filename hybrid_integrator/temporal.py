"""Temporal accumulation: each frame adds to the last ones, reprojected through the visibility
buffer.

One frame at one sample per pixel is noisy where it is ray traced; the frames before it saw the
same surfaces. Every pixel keeps a running mean of its colour and the number of frames in it. A
new frame finds each pixel's history where its surface was last frame: the pixel's world-space
hit (the G-buffer position) is projected with the *previous* camera, and the history at that
pixel is used only if it shows the same object on the same surface (object id equal, the two hit
points within 1 % of the distance to the eye along the surface normal, so that neighbouring
samples on a slanted plane still match); anything else (disocclusion, a silhouette, a surface
that moved) restarts from the current frame, so nothing ghosts.

- **Still camera**: every pixel is its own history, each frame's sub-pixel offset is another
  point of the pixel's sampling pattern (a pixel on a silhouette sees one object or the other:
  both belong to its mean), and the mean converges to what the hybrid's estimator converges to
  (with every effect traced: Mitsuba's ``path``), at the frame's cost per sample.
- **Moving camera**: the history is fetched at the nearest pixel, which blurs a little at each
  step, so it holds at most ``MOTION_FRAMES`` frames (an exponential moving average with
  α = 1/16 beyond that).

The accumulated colour is what is denoised (``denoise.py``), as real-time renderers do; the
history keeps the colour before denoising. The whole update is one frozen Dr.Jit function over
device arrays: the cameras and the frame cap are data, so a moving camera replays the same kernel.
"""
from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

#: frames a pixel's history holds while the camera moves (exponential average beyond)
MOTION_FRAMES = 16
#: frames it holds with a still camera (a plain mean of every frame)
STILL_FRAMES = 1 << 20


@dataclass
class Surface:
    """Per pixel, what a frame's first sample pass hit: world position, shading normal, object
    (``2**32-1``: none)."""

    position: mi.Point3f
    normal: mi.Vector3f
    object: mi.UInt32


@dataclass
class History:
    """The accumulated frames, as the next frame reprojects them."""

    color: mi.Float  # H·W·3 running mean (before denoising)
    count: mi.Float  # per pixel, the frames in that mean
    surface: Surface
    world_to_clip: np.ndarray  # the camera of the last frame (RasterCamera.world_to_clip)
    eye: np.ndarray
    width: int
    height: int


def _accumulate(color: mi.Float, surface: Surface, eye: mi.Float, history_color: mi.Float, history_count: mi.Float,
                history_surface: Surface, camera: mi.Float, width: int, height: int):
    """The frozen update: ``camera`` holds the previous world → clip matrix (row-major, 16
    floats), then the frame cap, then whether the camera is still (1/0)."""
    n = width * height
    m = [dr.gather(mi.Float, camera, k) for k in range(16)]
    p = surface.position
    clip = [m[4 * r] * p.x + m[4 * r + 1] * p.y + m[4 * r + 2] * p.z + m[4 * r + 3] for r in range(4)]
    x = (clip[0] / clip[3] + 1.0) * (0.5 * width)
    y = (clip[1] / clip[3] + 1.0) * (0.5 * height)
    hit = surface.object != 0xFFFFFFFF
    cap, still = dr.gather(mi.Float, camera, 16), dr.gather(mi.Float, camera, 17) > 0.5
    index = dr.arange(mi.UInt32, n)
    inside = (clip[3] > 0) & (x >= 0) & (x < width) & (y >= 0) & (y < height)
    prev = dr.select(hit & inside, mi.UInt32(dr.clip(mi.Int32(y), 0, height - 1)) * width
                     + mi.UInt32(dr.clip(mi.Int32(x), 0, width - 1)), index)
    prev_p = dr.gather(mi.Point3f, history_surface.position, prev)
    eye_p = mi.Point3f(*(dr.gather(mi.Float, eye, k) for k in range(3)))
    moved = dr.select(hit, inside & (dr.gather(mi.UInt32, history_surface.object, prev) == surface.object)
                      & (dr.abs(dr.dot(prev_p - p, surface.normal)) <= 0.01 * dr.norm(p - eye_p)), False)
    # a still camera: every pixel is its own history (the frames are more samples of the same
    # pixel, whichever object each sample hit: supersampling); a moving one: the tests above
    same = still | moved
    prev = dr.select(still, index, prev)
    count = dr.minimum(dr.select(same, dr.gather(mi.Float, history_count, prev), 0.0) + 1.0, cap)
    a = dr.rcp(count)
    out = []
    for c in range(3):
        current = dr.gather(mi.Float, color, index * 3 + c)
        old = dr.gather(mi.Float, history_color, prev * 3 + c)
        out.append(dr.select(same, dr.fma(current - old, a, old), current))
    blended = dr.zeros(mi.Float, 3 * n)
    for c in range(3):
        dr.scatter(blended, out[c], index * 3 + c)
    return blended, count


class Accumulator:
    """The history of one image size, updated by one frozen function per frame."""

    def __init__(self, freeze: bool = True, mark=None):
        """``mark(*arrays)``, if given, is called with the update's outputs where its body runs
        (unfrozen, or while ``dr.freeze`` records it): the stage clock's
        :meth:`~hybrid_integrator.pipeline.StageClock.mark`, which reads Dr.Jit's kernel history
        and so waits for the device. A replay does not run the body, so a frozen update adds no
        synchronization to the frame."""

        def update(*args):
            blended, count = _accumulate(*args)
            if mark is not None:
                mark(blended, count)
            return blended, count

        self._update = dr.freeze(update) if freeze else update

    def __call__(self, color: mi.TensorXf, surface: Surface, camera, history: History | None) -> tuple[mi.TensorXf, History]:
        """``color`` (H×W×3) with the reprojected history blended in; returns it and the new history."""
        height, width = color.shape[0], color.shape[1]
        flat = color.array
        if history is None or (history.width, history.height) != (width, height):
            count = dr.full(mi.Float, 1.0, width * height)
            blended = mi.Float(flat)
        else:
            still = np.array_equal(history.world_to_clip, camera.world_to_clip)
            data = mi.Float(np.r_[history.world_to_clip.ravel(), STILL_FRAMES if still else MOTION_FRAMES,
                                  1.0 if still else 0.0].astype(np.float32))
            blended, count = self._update(flat, surface, mi.Float(np.asarray(camera.eye, np.float32)), history.color,
                                          history.count, history.surface, data, width, height)
        new = History(color=blended, count=count, surface=surface, world_to_clip=camera.world_to_clip.copy(),
                      eye=np.asarray(camera.eye).copy(), width=width, height=height)
        return mi.TensorXf(blended, (height, width, 3)), new
