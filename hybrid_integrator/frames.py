"""Camera paths rendered to disk, in one process or on Ray workers (issue 13).

A camera path's frames are written one file set each: ``frame_00012.exr`` (image + layers),
``.png`` and ``.json`` (the frame's statistics), each written atomically (``io.atomic_path``), so
a frame on disk is a finished frame and a run can be resumed: frames already there are skipped.

With ``workers`` > 1 the frames go to Ray actors (``ray.init()`` locally, or a cluster's
address), one per GPU with ``cuda_ad_rgb`` (``gpus_per_worker``) or one per CPU worker with
``llvm_ad_rgb``. Each actor loads the scene once and keeps its renderer (GL context, recorded
kernels, cost model, selection) warm across the frames it renders; the path is cut into
contiguous chunks, one per actor, whose frames an actor renders in order, so the selection and the
cost model carried from frame to frame stay meaningful. What differs from one process: each chunk
starts its own carried state: its first frame probes the cost model (with a budget), and the
learnt ambient term (``lighting.py``) and errors are learnt again, so untraced pixels can differ
from a single process's (with ``learn_ambient=false`` and no budget the frames are the same).
Every frame is rendered with seed ``seed + frame``, as ``hi.render_sequence`` does.

A worker that dies loses only its unfinished frame: Ray restarts the actor and retries its tasks,
and a retried frame already on disk is skipped. ``workers`` = 1 renders in this process, without
Ray.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import HybridError


def frame_name(index: int) -> str:
    return f"frame_{index:05d}"


def frame_done(out_dir: Path, index: int) -> bool:
    """Whether frame ``index`` is on disk (its statistics are written last)."""
    return (out_dir / f"{frame_name(index)}.json").is_file()


@dataclass(frozen=True)
class Job:
    """What every worker needs to render frames of one camera path."""

    scene: str  # the scene file
    params: dict  # its $-parameters
    variant: str
    properties: dict  # the hybrid integrator's
    spp: int
    seed: int
    out_dir: str


class FrameRenderer:
    """One worker's renderer: the scene loaded once, the integrator (and its carried state) kept."""

    def __init__(self, job: Job):
        import mitsuba as mi

        import hybrid_integrator as hi

        mi.set_variant(job.variant)
        hi.register()
        self.job = job
        self.scene = hi.load_scene(job.scene, **job.params)
        self.integrator = hi.api._integrator(dict(job.properties))
        self.sensor = self.scene.sensors()[0]

    def render(self, index: int, camera: list, next_camera: list | None = None) -> int:
        """Render frame ``index`` from ``camera`` (a 4×4 to_world) and write it; a frame already on
        disk is skipped. ``next_camera``: the pose of the frame this renderer renders next, whose
        raster pass the frame draws ahead (``raster_ahead``). Returns ``index``."""
        import hybrid_integrator as hi
        from hybrid_integrator.raster.camera import camera_pose, place_sensor

        out = Path(self.job.out_dir)
        if frame_done(out, index):
            return index
        place_sensor(self.sensor, camera_pose(camera))  # as api.posed moves it: without waiting for the device
        result = self.integrator.render_result(self.scene, seed=self.job.seed + index, spp=self.job.spp,
                                               next_camera=next_camera)
        # its statistics complete before they are written (``frames_in_flight=2``: inflight.py); writing
        # reads the image back, which waits for the frame anyway
        hi.finish(self.scene)
        write_frame(out, index, result)
        return index


def write_frame(out_dir: Path, index: int, result) -> None:
    """The frame's EXR, PNG and statistics JSON (``io.write_result``), the JSON last."""
    from .io import write_result

    write_result(out_dir / f"{frame_name(index)}.exr", result, frame=index)


def chunks(frames: list[int], workers: int) -> list[list[int]]:
    """``frames`` cut into ``workers`` contiguous runs of near-equal length (empty ones dropped)."""
    return [c.tolist() for c in np.array_split(np.asarray(frames, dtype=np.int64), max(workers, 1)) if len(c)]


def render_frames(scene: str | Path, cameras, out_dir: str | Path, spp: int = 1, seed: int = 0, workers: int = 1,
                  params: dict | None = None, ray_address: str | None = None, gpus_per_worker: float = 0.0,
                  preview: bool = True, variant: str | None = None, **properties) -> dict:
    """Render the camera path ``cameras`` (``hi.camera_path`` transforms or 4×4 matrices) of the
    scene file ``scene`` into ``out_dir`` (module docstring). Returns a report: frames rendered
    now, frames skipped because they were on disk, the preview file."""
    import mitsuba as mi
    from tqdm import tqdm

    from .pipeline import check_frame_numbers
    from .raster.camera import camera_pose

    # the numbers and poses checked before anything is written or any worker starts
    spp, seed = check_frame_numbers(spp, seed)
    matrices = [camera_pose(c).tolist() for c in cameras]  # each a finite, invertible 4×4 transform
    if workers < 1:
        raise HybridError(f"workers={workers}: give 1 (this process) or more (Ray workers)")
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    job = Job(scene=str(scene), params=dict(params or {}), variant=variant or mi.variant(),
              properties=dict(properties), spp=spp, seed=seed, out_dir=str(out))
    todo = [k for k in range(len(matrices)) if not frame_done(out, k)]
    bar = tqdm(total=len(matrices), initial=len(matrices) - len(todo), desc="frames", unit="frame")
    if todo and workers == 1:
        renderer = FrameRenderer(job)
        for k, after in zip(todo, todo[1:] + [None]):
            renderer.render(k, matrices[k], None if after is None else matrices[after])
            bar.update()
    elif todo:
        _render_on_ray(job, matrices, todo, workers, ray_address, gpus_per_worker, bar)
    bar.close()
    gif = write_preview(out, len(matrices)) if preview else None
    return {"frames": len(matrices), "rendered": len(todo), "skipped": len(matrices) - len(todo),
            "workers": workers, "preview": None if gif is None else str(gif), "out_dir": str(out)}


def start_ray(missing: str, address: str | None = None, num_cpus: int | None = None):
    """The ``ray`` module, with Ray running: a local instance (``num_cpus`` workers' worth, None:
    all cores) or the cluster at ``address``, unless this process started it already. Where Ray
    is not installed, a :class:`HybridError` with the message ``missing``."""
    try:
        import ray
    except ImportError as exc:
        raise HybridError(missing) from exc
    if not ray.is_initialized():
        ray.init(address=address, num_cpus=num_cpus, include_dashboard=False, log_to_driver=False,
                 ignore_reinit_error=True)
    return ray


def _render_on_ray(job: Job, matrices: list, todo: list[int], workers: int, address: str | None, gpus: float,
                   bar) -> None:
    ray = start_ray("workers > 1 needs Ray: pip install 'hybrid_integrator[ray]' (or workers=1)", address,
                    None if address else workers)
    actor = ray.remote(num_gpus=gpus, num_cpus=0 if gpus else 1, max_restarts=2, max_task_retries=3)(FrameRenderer)
    pending = []
    for chunk in chunks(todo, workers):
        worker = actor.remote(job)
        # in order: state carries, and each frame draws its worker's next frame's raster pass ahead
        pending += [worker.render.remote(int(k), matrices[k], None if after is None else matrices[after])
                    for k, after in zip(chunk, chunk[1:] + [None])]
    while pending:
        done, pending = ray.wait(pending, num_returns=1)
        ray.get(done)
        bar.update(len(done))


def write_preview(out_dir: Path, frames: int, fps: int = 12) -> Path | None:
    """An animated GIF of the frames' PNGs (Pillow), beside them."""
    from PIL import Image

    pngs = [out_dir / f"{frame_name(k)}.png" for k in range(frames)]
    if not all(p.is_file() for p in pngs):
        return None
    images = [Image.open(p).convert("RGB") for p in pngs]
    path = out_dir / "preview.gif"
    from .io import atomic_path

    with atomic_path(path) as tmp:
        images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=int(1000 / fps), loop=0)
    return path
