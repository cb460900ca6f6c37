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
- **Moving camera**: the history is fetched at the nearest pixel, which misplaces it by up to half
  a pixel at each step, and the misplacements of the frames it holds add up: it holds at most
  ``MOTION_FRAMES`` frames (an exponential moving average with α = 1/``MOTION_FRAMES`` beyond
  that).

The accumulated colour is what is denoised (``denoise.py``), as real-time renderers do; the
history keeps the colour before denoising. A denoiser helps a young history and hurts an old one:
its output is a little blurred (a bias that more frames do not remove), and it sees the colour in
a box filter (it needs each pixel's own samples), while the film's filter (a tent, a Gaussian)
defines the image. So the history also keeps the mean of the colour's square and, where the film's
filter is not a box, the colour splatted in it; the denoised image is then *resolved* against that
film-filtered mean, per pixel, by how much of their difference the mean's own noise explains
(:func:`_resolve`): a young or noisy history shows the denoised image, a converged one its mean,
which converges to the film's image, Mitsuba's ``path`` at infinitely many samples (the bench's
still-camera rows, docs/results/README.md).

The whole update is one frozen Dr.Jit function over device arrays, and so is the resolve: the
cameras and the frame cap are data, so a moving camera replays the same kernels.
"""
from __future__ import annotations

from dataclasses import dataclass

import drjit as dr
import mitsuba as mi
import numpy as np

from .raster.interop import device_array

#: frames a pixel's history holds while the camera moves (exponential average beyond). Longer
#: histories average more noise away but carry more misplaced frames: with 16, on the default
#: scene's 30-frame path, the last frames came out worse than without history for some seeds (up
#: to +0.017 FLIP, 1-3 frames of 30, seeds 4-7); with 6 no frame is, for seeds 3-7, raw at 80×60
#: and denoised at 160×120, and the mean FLIP is lower too (denoised 0.159-0.160 against
#: 0.164 with 16 and 0.176 without history; tests/test_accuracy.py)
MOTION_FRAMES = 6
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
    square: mi.Float  # H·W·3 running mean of the colour squared (the mean's variance, :func:`resolve`)
    film: mi.Float | None  # H·W·3 running mean of the colour in the film's filter (None: ``color`` is in it)
    count: mi.Float  # per pixel, the frames in that mean
    surface: Surface
    world_to_clip: np.ndarray  # the camera of the last frame (RasterCamera.world_to_clip)
    eye: np.ndarray
    width: int
    height: int


def _accumulate(color: mi.Float, film: mi.Float | None, surface: Surface, eye: mi.Float, history: list[mi.Float],
                history_count: mi.Float, history_surface: Surface, camera: mi.Float, width: int, height: int):
    """The frozen update: ``camera`` holds the previous world → clip matrix (row-major, 16
    floats), then the frame cap, then whether the camera is still (1/0). ``history`` holds the
    running means of the colour, its square and, unless ``film`` is None, the film-filtered
    colour; returns their new values and the count."""
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
    means = [dr.zeros(mi.Float, 3 * n) for _ in history]
    for c in range(3):
        current = dr.gather(mi.Float, color, index * 3 + c)
        now = (current, current * current) + (() if film is None else (dr.gather(mi.Float, film, index * 3 + c),))
        for mean, value, old_mean in zip(means, now, history):
            old = dr.gather(mi.Float, old_mean, prev * 3 + c)
            dr.scatter(mean, dr.select(same, dr.fma(value - old, a, old), value), index * 3 + c)
    return means, count


#: half-widths of the windows the resolve averages its estimates over: the mean's variance over
#: 7×7 pixels (heavy-tailed noise: a pixel that has not yet drawn a rare bright path looks
#: certain, its neighbours that have tell), the denoiser's bias over 3×3 (it is local: edges)
VARIANCE_RADIUS, BIAS_RADIUS = 3, 1


def _window_mean(values: mi.Float, radius: int, width: int, height: int) -> mi.Float:
    """The mean of H·W·3 ``values`` over (2·radius+1)² pixels, per channel, clamped at the
    borders: a box filter, one pass per axis."""
    index = dr.arange(mi.UInt32, dr.width(values))
    pixel, channel = index // 3, index % 3
    x, y = mi.Int32(pixel % width), mi.Int32(pixel // width)
    for axis in (0, 1):
        total = mi.Float(0.0)
        for step in range(-radius, radius + 1):
            nx = dr.clip(x + step, 0, width - 1) if axis == 0 else x
            ny = dr.clip(y + step, 0, height - 1) if axis == 1 else y
            total += dr.gather(mi.Float, values, (mi.UInt32(ny) * width + mi.UInt32(nx)) * 3 + channel)
        values = total / (2 * radius + 1)
        dr.eval(values)
    return values


def _resolve(denoised: mi.Float, color: mi.Float, square: mi.Float, film: mi.Float, count: mi.Float, width: int,
             height: int) -> mi.Float:
    """The frozen resolve of :meth:`Accumulator.resolve`: per pixel and channel, the history's
    film-filtered mean ``f`` and the denoised ``d`` mixed as ``d + w (f − d)``, with
    ``w = b² / (b² + v)``: ``v`` the variance of the mean (from the running mean of the squares,
    raised by three standard errors of a sample variance of ``count`` frames: few frames give a
    variance that is often far too small), ``b² = (d − f)² − 2v`` (at least 0) the part of the
    difference that noise does not explain, i.e. the denoiser's bias; each averaged over a window
    (one pixel's estimate is too noisy: ``VARIANCE_RADIUS``, ``BIAS_RADIUS``). Fewer than 3
    frames: the denoised image."""
    index = dr.arange(mi.UInt32, 3 * width * height)
    frames = dr.gather(mi.Float, count, index // 3)
    dof = dr.maximum(frames - 1.0, 1.0)
    mean = dr.gather(mi.Float, color, index)
    var = dr.maximum(dr.gather(mi.Float, square, index) - mean * mean, 0.0) / dof * (1.0 + 3.0 * dr.sqrt(2.0 / dof))
    d, f = dr.gather(mi.Float, denoised, index), dr.gather(mi.Float, film, index)
    bias = dr.maximum(dr.square(d - f) - 2.0 * var, 0.0)
    var, bias = _window_mean(var, VARIANCE_RADIUS, width, height), _window_mean(bias, BIAS_RADIUS, width, height)
    w = dr.select((frames >= 3.0) & (bias > 0.0), bias / (bias + var), 0.0)
    return dr.fma(w, f - d, d)


class Accumulator:
    """The history of one image size, updated by one frozen function per frame, and the resolve
    of a denoised frame against it."""

    def __init__(self, freeze: bool = True, mark=None):
        """``mark(*arrays)``, if given, is called with the outputs of the update and of the
        resolve where their bodies run (unfrozen, or while ``dr.freeze`` records them): the stage
        clock's :meth:`~hybrid_integrator.pipeline.StageClock.mark`, which reads Dr.Jit's kernel
        history and so waits for the device. A replay does not run the body, so a frozen update
        adds no synchronization to the frame."""
        mark = mark or (lambda *arrays: None)

        def update(*args):
            means, count = _accumulate(*args)
            mark(*means, count)
            return means, count

        def resolve(*args):
            out = _resolve(*args)
            mark(out)
            return out

        self._update = dr.freeze(update) if freeze else update
        self._resolve = dr.freeze(resolve) if freeze else resolve

    def __call__(self, color: mi.TensorXf, film: mi.TensorXf | None, surface: Surface, camera,
                 history: History | None) -> tuple[mi.TensorXf, History]:
        """``color`` (H×W×3) with the reprojected history blended in; returns it and the new
        history. ``film``: the same frame in the film's filter where ``color`` is not (the
        denoiser's box-filtered input), else None."""
        height, width = color.shape[0], color.shape[1]
        flat = color.array
        film = None if film is None else film.array
        restart = history is None or (history.width, history.height) != (width, height)
        if restart or (history.film is None) != (film is None):  # a new size, or another filter
            count = dr.full(mi.Float, 1.0, width * height)
            means = [mi.Float(flat), flat * flat] + ([] if film is None else [mi.Float(film)])
        else:
            still = np.array_equal(history.world_to_clip, camera.world_to_clip)
            data = device_array(mi.Float, np.r_[history.world_to_clip.ravel(), STILL_FRAMES if still else MOTION_FRAMES,
                                                1.0 if still else 0.0].astype(np.float32))
            kept = [history.color, history.square] + ([] if film is None else [history.film])
            eye = device_array(mi.Float, np.asarray(camera.eye, np.float32))
            means, count = self._update(flat, film, surface, eye, kept, history.count, history.surface, data, width,
                                        height)
        new = History(color=means[0], square=means[1], film=means[2] if len(means) > 2 else None, count=count,
                      surface=surface, world_to_clip=camera.world_to_clip.copy(), eye=np.asarray(camera.eye).copy(),
                      width=width, height=height)
        return mi.TensorXf(means[0], (height, width, 3)), new

    def resolve(self, denoised: mi.TensorXf, history: History) -> mi.TensorXf:
        """The denoised history mixed with its film-filtered mean where the denoiser's bias
        outweighs the mean's noise (:func:`_resolve`): the denoiser helps a young history, and a
        long one converges to the film's image, not to the denoiser's."""
        film = history.color if history.film is None else history.film
        out = self._resolve(denoised.array, history.color, history.square, film, history.count, history.width,
                            history.height)
        return mi.TensorXf(out, (history.height, history.width, 3))
