"""Benchmarks: the paper's Tables 3 and 4 (§8), reproduced and extended with accuracy.

For one scene, after warm-up, as medians over ``frames`` repeated frames (one sample per pixel by
default, the real-time setting) with the backend synchronized, :func:`bench_scene` measures:

- ``raster``: the raster layer alone (``candidates=""``): its frame time (raster, deferred
  lighting, composition; nothing traced) is the paper's **DR** (deferred rendering time), shown
  beside the GPU time of its OpenGL pass alone (``gl_ms``, a GL timer query: the draw, or the
  compute shaders of ``raster="compute"``, the default on CUDA);
- ``rt-baseline``: ``primary="raytrace"``, every candidate traced: the paper's **RT**;
- ``hybrid``: raster primaries, every candidate traced: the paper's **Hybrid**; Gain = RT / Hybrid;
  and the **paired Gain** (:func:`paired_gain`): the two frames rendered in turn, one pair at a
  time, the median and quartiles of the pairs' ratios. The two blocks of frames behind Gain are
  measured a second apart, and a host whose speed drifts moves it by a few per cent between runs
  of the same code (issue 10, stop 29); a pair's frames share the drift; and the same paired Gain
  with two frames in flight (``frames_in_flight=2``, ``inflight.py``: the next frame issued while
  the GPU finishes the last, each frame timed by CUDA events), the sides in turns of
  :data:`TURN_BLOCK` frames;
- ``hybrid@X%``: ``budget_ms`` = X % of the all-candidates trace time, X in ``budgets`` (0 %:
  a budget that pays for nothing). Each budgeted run first renders the cost model's three probe
  frames (``budget.py``), which are warm-up, not measured;
- ``path@Nspp``: Mitsuba's ``path`` at 1, 2, 4 … spp (the time/error curve), each point replayed
  from a recording (``dr.freeze``, with the scene's variables as the hybrid's device pass takes
  them: ``compare.timed_path``), as the hybrid's frame is: the fastest way Mitsuba's ``path`` runs
  a real-time frame here, the same images as ``mi.render``'s; and ``path@equal-time``: the spp
  whose time, on the line through that curve's ends (a fixed cost plus a cost per sample), equals
  the hybrid's frame time, rendered and measured (the paper sets the hybrid against the Brigade
  path tracer, Table 4; at least 1 spp, so it can take longer); ``path`` is timed over ``frames``
  frames too, as far as they fit in a second (``compare.TIME_LIMIT_S``; at least 3: the
  many-sample points of the curve). Until issue 10's stop 49 the curve was timed through
  ``mi.render``, which traces the path kernel on the host at every call: 1.7–22 ms more per frame
  on the H200 (stop 46), time the hybrid's frozen frame does not spend;
- ``path@1spp, mi.render``: the 1-spp frame as Mitsuba users call it (``mi.render``), Table 3's
  ``path`` column beside the frozen one;
- with accuracy, also the rest of the time–error plane: the hybrid without the denoiser, with
  OIDN 'high', at 2 and 4 spp, with history; ``path+denoiser@Nspp``: ``path`` and its guides
  replayed from one recording, then the same denoiser at 'high' (``compare.timed_path_denoised``);
  ``path+denoiser 'fast'@1spp``: the same at the hybrid's default quality, 'fast', against the
  hybrid's default frame; and against each still-camera history, ``path`` given the total time of
  its frames (``path@history-time``), raw and with the denoiser the history's frames have
  (``path+denoiser@history-time``: the same spp; before issue 10's stop 49 only the raw one, a
  rival without the denoiser the history has);

The hybrid's frames are timed with ``stage_times=False`` (no kernel history: no CUDA events around
every launch, none read after the frame; ``path`` is timed without them too; until issue 10's
stop 50 the hybrid's timed frames carried them: 0.19-0.26 ms per frame on the H200); a budgeted
frame, whose cost model needs the trace's time, keeps them on every ``timing_interval``-th frame
(since stop 59; before, on all). The per-stage breakdown (device times, ``pipeline.FrameStats``)
of DR, the hybrid and the RT baseline comes from as many frames again with the stage times on, and
each budgeted row's from its own timed frames (where none of them was, from as many again with
the stage times on). The error of every image
against the ground truth (``path`` at ``gt_spp``, cached: ``compare.ground_truth``), FLIP, relative
MSE and ΔE2000 (``metrics.py``), is measured after all the timings, in parallel worker processes. A frame's
error is a random number (its samples, and for the hybrid the one sub-pixel offset all pixels of
a pass share): the error of a raw frame (not denoised) of at most 2 spp is the mean over
``ERROR_FRAMES`` frames (a hybrid run's last frames, ``path`` rendered with as many seeds); the
other rows, whose frames vary far less, are measured on one frame (HDR-FLIP takes seconds per
1280×720 image).

:func:`run` runs one child process per scene (``hybrid bench --single``): each scene gets a fresh
Dr.Jit state and the GPU memory of one scene is freed before the next. It then writes the JSON, the tables (Table 3 and Table 4
layout, beside the paper's figures) and one chart per scene: time per frame (log) against FLIP.
:func:`scaling` measures hybrid and RT baseline against triangle count (``procedural.py``) and
resolution.
"""
from __future__ import annotations

import argparse
import json
import math
import platform
import re
import statistics
import subprocess
import sys
import time
from collections.abc import Iterator
from dataclasses import asdict, dataclass, field, replace
from pathlib import Path

import mitsuba as mi
import numpy as np

from .compare import ground_truth, render_path, require_srgb, timed_path, timed_path_denoised
from .errors import HybridError, require_counts, require_fractions
from .frozen import require_frozen
from .metrics import errors_in_parallel
from .pipeline import HybridSettings, resolve_refine
from .primary import resolve_outline
from .procedural import procedural_scene, scene_triangles
from .raster.context import machine
from .raster.camera import sensor_to_world
from .raster.visibility import resolve_method
from .scene import load_scene

#: frames whose errors are averaged for a raw frame of few samples (module docstring)
ERROR_FRAMES = 4
#: a still camera's history is also measured after these many frames (and after all of them)
HISTORY_CHECKPOINTS = (1, 2, 4, 8, 16)
#: paths per primary hit of the second still-camera history (``secondary_spp``)
HISTORY_PATHS = 8
#: frames per side and round where frames in turn go by blocks, the first of each not measured: the
#: paired Gain with frames in flight, and the budget's RT / 50 % by blocks (scripts/budget_benchmark.py)
TURN_BLOCK = 5


def history_rival(method: str, denoised: bool = False) -> str:
    """The ``path`` row given the total time of a history row's frames (``denoised``: ``path`` +
    the hybrid's denoiser at the same spp)."""
    return ("path+denoiser" if denoised else "path") + "@history-time" + method.removeprefix("hybrid+history")


def error_frames(spp: int, raw: bool) -> int:
    """Frames whose errors a row averages (module docstring)."""
    return ERROR_FRAMES if raw and spp <= 2 else 1


#: the paper's Tables 3 and 4 (ms at 1280×720 on a GTX 570), by the project scene that stands in
PAPER = {
    "armadillo_glass": {"scene": "Armadillo", "vertices": 193737, "triangles": 380655, "DR": 3.134, "RT": 25.112,
                        "Hybrid": 18.518, "Gain": 1.35},
    "sponza_mirror": {"scene": "Sponza", "vertices": 145173, "triangles": 262187, "DR": 2.227, "RT": 66.667,
                      "Hybrid": 34.482, "Gain": 1.93},
    "showcase": {"scene": "Showcase", "vertices": 112603, "triangles": 224440, "DR": 2.336, "RT": 40.0,
                 "Hybrid": 23.255, "Gain": 1.72},
    "dining_room": {"scene": "Dining Room", "vertices": 386541, "triangles": 224954, "Brigade": 76.92,
                    "Hybrid": 28.283},
}
FIELDS = ("scene", "name", "variant", "device", "raster", "width", "height", "spp", "frames", "vertices", "triangles", "shapes",
          "ground_truth", "dr_ms", "gl_ms", "rt_ms", "path_1spp_ms", "path_1spp_frozen_ms", "hybrid_ms", "gain", "gain_paired", "all_candidates_trace_ms", "equal_time",
          "methods", "command")


@dataclass
class Measurement:
    """One method on one scene: its median frame time, its error, what it traced."""

    method: str
    kind: str  # raster | hybrid | rt | path
    time_ms: float  # median per frame
    frame_ms: list[float]  # every measured frame
    flip: float
    rel_mse: float
    delta_e2000: float
    spp: int
    stages_ms: dict[str, float] = field(default_factory=dict)  # median per stage (hybrid kinds)
    budget_ms: float | None = None
    pixels_traced: float | None = None  # median per frame
    secondary_rays: float | None = None  # median per frame
    frames_accumulated: int | None = None  # temporal accumulation: frames in the measured image


def load_bench_scene(spec: str, params: dict) -> tuple[mi.Scene, str]:
    """A scene file, or ``procedural:TRIANGLES``; returns the scene and its short name. Of the
    ``params``, each file gets those it takes."""
    if spec.startswith("procedural:"):
        count = spec.split(":", 1)[1]
        try:
            triangles = int(float(count))
        except ValueError:
            raise HybridError(f"procedural scene: '{count}' is not a number of triangles "
                              "(procedural:TRIANGLES, e.g. procedural:1e6)") from None
        keys = {k: int(v) for k, v in params.items() if k in ("resx", "resy", "spp", "max_depth")}
        return procedural_scene(triangles, **keys), f"procedural_{triangles}"
    # -D applies to the scenes that take it: Mitsuba refuses parameters a file does not use
    text = Path(spec).read_text(errors="replace") if Path(spec).is_file() else ""
    # (a whole name: ``$res`` is not used by a file that names only ``$resx``)
    used = {k: v for k, v in params.items() if re.search(rf"\${re.escape(k)}(?![A-Za-z0-9_])", text)}
    return load_scene(spec, **used), Path(spec).stem


def path_cameras(scene_file: str | Path, frames: int) -> list | None:
    """``frames`` cameras along the camera path of ``scene_file`` (``NAME_path.json`` beside it:
    look-at keyframes, ``api.camera_path``), or None where it has none."""
    from .api import camera_path

    path = Path(scene_file)
    keyframes = path.with_name(path.stem + "_path.json")
    return camera_path(json.loads(keyframes.read_text())["keyframes"], frames) if keyframes.is_file() else None


@dataclass
class TurnScene:
    """A scene made ready for :func:`frames_in_turn` (:func:`turn_scene`)."""

    scene: mi.Scene
    name: str
    cameras: list | None  # its camera path, one pose per frame of a round (None: the sensor's pose)
    all_candidates_trace_ms: float  # the hybrid's median trace time, every candidate traced (device ms)


def turn_scene(spec: str, params: dict, poses: int) -> TurnScene:
    """A scene for frames in turn, as the GPU probes of issue 10 take it: loaded as the bench loads
    it (:func:`load_bench_scene`), ``poses`` cameras along its path where it has one
    (:func:`path_cameras`; :func:`turn_poses` says how many), and the all-candidates hybrid's median trace time, from 40 frames
    along that path (or 12 from its sensor), the first two not counted: what a budget's
    fractions are of."""
    import hybrid_integrator as hi

    scene, name = load_bench_scene(spec, params)
    along = path_cameras(spec, 40)
    frames = (hi.render_sequence(scene, along, spp=1, layers=False) if along is not None
              else [hi.render(scene, spp=1, seed=k, layers=False) for k in range(12)])
    return TurnScene(scene=scene, name=name, cameras=path_cameras(spec, poses),
                     all_candidates_trace_ms=statistics.median(f.stats.times_ms["trace"] for f in frames[2:]))


def turn_arguments(description: str, budgets=(0.5,), block: int | None = None) -> argparse.ArgumentParser:
    """The command line that the GPU probes of frames in turn share (docs/results/gpu/issue10): the
    scene files, ``--variant``, ``--frames`` measured per side, ``--budgets`` (fractions of the
    all-candidates trace time, :func:`turn_scene`), ``-D NAME=VALUE`` scene parameters (``defines``:
    name, value pairs) and, given a default ``block``, ``--block`` frames per side and round."""
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("scenes", nargs="+", type=Path)
    parser.add_argument("--variant", default="llvm_ad_rgb")
    parser.add_argument("--frames", type=int, default=40, help="measured frames per side")
    parser.add_argument("--budgets", type=float, nargs="*", default=list(budgets), help="fractions of the hybrid's trace time")
    parser.add_argument("-D", dest="defines", action="append", default=[], type=lambda d: tuple(d.split("=", 1)),
                        help="scene parameter NAME=VALUE")
    if block is not None:
        parser.add_argument("--block", type=int, default=block, help="frames per side and round")
    return parser


def turn_budgets(args: argparse.Namespace, warmup: int) -> Iterator[tuple[TurnScene, float, float]]:
    """A probe's scenes and budgets from its :func:`turn_arguments` (the variant set and the
    plugin registered): each scene made ready (:func:`turn_scene`, with the poses
    :func:`turn_poses` gives for ``warmup`` rounds of ``args.block`` frames; its all-candidates trace
    time printed), then each fraction of ``args.budgets`` as (scene, fraction, budget ms)."""
    require_fractions("--budgets", args.budgets)
    for path in args.scenes:
        ready = turn_scene(str(path), dict(args.defines), turn_poses(args.frames, warmup, args.block))
        print(f"{ready.name}: all-candidates trace {ready.all_candidates_trace_ms:.3f} ms", flush=True)
        for fraction in args.budgets:
            yield ready, fraction, fraction * ready.all_candidates_trace_ms


def turn_poses(frames: int, warmup: int = 3, block: int = 1) -> int:
    """The camera poses :func:`frames_in_turn` takes for ``frames`` measured frames per side:
    one per frame of a side's rounds, warm-up rounds included."""
    return (warmup + -(-frames // max(block - 1, 1))) * block


def frames_in_turn(scene: mi.Scene, sides: dict[str, dict], frames: int, spp: int, seed: int,
                   warmup: int = 3, before=None, block: int = 1, cameras=None,
                   host_speed: bool = False, after=None) -> dict[str, list[dict]]:
    """One integrator per entry of ``sides`` (name → properties), each carrying its own state,
    rendering ``warmup`` + ``frames`` frames in turn (seed ``seed + k`` for all in round k; the
    order rotates from round to round, so that none always follows another); ``before(name)``, if
    given, is called before each of a side's frames (a probe's stand-ins). Returns, per side, the
    ``times_ms`` of its measured frames.

    ``block`` > 1: in each round a side renders ``block`` frames in a row, the first of which is
    not measured: with ``frames_in_flight=2`` it starts while the GPU still runs the other side's
    last frame (and the hybrid's raster pass drawn ahead for a frame of its own that does not come
    next); ``frames`` measured frames per side, in rounds of ``block`` − 1 (the last round may
    measure fewer). ``warmup`` rounds are not measured.

    ``cameras``: a camera path (``api.camera_path``), one pose per frame of a side's round
    (``block`` per round, warm-up rounds included): every side renders the j-th frame of round k
    from pose k·``block`` + j, told the next pose (as ``api.render_sequence`` tells a frame: the
    raster pass drawn ahead), so that each side's frames move along the path as in a sequence of
    its own (:func:`turn_poses` poses are needed); the sensor's own pose is restored after
    (``api.posed``). Without it, the sensor's pose throughout.

    ``after(name, at, result)``, if given, is called after each measured frame (outside its time)
    with its pose's index on the path (or the frame's number in its side's rounds) and its
    ``HybridResult``: a probe's images and statistics.

    ``host_speed``: before each frame (outside its time) the host's speed is taken
    (:func:`host_loop_ms`), and each measured frame's entry has it as ``host_loop``
    (:func:`paired_ratio_by_host` splits a ratio by it)."""
    from .api import _integrator, finish, posed
    from .raster.camera import camera_pose

    integrators = {name: _integrator(dict(props)) for name, props in sides.items()}
    times: dict[str, list[dict]] = {name: [] for name in sides}
    order = list(sides)
    rounds = turn_poses(frames, warmup, block) // block
    poses = None if cameras is None else [camera_pose(c) for c in cameras]
    if poses is not None and len(poses) < rounds * block:
        raise HybridError(f"frames_in_turn: {len(poses)} camera poses for {rounds} rounds of {block} frames "
                          "(warm-up included)")
    with posed(scene.sensors()[0]) as place:
        for k in range(rounds):
            for name in order:
                for j in range(block):
                    at, upcoming = k * block + j, None  # the frame's pose on the path
                    if poses is not None:
                        place(poses[at])
                        upcoming = poses[at + 1] if at + 1 < len(poses) else None
                    if before is not None:
                        before(name)
                    # before every frame, measured or not, so that each follows the same host work
                    loop = host_loop_ms() if host_speed else None
                    result = integrators[name].render_result(scene, seed=seed + at, spp=spp, layers=False,
                                                             next_camera=upcoming)
                    if k >= warmup and (block == 1 or j > 0) and len(times[name]) < frames:
                        entry = result.stats.times_ms
                        times[name].append(entry if loop is None else dict(entry, host_loop=loop))
                        if after is not None:
                            after(name, at, result)
            order = order[1:] + order[:1]
        finish(scene)  # the last frame's times, with frames_in_flight=2
    return times


def paired_ratio(times: dict[str, list[dict]], numerator: str, denominator: str, block: int = 1,
                 keep: list[bool] | None = None) -> dict:
    """``numerator``'s frame time / ``denominator``'s, pair by pair, of frames rendered in turn
    (:func:`frames_in_turn`'s ``times``): the median ratio, its quartiles, the pairs, and each
    side's median frame time. ``block`` > 1: a pair is the two sides' median frames of a round.
    ``keep``: per round (pair), whether it counts (default: all)."""
    total = {side: [t["total"] for t in times[side]] for side in (numerator, denominator)}
    per_round = max(block - 1, 1)
    rounds = {side: [statistics.median(v[i:i + per_round]) for i in range(0, len(v), per_round)]
              for side, v in total.items()}
    if keep is not None:
        rounds = {side: [r for r, k in zip(v, keep) if k] for side, v in rounds.items()}
        total = {side: [t for i, t in enumerate(v) if keep[i // per_round]] for side, v in total.items()}
    ratios = np.asarray(rounds[numerator]) / np.asarray(rounds[denominator])
    q25, median, q75 = (float(q) for q in np.percentile(ratios, [25, 50, 75]))
    return {"median": median, "q25": q25, "q75": q75, "pairs": int(len(ratios)),
            f"{numerator}_ms": statistics.median(total[numerator]),
            f"{denominator}_ms": statistics.median(total[denominator])}


#: a host whose loop (:func:`host_loop_ms`) takes at most this × the run's fastest counts as fast
FAST_HOST = 1.25


def host_loop_ms() -> float:
    """The host CPU's speed now, in ms: the best of three runs of a fixed pure-Python loop (2,500
    additions; ~0.1 ms on the GPU machines' CPUs at their fast speed). Those machines' CPUs run at
    two speeds about 1.7× apart, each CPU slow for runs of a few ms to a second, 31-97 % of the
    time on four CPUs sampled for 10 s (docs/results/gpu/issue10/stop58): a frame bound by its host's work takes as long as the
    CPU it lands on allows, one bound by the GPU hides it."""
    best = math.inf
    for _ in range(3):
        start = time.perf_counter()
        total = 0
        for i in range(2500):
            total += i * i
        best = min(best, time.perf_counter() - start)
    return best * 1e3


def host_loops(n: int = 21) -> dict[str, float]:
    """``n`` :func:`host_loop_ms` in a row: their fastest and median ms (a bench scene's report
    takes them at its start and its end, so that a run on slow CPUs shows as one)."""
    loops = [host_loop_ms() for _ in range(n)]
    return {"min_ms": min(loops), "median_ms": statistics.median(loops)}


def fast_hosts(loops: list[list[float]], fast: float = FAST_HOST) -> tuple[list[list[bool]], float]:
    """Per list of host loops (:func:`host_loop_ms`), whether each was taken on a fast host: within
    ``fast`` × the fastest loop of all the lists; and that fastest loop (ms)."""
    fastest = min(min(v) for v in loops if v)
    return [[x <= fast * fastest for x in v] for v in loops], fastest


def paired_ratio_by_host(times: dict[str, list[dict]], numerator: str, denominator: str, block: int = 1,
                         fast: float = FAST_HOST) -> dict:
    """:func:`paired_ratio` apart for the pairs rendered on a fast host and on a slow one, from
    frames in turn with ``host_speed`` (:func:`frames_in_turn`): a pair (a round, with ``block`` >
    1) is fast where the host loop before each of its measured frames took at most ``fast`` × the
    fastest of them all. Returns ``fast`` and ``slow`` (each :func:`paired_ratio`'s, or None
    where no pair is), the share of fast pairs and the fastest loop (ms)."""
    per_round = max(block - 1, 1)
    frames, fastest = fast_hosts([[t["host_loop"] for t in times[side]] for side in (numerator, denominator)], fast)
    pairs = min(-(-len(v) // per_round) for v in frames)
    is_fast = [all(all(v[r * per_round:(r + 1) * per_round]) for v in frames) for r in range(pairs)]
    split = {label: paired_ratio(times, numerator, denominator, block, keep=[f == want for f in is_fast])
             if any(f == want for f in is_fast) else None for label, want in (("fast", True), ("slow", False))}
    return split | {"fast_share": sum(is_fast) / max(pairs, 1), "fastest_loop_ms": fastest}


def paired_gain(scene: mi.Scene, properties: dict, frames: int, spp: int, seed: int, warmup: int = 3,
                block: int = 1) -> dict:
    """RT baseline / all-candidates hybrid, frame by frame (module docstring): the two integrators
    with these ``properties``, one with ``primary="raytrace"``, render in turn
    (:func:`frames_in_turn`). Returns the median ratio of the measured pairs, its quartiles, and
    each side's median frame time (:func:`paired_ratio`). ``block`` > 1 (frames in flight): the
    sides take turns by blocks of frames, and a pair is the two sides' median frames of a round."""
    times = frames_in_turn(scene, {"hybrid": properties, "rt": dict(properties, primary="raytrace")}, frames, spp,
                           seed, warmup, block=block)
    return paired_ratio(times, "rt", "hybrid", block)


def bench_scene(spec: str, params: dict | None = None, frames: int = 5, spp: int = 1, gt_spp: int = 1024,
                max_path_spp: int = 64, budgets=(0.0, 0.25, 0.5, 0.75), seed: int = 0, freeze: bool = True,
                accuracy: bool = True, **properties) -> dict:
    """Every measurement of the module docstring on one scene; ``properties`` are the hybrid
    integrator's (``max_depth`` is shared with ``path`` and the ground truth). Without
    ``accuracy`` (a point of a scaling curve, or a timing run): no ground truth, errors NaN, and
    no equal-time ``path``."""
    import hybrid_integrator as hi

    params = dict(params or {})
    require_counts("bench", frames=frames, spp=spp, gt_spp=gt_spp, max_path_spp=max_path_spp)
    require_fractions("bench", budgets)
    scene, name = load_bench_scene(spec, params)
    host_start = host_loops()
    max_depth = int(properties.get("max_depth", -1))
    reference, gt_file, cached = None, None, False
    if accuracy:
        require_srgb("bench", scene, **properties)
        reference, gt_file, cached = ground_truth(spec if not spec.startswith("procedural:") else name, scene, params,
                                                  gt_spp, max_depth)
    sensor = scene.sensors()[0]
    camera = sensor_to_world(sensor)
    rows: list[Measurement] = []
    images: list = []  # each row's images: their errors are measured after every timing
    nan = float("nan")

    # every hybrid frame's properties: timed without the kernel history (module docstring)
    base = {"freeze": freeze, "stage_times": False, **properties}

    def hybrid(method: str, kind: str, warmup: int, frame_spp: int | None = None, profile: bool = False,
               **extra) -> Measurement:
        """A row of hybrid frames, timed without stage times (``stage_times=False``, as a
        renderer ships the frame; a budget's frames time theirs); ``profile``: its stages' device
        times from as many frames again with ``stage_times=True``."""
        props = {**base, **extra}
        every = hi.render_sequence(scene, [camera] * (warmup + frames), spp=frame_spp or spp, seed=seed,
                                   layers=False, **props)
        results = every[warmup:]
        profiled = [r.stats for r in results if r.stats.stages_timed]
        if profile and not profiled:
            profiled = [r.stats for r in hi.render_sequence(scene, [camera] * (warmup + frames), spp=frame_spp or spp,
                                                            seed=seed, layers=False,
                                                            **dict(props, stage_times=True))[warmup:]]
        # read back only where errors are measured; an accumulating history is measured at its end
        raw = not props.get("denoise", True) and not extra.get("temporal")
        images.append([r.image for r in results[-error_frames(frame_spp or spp, raw):]])
        stats = [r.stats for r in results]
        for s in stats:
            require_frozen(s.frozen_inputs, f"bench: {method}")
        row = Measurement(method, kind, statistics.median(s.times_ms["total"] for s in stats),
                          [s.times_ms["total"] for s in stats], nan, nan, nan, frame_spp or spp,
                          {k: statistics.median(s.times_ms[k] for s in profiled) for k in profiled[0].times_ms}
                          if profiled else {},
                          extra.get("budget_ms"), statistics.median(s.pixels_traced for s in stats),
                          statistics.median(s.secondary_rays for s in stats),
                          warmup + frames if extra.get("temporal") else None)
        rows.append(row)
        if extra.get("temporal"):  # the history on its way: the same frames, measured earlier
            for n in (n for n in HISTORY_CHECKPOINTS if n < len(every)):
                rows.append(replace(row, method=f"{method}@{n}", frames_accumulated=n))
                images.append([every[n - 1].image])
        return row

    # warm-up: three frames (the first compiles, the second may record frozen kernels again with the
    # seed made opaque); a budgeted run's first three frames are the cost model's probes
    raster = hybrid("raster", "raster", 3, profile=True, candidates="")
    everything = hybrid("hybrid", "hybrid", 3, profile=True)
    rt = hybrid("rt-baseline", "rt", 3, profile=True, primary="raytrace")
    paired = paired_gain(scene, base, frames, spp, seed)
    # the same two frames with the next frame issued while the GPU finishes the last (inflight.py):
    # blocks of five frames in turn, four measured
    in_flight = paired_gain(scene, {**base, "frames_in_flight": 2}, frames, spp, seed,
                            block=TURN_BLOCK)
    trace_all = everything.stages_ms["trace"]
    for fraction in budgets:  # 0 % still needs a positive budget (0 means unlimited)
        # its stages from its timed frames (every ``timing_interval``-th), else from as many again
        hybrid(f"hybrid@{fraction:.0%}", "hybrid", 5, profile=True, budget_ms=max(fraction * trace_all, 1e-6))
    if accuracy:  # the rest of the time–error plane: no denoiser, more samples, history
        hybrid("hybrid, no denoiser", "hybrid", 3, denoise=False)
        hybrid("hybrid, denoiser 'high'", "hybrid", 3, denoise_quality="high")
        for s in (2, 4):
            hybrid(f"hybrid {s * spp} spp", "hybrid", 3, frame_spp=s * spp)
        # path + denoiser below uses the 'high' filter too: the same denoiser on both sides
        hybrid(f"hybrid {2 * spp} spp, denoiser 'high'", "hybrid", 3, frame_spp=2 * spp, denoise_quality="high")
        histories = [hybrid("hybrid+history", "hybrid", 3, temporal=True),
                     hybrid(f"hybrid+history, {HISTORY_PATHS} paths/hit", "hybrid", 3, temporal=True,
                            secondary_spp=HISTORY_PATHS)]

    def path(method: str, path_spp: int, frozen: bool = True) -> Measurement:
        image, times = timed_path(scene, path_spp, max_depth, seed, repeats=frames, frozen=frozen)
        images.append([image] + [render_path(scene, path_spp, max_depth, seed + k)
                                 for k in range(1, error_frames(path_spp, raw=True))])
        rows.append(Measurement(method, "path", statistics.median(times), times, nan, nan, nan, path_spp))
        return rows[-1]

    def path_denoised(method: str, path_spp: int, quality: str) -> None:
        image, times = timed_path_denoised(scene, path_spp, max_depth, seed, repeats=frames, quality=quality)
        images.append([image])
        rows.append(Measurement(method, "path+denoiser", statistics.median(times), times, nan, nan, nan, path_spp))

    equal_time = None
    # the whole curve where errors are measured; its first point (the 1-spp time) always
    curve = [path(f"path@{s}spp", s) for s in (2 ** k for k in range(max_path_spp.bit_length() if accuracy else 1))]
    called = path("path@1spp, mi.render", 1, frozen=False)
    if accuracy:
        # equal time: the spp whose time fits the hybrid's frame, by a line through the curve's ends
        first, last = curve[0], curve[-1]
        per_spp = max((last.time_ms - first.time_ms) / max(last.spp - first.spp, 1), 0.1 * last.time_ms / last.spp)
        fixed = max(first.time_ms - per_spp * first.spp, 0.0)
        # at most 16× the curve's last point: further out the line is a guess
        path("path@equal-time", int(np.clip((everything.time_ms - fixed) / per_spp, 1, 16 * last.spp)))
        # each history's frames, all of them, against path given their total time: raw (the
        # paper's rival, a path tracer) and with the denoiser the history's frames have, if any, at
        # the same spp (its guides and filter add a few ms to that time)
        quality = properties.get("denoise_quality", HybridSettings.denoise_quality)
        for history in histories:
            total = history.time_ms * history.frames_accumulated
            rival_spp = int(np.clip((total - fixed) / per_spp, 1, 16 * last.spp))
            path(history_rival(history.method), rival_spp)
            if properties.get("denoise", HybridSettings.denoise):
                path_denoised(history_rival(history.method, denoised=True), rival_spp, quality)
        # path + the same denoiser: 'high' at 1, 2, 4 spp; 'fast', the hybrid's default, at 1 spp
        for s in (1, 2, 4):
            path_denoised(f"path+denoiser@{s}spp", s, "high")
        path_denoised("path+denoiser 'fast'@1spp", 1, "fast")
        # the errors after every timing: their workers take every core
        tests = [np.array(image, dtype=np.float32)[..., :3] for row in images for image in row]
        errors = iter(errors_in_parallel(tests, [reference] * len(tests)))
        for i, row in enumerate(images):
            mine = [next(errors) for _ in row]
            rows[i] = replace(rows[i], **{k: float(np.mean([getattr(e, k) for e in mine]))
                                          for k in ("flip", "rel_mse", "delta_e2000")})
        equal = next(row for row in rows if row.method == "path@equal-time")
        equal_time = {"spp": equal.spp, "time_ms": equal.time_ms, "flip": equal.flip}

    film = sensor.film().size()
    meshes = [sh for sh in scene.shapes() if isinstance(sh, mi.Mesh)]
    method = resolve_method(properties.get("raster", "auto"))
    return {
        "scene": spec, "name": name, "variant": mi.variant(), "device": _device(),
        "host_loop_ms": {"start": host_start, "end": host_loops()},
        "raster": method, "refine": _refine(properties.get("refine", "auto")),
        "outline": resolve_outline(properties.get("outline", "auto"), method), "width": int(film[0]),
        "height": int(film[1]), "spp": spp, "frames": frames,
        "vertices": sum(int(m.vertex_count()) for m in meshes), "triangles": scene_triangles(scene),
        "shapes": len(scene.shapes()),
        "ground_truth": {"integrator": "path", "spp": gt_spp, "max_depth": max_depth,
                         "file": None if gt_file is None else str(gt_file), "cached": cached},
        "dr_ms": raster.time_ms, "gl_ms": raster.stages_ms.get("gl", 0.0), "rt_ms": rt.time_ms,
        "path_1spp_ms": called.time_ms, "path_1spp_frozen_ms": curve[0].time_ms,
        "hybrid_ms": everything.time_ms, "gain": rt.time_ms / everything.time_ms, "gain_paired": paired, "gain_in_flight": in_flight, "all_candidates_trace_ms": trace_all,
        "equal_time": equal_time, "methods": [asdict(r) for r in rows], "command": None,  # set by run()
    }


def _device() -> str:
    m = machine()
    return f"{platform.node()}: GL {m['gl_renderer']}, {m['cpu']}"


# --- running scenes in child processes, tables and charts ---------------------------------------

def _child(spec: str, out: Path, options: list[str]) -> dict:
    out.parent.mkdir(parents=True, exist_ok=True)
    cmd = [sys.executable, "-m", "hybrid_integrator.cli", "bench", "--single", str(out), *options, spec]
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        raise HybridError(f"bench of {spec} failed (exit {done.returncode}):\n{done.stderr[-3000:]}")
    return json.loads(out.read_text())


@dataclass(frozen=True)
class Workers:
    """Where the bench's child jobs run: one after another here (``ray`` None), or as Ray tasks
    (``ray``: "auto" starts a local Ray instance, else a cluster's address), each holding
    ``gpus`` GPUs (Ray sets ``CUDA_VISIBLE_DEVICES``, which the child inherits) or one CPU."""

    ray: str | None = None
    gpus: float = 0.0


def _children(jobs: list[tuple[str, Path, list[str]]], workers: Workers, desc: str) -> list[dict]:
    """The reports of ``jobs`` (``(spec, json file, options)``, each one child process: ``_child``),
    in order. On Ray, jobs run at once as far as the resources go (one per GPU with ``gpus`` = 1);
    ground truths are shared through the disk cache (``compare.ground_truth``: on a cluster, point
    ``$HYBRID_CACHE`` at a shared folder). Jobs that share a device disturb each other's timings:
    give each a GPU, or one machine each."""
    from tqdm import tqdm

    bar = tqdm(total=len(jobs), desc=desc, unit="job")
    if workers.ray is None:
        reports = []
        for job in jobs:
            reports.append(_child(*job))
            bar.update()
        bar.close()
        return reports
    from .frames import start_ray

    ray = start_ray("bench --ray needs Ray: pip install 'hybrid_integrator[ray]'",
                    None if workers.ray == "auto" else workers.ray)
    task = ray.remote(num_gpus=workers.gpus, num_cpus=0 if workers.gpus else 1, max_retries=2)(_child)
    pending = {task.remote(*job): k for k, job in enumerate(jobs)}
    reports: list[dict | None] = [None] * len(jobs)
    waiting = list(pending)
    while waiting:
        done, waiting = ray.wait(waiting, num_returns=1)
        reports[pending[done[0]]] = ray.get(done[0])
        bar.update()
    bar.close()
    return reports


def run(specs: list[str], out_dir: Path, options: list[str], command: str, workers: Workers = Workers()) -> list[dict]:
    """Bench each scene in its own process (see module docstring; on Ray workers with
    ``workers``); write ``out_dir/NAME.json``, ``bench.json``, ``bench.md`` and, where the errors
    were measured (not ``--no-accuracy``), the time–FLIP chart ``NAME.png``."""
    names = [spec.replace(":", "_") if spec.startswith("procedural:") else Path(spec).stem for spec in specs]
    reports = _children([(spec, out_dir / f"{name}.json", options) for spec, name in zip(specs, names)], workers,
                        "scenes")
    for name, report in zip(names, reports):
        report["command"] = command
        (out_dir / f"{name}.json").write_text(json.dumps(report, indent=2))
        if any(math.isfinite(m["flip"]) for m in report["methods"]):
            chart(report, out_dir / f"{name}.png")
    (out_dir / "bench.json").write_text(json.dumps(reports, indent=2))
    (out_dir / "bench.md").write_text(tables(reports, [command]) + "\n")
    return reports


def _refine(refine: str) -> str:
    """The ``refine`` property as the report names it: ``auto`` with what it means on this variant."""
    resolved = resolve_refine(refine)
    return "auto: trace where a frame traces an object, else primary" if refine == "auto" and resolved == "trace" \
        else resolved


def _ms(value) -> str:
    """A time for the tables; reports written before it was measured have none."""
    return "–" if value is None else f"{value:.2f}"


def _host_line(reports: list[dict]) -> str:
    """The host's speed during each scene's run (:func:`host_loops` at its start and end)."""
    def loops(h: dict) -> str:
        return f"{h['min_ms']:.3f} / {h['median_ms']:.3f}"
    return ("Host speed (`bench.host_loop_ms`, fastest / median of 21 at a scene's start; at its end; ~0.1 ms on "
            "a fast CPU of the GPU machines, whose CPUs run at two speeds): "
            + "; ".join(f"{r['name']} {loops(r['host_loop_ms']['start'])}, {loops(r['host_loop_ms']['end'])} ms"
                        for r in reports) + "  ")


def tables(reports: list[dict], commands: list[str]) -> str:
    """Table 3 and Table 4 layouts beside the paper's figures, then every method per scene."""
    first = reports[0]
    lines = [f"# Benchmarks: {first['variant']}, {first['width']}×{first['height']}, {first['spp']} spp per frame",
             "", *(f"Command: `{c}`  " for c in commands), f"Machine: {first['device']}  ",
             *([_host_line(reports)] if all("host_loop_ms" in r for r in reports) else []),
             f"Raster pass: {first.get('raster', 'draw')} (`raster/visibility.py`); refined pixels: "
             f"refine={first.get('refine', 'primary')} (`pipeline.resolve_refine`), "
             f"outline={first.get('outline', 'silhouettes')} (`primary.OUTLINES`)  ",
             f"Medians over {first['frames']} frames after warm-up; times in ms per frame; errors against "
             f"`path` at {first['ground_truth']['spp']} spp (max_depth {first['ground_truth']['max_depth']}). "
             "The hybrid's frames are timed with `stage_times=false` (no kernel history; a budget keeps it on "
             "every `timing_interval`-th frame, its cost model's); the device ms per stage of DR, the hybrid and "
             "the RT baseline are from as many frames again with it on, those of a budget from its own timed "
             "frames, other rows have none.", "",
             "## Table 3 layout: hybrid against pure ray tracing", "",
             "DR: a frame that traces nothing (raster, deferred lighting, composition); GL: its OpenGL pass "
             "alone (GPU time; the compute-shader rasterizer on CUDA, `raster/compute.py`); `path`: Mitsuba's path tracer at 1 spp on the same scene "
             "(`mi.render`; frozen: replayed from a recording, `dr.freeze`, as the hybrid's frame is).", "",
             "Gain: RT / Hybrid of the two rows; paired: the same two frames rendered in turn, the median "
             "ratio of the pairs [quartiles] (`bench.paired_gain`); 2 in flight: the same with "
             "`frames_in_flight=2` (`inflight.py`), in turns of five frames, four measured: the median ratio "
             "of the turns' medians, and the two sides' median frames (device time, CUDA events).", "",
             "| scene | vertices | triangles | shapes | DR | GL pass | RT | Hybrid | Gain | Gain, paired | "
             "Gain, 2 in flight (Hybrid / RT ms) | `path` 1 spp | `path` 1 spp, frozen | paper (GTX 570): DR / RT / Hybrid / Gain |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in reports:
        p = PAPER.get(r["name"], {})
        paper = f"{p['DR']} / {p['RT']} / {p['Hybrid']} / {p['Gain']}" if "RT" in p else "–"
        g = r.get("gain_paired")  # reports written before it was measured have none
        paired = f"{g['median']:.3f} [{g['q25']:.3f}, {g['q75']:.3f}]" if g else "–"
        f = r.get("gain_in_flight")
        flight = f"{f['median']:.3f} ({f['hybrid_ms']:.2f} / {f['rt_ms']:.2f})" if f else "–"
        lines.append(f"| {r['name']} | {r['vertices']:,} | {r['triangles']:,} | {r['shapes']} | {r['dr_ms']:.2f} | "
                     f"{r['gl_ms']:.2f} | {r['rt_ms']:.2f} | {r['hybrid_ms']:.2f} | {r['gain']:.2f} | {paired} | "
                     f"{flight} | {r['path_1spp_ms']:.2f} | {_ms(r.get('path_1spp_frozen_ms'))} | {paper} |")
    if all(r["equal_time"] for r in reports):
        lines += _table4(reports)
    for r in reports:
        lines += ["", f"## {r['name']}: every method", "",
                  "| method | ms per frame | FLIP | rel. MSE | ΔE2000 | spp | pixels traced | secondary rays | device ms: GL / raster / lighting / select / trace / compose | host issue ms |",
                  "|---|---|---|---|---|---|---|---|---|---|"]
        for m in r["methods"]:
            st = m["stages_ms"]
            stages = " / ".join(f"{st.get(k, 0.0):.2f}" for k in ("gl", "raster", "lighting", "select", "trace", "compose")) if st else ""
            traced = "" if m["pixels_traced"] is None else f"{m['pixels_traced']:,.0f}"
            rays = "" if m["secondary_rays"] is None else f"{m['secondary_rays']:,.0f}"
            issue = f"{st['issue']:.2f}" if st else ""
            lines.append(f"| {m['method']} | {m['time_ms']:.2f} | {m['flip']:.4f} | {m['rel_mse']:.4f} | "
                         f"{m['delta_e2000']:.2f} | {m['spp']} | {traced} | {rays} | {stages} | {issue} |")
    return "\n".join(lines)


def _table4(reports: list[dict]) -> list[str]:
    lines = ["", "## Table 4 layout: hybrid against a path tracer at equal time", "",
              "| scene | Hybrid ms | Hybrid FLIP | path spp at equal time | path ms | path FLIP | paper: Brigade / Hybrid ms |",
              "|---|---|---|---|---|---|---|"]
    for r in reports:
        h = next(m for m in r["methods"] if m["method"] == "hybrid")
        p = PAPER.get(r["name"], {})
        paper = f"{p['Brigade']} / {p['Hybrid']}" if "Brigade" in p else "–"
        lines.append(f"| {r['name']} | {h['time_ms']:.1f} | {h['flip']:.4f} | {r['equal_time']['spp']} | "
                     f"{r['equal_time']['time_ms']:.1f} | {r['equal_time']['flip']:.4f} | {paper} |")
    return lines


def chart(report: dict, path: Path) -> None:
    """Time per frame (log) against FLIP: one point per method, the budgets and path's spp as curves."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    methods = report["methods"]
    fig, ax = plt.subplots(figsize=(10.5, 4.8))
    by_name = {m["method"]: m for m in methods}
    budgets = [m for m in methods if m["method"].startswith("hybrid@")] + [by_name[k] for k in ("hybrid",) if k in by_name]
    curves = {"hybrid, budget 0…100 %": (budgets, lambda m: m["method"].split("@")[1] if "@" in m["method"] else "100%"),
              "hybrid, spp per frame": ([by_name[k] for k in by_name if k == "hybrid" or k.endswith(" spp") and k.startswith("hybrid ")],
                                        lambda m: f"{m['spp']}"),
              "Mitsuba path, 1…N spp (frozen)": ([m for m in methods if re.fullmatch(r"path@\d+spp", m["method"])],
                                        lambda m: m["method"].split("@")[1]),
              "hybrid + OIDN 'high' (as path + denoiser)": (
                  [m for m in methods if m["method"].endswith("denoiser 'high'") and m["method"].startswith("hybrid")],
                  lambda m: f"{m['spp']}"),
              "path + denoiser ('high')": ([m for m in methods if m["method"].startswith("path+denoiser@")],
                                           lambda m: m["method"].split("@")[1])}
    for label, (ms, tag) in curves.items():
        if not ms:
            continue
        ms = sorted(ms, key=lambda m: m["time_ms"]) if label.startswith(("Mitsuba", "path")) else ms
        ax.plot([m["time_ms"] for m in ms], [m["flip"] for m in ms], "o-", label=label)
        for m in ms:
            ax.annotate(tag(m), (m["time_ms"], m["flip"]), fontsize=7, xytext=(3, 3), textcoords="offset points")
    for name, marker in (("raster", "s"), ("hybrid, no denoiser", "P"), ("rt-baseline", "^"), ("path@equal-time", "*"),
                         ("path@1spp, mi.render", "v"), ("path+denoiser 'fast'@1spp", "D")):
        m = by_name.get(name)
        if m is None:
            continue
        ax.plot([m["time_ms"]], [m["flip"]], marker, markersize=9, label=f"{name} ({m['spp']} spp)" if name == "path@equal-time" else name)
    for name, history in by_name.items():  # a still camera: its frames together, against path given their time
        if not name.startswith("hybrid+history") or "@" in name:
            continue
        steps = sorted([m for m in methods if m["method"].startswith(name + "@")] + [history],
                       key=lambda m: m["frames_accumulated"])
        line, = ax.plot([m["time_ms"] * m["frames_accumulated"] for m in steps], [m["flip"] for m in steps], "X--",
                        markersize=7, label=f"{name.replace('hybrid+history', 'hybrid + history')}: "
                                            f"1…{history['frames_accumulated']} frames (total time)")
        for m in steps:
            ax.annotate(str(m["frames_accumulated"]), (m["time_ms"] * m["frames_accumulated"], m["flip"]), fontsize=7,
                        xytext=(3, -9), textcoords="offset points")
        for denoised, marker, what in ((False, "x", "path"), (True, "+", "path + denoiser")):
            p = by_name.get(history_rival(name, denoised))
            if p:
                ax.plot([p["time_ms"]], [p["flip"]], marker, color=line.get_color(), markersize=10,
                        label=f"{what} at its total time ({p['spp']} spp)")
    ax.set_xscale("log")
    ax.set_yscale("log")  # a still camera's history goes an order of magnitude below one frame's error
    ax.set_xlabel("time per frame (ms, log)")
    ax.set_ylabel("FLIP against the ground truth (log)")
    ax.set_title(f"{report['name']}: {report['variant']}, {report['width']}×{report['height']}, {report['spp']} spp/frame",
                 fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: the curves fill the plot
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def scaling(axis: str, values: list[str], out: Path, options: list[str], command: str,
            workers: Workers = Workers()) -> list[dict]:
    """Hybrid (all candidates) and RT baseline time against triangle count (``procedural:N`` at the
    given resolution) or resolution (``WxH`` on ``procedural:1000000``), one child process per
    point (on Ray workers with ``workers``); writes ``out.json``, ``out.md``, ``out.png``
    (:func:`scaling_report`)."""
    import tempfile

    pattern = r"[0-9]+" if axis == "triangles" else r"[0-9]+x[0-9]+"
    wrong = [v for v in values if not re.fullmatch(pattern, v.lower())]
    if wrong:
        raise HybridError(f"bench --scaling {axis}: {wrong} are not "
                          + ("triangle counts" if axis == "triangles" else "resolutions WxH (e.g. 1280x720)"))
    with tempfile.TemporaryDirectory() as tmp:
        jobs = []
        for value in values:
            if axis == "triangles":
                spec, extra = f"procedural:{value}", []
            else:
                w, h = value.lower().split("x")
                spec, extra = "procedural:1000000", ["-D", f"resx={w}", "-D", f"resy={h}"]
            jobs.append((spec, Path(tmp) / f"{value}.json", ["--scaling-point", *options, *extra]))
        reports = _children(jobs, workers, f"scaling by {axis}")
    return scaling_report(axis, reports, out, command)


def scaling_report(axis: str, reports: list[dict], out: Path, command: str) -> list[dict]:
    """The points of a scaling curve (one ``bench_scene`` report each) as JSON, table and chart."""
    points = [{k: r[k] for k in ("triangles", "width", "height", "hybrid_ms", "rt_ms", "gain", "dr_ms",
                                 "all_candidates_trace_ms")} for r in reports]
    first = reports[0]
    result = {"axis": axis, "variant": first["variant"], "device": first["device"], "command": command, "points": points}
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".json").write_text(json.dumps(result, indent=2))
    x = [p["triangles"] if axis == "triangles" else p["width"] * p["height"] for p in points]
    lines = [f"# Scaling with {axis}: {first['variant']}", "", f"Command: `{command}`  ", f"Machine: {first['device']}", "",
             "| triangles | resolution | DR ms | hybrid ms | RT baseline ms | gain (RT / hybrid) | all-candidates trace ms |",
             "|---|---|---|---|---|---|---|"]
    for p in points:
        lines.append(f"| {p['triangles']:,} | {p['width']}×{p['height']} | {p['dr_ms']:.1f} | {p['hybrid_ms']:.1f} | "
                     f"{p['rt_ms']:.1f} | {p['gain']:.2f} | {p['all_candidates_trace_ms']:.1f} |")
    out.with_suffix(".md").write_text("\n".join(lines) + "\n")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.5, 4))
    for key, label in (("hybrid_ms", "hybrid (all candidates)"), ("rt_ms", "RT baseline"), ("dr_ms", "DR (raster + lighting)")):
        ax.plot(x, [p[key] for p in points], "o-", label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("triangles" if axis == "triangles" else "pixels")
    ax.set_ylabel("ms per frame")
    ax.set_title(f"time against {axis} ({first['variant']})", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=100)
    plt.close(fig)
    return points
