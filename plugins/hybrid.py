"""The ``hybrid`` Mitsuba integrator: raster primary hits, ray-traced effects (Sabino et al. 2012).

.. code-block:: xml

    <integrator type="hybrid">
        <string name="primary" value="raster"/>        <!-- or "raytrace": the pure RT baseline -->
        <string name="raster" value="auto"/>           <!-- or "draw", "compute" -->
        <string name="refine" value="auto"/>           <!-- or "primary", "trace" -->
        <string name="outline" value="auto"/>          <!-- or "ties", "silhouettes" -->
        <string name="effects" value="shadow, reflection, refraction, indirect"/>
        <string name="candidates" value="mirror_sphere, glass_sphere"/>  <!-- default: all shapes -->
        <float name="blend" value="1"/>                <!-- composition weight of the RT layer -->
        <integer name="max_depth" value="-1"/>         <!-- as Mitsuba's path; -1 = unlimited -->
        <integer name="rr_depth" value="5"/>
        <integer name="rr_tail_depth" value="16"/>     <!-- default: 16 denoised, -1 (path's roulette) not -->
        <float name="rr_tail_prob" value="0.5"/>       <!-- roulette's cap from rr_tail_depth on -->
        <boolean name="hide_emitters" value="false"/>
        <float name="budget_ms" value="0"/>            <!-- ray-tracing time per frame; 0 = unlimited -->
        <string name="selection" value="nested"/>      <!-- or "greedy", "graph" (§4.2), "exact" -->
        <string name="relevance" value="error"/>       <!-- or "area" (eq. 1 alone) -->
        <float name="importance" value="0"/>           <!-- I of eq. 3 -->
        <boolean name="freeze" value="true"/>          <!-- replay recorded kernels (dr.freeze) -->
        <boolean name="denoise" value="true"/>         <!-- Open Image Denoise, G-buffer guides -->
        <string name="denoise_quality" value="fast"/>  <!-- or "balanced", "high" -->
        <boolean name="temporal" value="false"/>       <!-- accumulate frames, reprojected -->
        <integer name="secondary_spp" value="1"/>      <!-- paths traced from each primary hit -->
        <boolean name="learn_ambient" value="true"/>   <!-- raster layer + learnt ambient light -->
        <boolean name="shadow_tier" value="true"/>     <!-- budgets: shadow rays alone + learnt indirect -->
        <boolean name="partial_objects" value="true"/>  <!-- budgets: what is left buys part of an object -->
        <string name="raster_ahead" value="auto"/>     <!-- or "on", "off": next frame's raster pass -->
        <integer name="frames_in_flight" value="1"/>   <!-- 2: the next frame issued while the GPU finishes this one -->
        <boolean name="stage_times" value="true"/>     <!-- false: no per-stage device times, a shorter frame -->
        <integer name="timing_interval" value="4"/>    <!-- budget, stage_times false: trace timed every 4th frame -->
    </integrator>

Properties
----------
``primary``      where primary hits come from: ``raster`` (the moderngl visibility buffer) or
                 ``raytrace`` (Mitsuba's camera rays), the only difference between the hybrid and
                 the paper's "pure GPU ray tracer" baseline (§8).
``raster``       how the raster pass rasterizes: ``draw`` (OpenGL's rasterizer, one draw call),
                 ``compute`` (OpenGL compute shaders: small triangles one per invocation, large
                 ones by screen tiles; ``hybrid_integrator/raster/compute.py``) or ``auto`` (the
                 default: ``compute`` on a CUDA variant, where it is 1.5–9× faster than the draw on
                 the H100, and ``draw`` on the CPU's llvmpipe). Both give the same visibility
                 buffer up to ties on shared edges and coplanar faces.
``refine``       where the raster's *refined* pixels (silhouettes, analytic shapes' proxies, raster
                 misses: their camera ray is traced, ``hybrid_integrator/primary.py``) are traced:
                 ``primary``, masked in the primary stage's kernel; or ``trace``, inside the trace
                 stage's launch, launched first, with their selection (their lighting after it):
                 the primary stage then traces no ray. The images are the same. ``auto`` (the
                 default): ``trace`` on a CUDA variant where the frame can trace an object, else
                 ``primary``. On an H200 a kernel that traces any ray costs 0.2–0.6 ms whatever
                 its number of rays; ``trace``'s frames were 0.99–1.06× as fast as ``primary``'s
                 on the four bench scenes (about 2 % faster on average) and 0.98× on
                 ``scenes/many_objects.xml`` (``docs/results/gpu/issue10/stop33``). On the CPU
                 ``trace`` grows the trace kernel by about what it saves
                 (``docs/results/cpu/refine``).
``outline``      which pixels of an object's outline are refined: ``ties``, those where the
                 raster's answer may differ from the camera ray's: the sample lies within 1/64
                 pixel of its triangle's edge, or of a neighbour's triangle in front of it, or a
                 neighbour's surface lies at the same depth (``primary.outline_ties``; 0.2–1.3 %
                 of the bench scenes' pixels at 320×180); ``silhouettes``: every pixel whose
                 4-neighbourhood shows another object (3–17 %); ``auto`` (the default): ``ties``
                 with the ``compute`` raster pass, ``silhouettes`` with the ``draw``, whose vertex
                 snapping ``ties`` cannot follow on dense meshes (``primary.resolve_outline``).
                 Either way the primary hits are the camera rays' (``tests/test_integrator.py``,
                 ``docs/results/cpu/refine_need.md``), up to coplanar faces' z-fighting.
``effects``      comma list of ``shadow``, ``reflection``, ``refraction``, ``indirect`` (default:
                 all four, with which the traced pixels are Mitsuba's ``path`` estimator and
                 converge to it; the paper's effects are the first three).
``candidates``   the pre-production candidates of §4.1: comma list of object ids (the scene file's
                 ``<shape>`` ids, ``hybrid_integrator/objects.py``), each optionally
                 with the ray kinds it deserves, ``"armadillo:refraction|shadow, floor:reflection"``
                 (default: every shape, kinds from its material; ``""``: none, the image is then the
                 raster layer). See ``hybrid_integrator/heuristic.py``.
``blend``        the composition weight of §5: traced pixels show ``blend·rt + (1−blend)·raster``.
``budget_ms``    the frame's ray-tracing time budget in ms of device time (0: unlimited; negative
                 or NaN is an error). Objects are ranked by relevance (eq. 1-3, from the previous
                 frame's visibility buffer), selected within the budget by ``selection`` with costs
                 predicted by a cost model calibrated online on the measured trace time, and traced
                 in one call (``hybrid_integrator/budget.py``). The frame is always complete.
``selection``    ``nested`` (the default: the longest run by relevance per cost that fits, starting
                 at the first object that fits alone where the first does not; from the first
                 object's cost up, more budget only ever adds objects), ``greedy`` (by relevance per cost, skipping
                 what does not fit: it captured ≥ 99.5 % of the optimum's relevance on random
                 instances, docs/results), ``graph`` (the paper's selection graph, §4.2-4.3) or
                 ``exact`` (0/1 knapsack).
``relevance``    ``error`` (the default: eq. 1's visibility weighted by the error tracing an object
                 removed in earlier frames, ``hybrid_integrator/heuristic.py``) or ``area`` (eq. 3
                 as the paper has it).
``importance``   I of eq. 3: relevance bonus of objects selected in the previous frame.
``freeze``       record the frame's device pass once (``dr.freeze``) and replay its kernels in later
                 frames instead of tracing its Python again (``hybrid_integrator/pipeline.py``),
                 with a snapshot of the scene's Dr.Jit variables (``hybrid_integrator/frozen.py``:
                 after editing the scene through ``mi.traverse``, call ``hi.forget(scene)``); off:
                 the same kernels, traced every frame (slower; for checking).
``denoise``      denoise the frame with Open Image Denoise, guided by the G-buffer's albedo and
                 normal (exact and noise-free: ``hybrid_integrator/denoise.py``); on the GPU it
                 runs on Dr.Jit's CUDA stream. A frame that traces nothing (no candidate, or
                 none selected within the budget) is the raster layer, which has no noise: it is
                 not denoised (``stats.times_ms["denoise"]`` is 0). ``denoise_quality``: OIDN's ``fast`` (the
                 default: 1.1 ms at 1280×720 on an H100, against 3.2 ms for ``high``),
                 ``balanced`` or ``high``.
``temporal``     blend each frame with the previous ones, reprojected through the visibility
                 buffer (``hybrid_integrator/temporal.py``): a still camera converges, a moving one
                 keeps up to 16 frames of history where the same surface is seen. The history is
                 kept by the integrator between ``render`` calls: give each call its own ``seed``.
``secondary_spp`` paths traced from each traced pixel's primary hit per pass (default 1), in one
                 kernel launch, averaged: the raster draws each hit once, and one launch of k× the
                 lanes costs the GPU less per path than k launches (``spp`` passes, instead, each
                 draw and trace their own jittered hits: antialiasing within the frame). For a
                 still camera with ``temporal``, whose frames add the antialiasing.
``learn_ambient`` add to the raster layer, per object, ``albedo × E`` with ``E`` the ambient
                 irradiance learnt from that object's traced pixels in earlier frames (the cheap
                 model of indirect light and shadowing where nothing is traced this frame;
                 ``hybrid_integrator/lighting.py``).
``shadow_tier``  with a budget (and ``relevance="error"``): a diffuse object may also be traced by
                 its shadow rays alone, its indirect light from a term learnt where it was traced
                 whole, at a fraction of the cost; chosen like an object, by the error it was
                 measured to remove (``hybrid_integrator/heuristic.py``; default on;
                 ``stats.shadow_only`` lists the objects so traced).
``partial_objects`` with a budget: what the selection leaves buys a part of one more object, its
                 pixels at 1, 2 or 3 of the four positions of each 2×2 pixel quad; the others,
                 where the BSDF has a delta lobe (a mirror, a glass), filled with the mean of their
                 traced neighbours on the object (checkerboard rendering), elsewhere the raster
                 layer (``hybrid_integrator/selection.py``), where before the budget bought
                 nothing more once the next object did not fit whole (default on since stop 75: on
                 the H100 it cut the glass Armadillo's error at 50 % from FLIP 0.185 to 0.061;
                 since stop 72 no frame with a part was worse than whole objects by more than the
                 showcase's 50 % frame varies between runs, docs/results/gpu/issue10/stop71 and
                 stop72; off, a budgeted frame traces whole objects only and leaves unspent what
                 ``nested`` leaves, docs/results/gpu/issue10/stop75;
                 ``stats.partial_object`` and ``stats.partial_quarters`` say which and how much).
``raster_ahead`` where the next frame's pose is known (a camera that stood still since the frame
                 before, or the next pose of ``hi.render_sequence``'s camera path), a frame issues
                 the next frame's raster pass at its end, behind its own work: OpenGL runs it once
                 the GPU is done with the frame, and the next frame starts from a finished
                 visibility buffer (``stats.raster_ahead``; one that does not match, such as after
                 an unforeseen camera move, is drawn again: ``stats.raster_discarded``). ``auto`` (the default): where
                 the buffer reaches Dr.Jit through CUDA–OpenGL interop, whose unmap orders
                 OpenGL's draw after the frame's CUDA work; ``on``; ``off``.
``frames_in_flight`` 1 (the default): each frame ends with the backend's synchronization and
                 reports its stages' device times. 2: a frame returns without it, while the GPU
                 still develops and denoises it (the hybrid once its trace is done and the next
                 raster pass is drawn ahead), so the next frame's host work runs meanwhile and the
                 GPU goes from frame to frame without waiting for the host
                 (``hybrid_integrator/inflight.py``). Its counts and times are read when the next
                 frame has issued its device passes (``hi.render_sequence`` and ``hi.render`` read
                 the last one's; else ``hi.finish(scene)``): ``total`` (device time between CUDA
                 events: from the end of the frame before, if that was still in flight, else from
                 its own start), ``gl``, ``denoise``; its stages' times are NaN (Dr.Jit reads its
                 kernel history only after a synchronization); what it learns (the ambient term)
                 shades the frame after next. A frame with a budget is rendered one at a time (it
                 learns from the trace's time); ``stats.in_flight`` says how each frame ran.
``stage_times``  true (the default): each frame reports its stages' device times
                 (``stats.times_ms``), from Dr.Jit's kernel history, which records a pair of CUDA
                 events around every launch and is read once the frame's device passes are done,
                 while the GPU denoises the frame (after its synchronization where nothing is
                 denoised, or with ``temporal``). false: a frame without a budget keeps no history
                 (its stages NaN, ``stats.stages_timed`` false; ``total``, ``gl`` and ``denoise``
                 still timed): the frame as a renderer ships it. On the H200 a denoised frame is
                 about as fast either way (-0.08 to +0.03 ms on two scenes), a DR frame 0.05-0.10
                 ms faster (``SIDES=new bash docs/results/gpu/issue10/stop51/run.sh cost
                 SCENE…``). A budgeted frame's cost model learns the trace's time, so without
                 ``stage_times`` a budget still times every ``timing_interval``-th frame.
``timing_interval``  with a budget and ``stage_times`` false, a frame times its stages (and its
                 cost model learns from its trace) every ``timing_interval`` frames of a sequence
                 (default 4; 1: every frame), every frame until the model is calibrated, and the
                 frame after an untimed one whose wall time jumped by over half the budget (its
                 overrun, unseen, is timed then); the frames between report NaN stages and
                 ``stats.budget_met`` None. The kernel history
                 costs a budgeted frame, bound by its host, a pair of CUDA events per launch before
                 the GPU reaches the trace and their readout: on an H200 the frames without it
                 were 0.2-0.9 ms shorter along the 226 objects' camera path at 25-75 % budgets, and
                 a budget timed every 4th frame 1.04-1.19× as fast as one timed on every frame, in
                 turn (``bash docs/results/gpu/issue10/stop59/run.sh untimed``); but the
                 Armadillo's budgeted frames, bound by the GPU, 0.96-0.98× there, and 1.17-1.18×
                 in another machine start (``bash docs/results/gpu/issue10/stop60/run.sh ahead``).
``max_depth``, ``rr_depth``, ``hide_emitters``: as Mitsuba's ``path``.
``rr_tail_depth``, ``rr_tail_prob``  past ``rr_depth`` a path goes on with probability
                 min(max throughput · η², 0.95), as in ``path``; from depth ``rr_tail_depth`` on
                 (default: 16 in a denoised frame, -1 in one without the denoiser; -1: never)
                 at most ``rr_tail_prob`` (default 0.5). Through glass a
                 path keeps going with probability 0.95, so a GPU launch ended in a tail of a few
                 lanes hundreds of vertices deep; the cap ends it, unbiased, with more variance
                 only in paths that deep (``trace.RouletteCap``: H200, the showcase 1.11× faster,
                 FLIP 0.0970 → 0.0971; the Armadillo 1.04×, 0.0310 → 0.0314). That variance is rare
                 fireflies, which the denoiser removes; so without the denoiser (``denoise``
                 false) the default is -1. To average frames into a reference, set -1.

Each property has the type its XML tag above says (from Python: ``bool``, ``int``, a number, ``str``;
a float takes an integer): another is an error naming the property, as ``denoise='no' must be a
boolean``, not a value read as something else.

``blend``, ``budget_ms`` and ``importance`` are exposed to ``mi.traverse``. The selection of the
last frame and the cost model are carried from one ``render`` call to the next (``self.state``). ``mi.render(scene)`` returns the
image; the last frame's layers and statistics are in ``integrator.last_result``.
"""
from __future__ import annotations

import dataclasses

import drjit as dr
import mitsuba as mi

from hybrid_integrator.environment import require_jit_rgb_variant
from hybrid_integrator.errors import HybridError
from hybrid_integrator.budget import FrameState
from hybrid_integrator.pipeline import HybridResult, HybridSettings

NAME = "hybrid"


class HybridIntegrator(mi.SamplingIntegrator):
    """Hybrid rasterized + ray-traced rendering as a Mitsuba integrator."""

    def __init__(self, props: mi.Properties):
        require_jit_rgb_variant()
        super().__init__(props)
        self.settings = HybridSettings.from_properties({name: props[name] for name in props.keys()})
        self.last_result: HybridResult | None = None
        #: carried from frame to frame: last selection (S of eq. 3) and the calibrated cost model
        self.state = FrameState()
        self._params = {name: mi.Float(getattr(self.settings, name)) for name in ("blend", "budget_ms", "importance")}

    def render_result(self, scene: mi.Scene, sensor: int | mi.Sensor = 0, seed: int = 0, spp: int = 0,
                      aovs=(), layers: bool = True, next_camera=None) -> HybridResult:
        """Render a frame and return image, layers (unless ``layers=False``) and statistics
        (``hi.render`` calls this); ``next_camera``: the sensor's ``to_world`` in the next frame,
        where known (``hi.render_sequence`` gives it: ``raster_ahead``)."""
        from hybrid_integrator.api import renderer

        if not scene.shapes():  # nothing to rasterize or trace: what Mitsuba shows is the background
            self.last_result = _background(scene, self.settings, sensor, seed, spp)
        else:
            self.last_result = renderer(scene).render(self.settings, sensor=sensor, spp=spp, seed=seed,
                                                      aovs=aovs, state=self.state, layers=layers,
                                                      next_camera=next_camera)
        return self.last_result

    def render(self, scene: mi.Scene, sensor: int | mi.Sensor = 0, seed: int = 0, spp: int = 0,
               develop: bool = True, evaluate: bool = True) -> mi.TensorXf:
        if not develop:
            raise HybridError("the hybrid integrator always develops the film: develop=False is not supported")
        return self.render_result(scene, sensor=sensor, seed=int(dr.ravel(seed)[0]) if not isinstance(seed, int) else seed,
                                  spp=spp).image

    def sample(self, scene, sampler, ray, medium=None, active=True):
        """Mitsuba's per-ray interface, which integrators that nest another (``aov``, ``moment``,
        ...) call: the hybrid renders whole frames (its primaries come from the raster pass), so
        it has none, and says so (nanobind reported a "pure virtual function")."""
        raise HybridError("the hybrid integrator renders whole frames and cannot be nested in another integrator "
                          "(aov, moment, ...): use it at the top level; its G-buffer AOVs come from hi.render(aovs=...)")

    def traverse(self, callback) -> None:
        for name, value in self._params.items():
            callback.put(name, value, mi.ParamFlags.NonDifferentiable)

    def parameters_changed(self, keys=()) -> None:
        changes = {name: float(dr.ravel(self._params[name])[0]) for name in self._params}
        self.settings = dataclasses.replace(self.settings, **changes)

    def to_string(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in dataclasses.asdict(self.settings).items())
        return f"HybridIntegrator[{fields}]"


def _background(scene: mi.Scene, settings: HybridSettings, sensor, seed: int, spp: int) -> HybridResult:
    """A scene without shapes (none, or only infinite emitters): the frame is Mitsuba's ``path``
    render of it (the environment, or black), recorded as a fallback in the frame's statistics."""
    import time

    from hybrid_integrator.pipeline import FrameStats, check_frame_numbers
    from hybrid_integrator.raster.camera import resolve_sensor

    spp, seed = check_frame_numbers(spp, seed)  # (the hybrid's frames check them in HybridRenderer.render)
    sensor = resolve_sensor(scene, sensor)
    integrator = mi.load_dict({"type": "path", "max_depth": settings.max_depth, "hide_emitters": settings.hide_emitters})
    start = time.perf_counter()
    image = mi.render(scene, integrator=integrator, sensor=sensor, seed=seed, spp=spp)
    dr.eval(image)
    dr.sync_thread()
    size = sensor.film().crop_size()
    stats = FrameStats(width=int(size[0]), height=int(size[1]), spp=int(spp) or sensor.sampler().sample_count(),
                       primary=settings.primary, fallback="the scene has no shapes: Mitsuba's path renders its background")
    stats.times_ms["total"] = (time.perf_counter() - start) * 1e3
    return HybridResult(image=image, stats=stats, pixel_format=sensor.film().bitmap().pixel_format())


def register() -> None:
    """Register ``hybrid`` for the active Mitsuba variant (again after each ``mi.set_variant``)."""
    mi.register_integrator(NAME, lambda props: HybridIntegrator(props))
