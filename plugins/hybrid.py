"""The ``hybrid`` Mitsuba integrator: raster primary hits, ray-traced effects (Sabino et al. 2012).

.. code-block:: xml

    <integrator type="hybrid">
        <string name="primary" value="raster"/>        <!-- or "raytrace": the pure RT baseline -->
        <string name="effects" value="shadow, reflection, refraction"/>  <!-- + "indirect" -->
        <string name="candidates" value="mirror_sphere, glass_sphere"/>  <!-- default: all shapes -->
        <float name="blend" value="1"/>                <!-- composition weight of the RT layer -->
        <integer name="max_depth" value="-1"/>         <!-- as Mitsuba's path; -1 = unlimited -->
        <integer name="rr_depth" value="5"/>
        <boolean name="hide_emitters" value="false"/>
        <float name="budget_ms" value="0"/>            <!-- frame-time budget; 0 = unlimited -->
    </integrator>

Properties
----------
``primary``      where primary hits come from: ``raster`` (the moderngl visibility buffer) or
                 ``raytrace`` (Mitsuba's camera rays), the only difference between the hybrid and
                 the paper's "pure GPU ray tracer" baseline (§8).
``effects``      comma list of ``shadow``, ``reflection``, ``refraction``, ``indirect``. With all
                 four the integrator converges to Mitsuba's ``path``.
``candidates``   comma list of shape ids whose pixels may be ray traced (§4.1); an empty string
                 means none (the image is then the raster layer).
``blend``        the composition weight of §5: traced pixels show ``blend·rt + (1−blend)·raster``.
``budget_ms``    the frame's time budget for ray tracing. Accepted and validated (negative or NaN
                 is an error); the relevance/cost heuristic that spends it is a later stage, so
                 today every candidate is traced whatever the budget.
``max_depth``, ``rr_depth``, ``hide_emitters``: as Mitsuba's ``path``.

``blend`` and ``budget_ms`` are exposed to ``mi.traverse``. ``mi.render(scene)`` returns the
image; the last frame's layers and statistics are in ``integrator.last_result``.
"""
from __future__ import annotations

import dataclasses

import drjit as dr
import mitsuba as mi

from hybrid_integrator.environment import require_jit_rgb_variant
from hybrid_integrator.errors import HybridError
from hybrid_integrator.pipeline import HybridResult, HybridSettings

NAME = "hybrid"


class HybridIntegrator(mi.SamplingIntegrator):
    """Hybrid rasterized + ray-traced rendering as a Mitsuba integrator."""

    def __init__(self, props: mi.Properties):
        require_jit_rgb_variant()
        super().__init__(props)
        fields = {f.name: f for f in dataclasses.fields(HybridSettings)}
        values = {}
        for name in props.keys():
            if name not in fields:
                raise HybridError(f"the hybrid integrator has no property '{name}': it takes {sorted(fields)}")
            value = props[name]
            values[name] = None if name == "candidates" and value is None else value
        self.settings = HybridSettings(**values)
        self.last_result: HybridResult | None = None
        self._params = {"blend": mi.Float(self.settings.blend), "budget_ms": mi.Float(self.settings.budget_ms)}

    def render_result(self, scene: mi.Scene, sensor: int | mi.Sensor = 0, seed: int = 0, spp: int = 0,
                      aovs=()) -> HybridResult:
        """Render a frame and return image, layers and statistics (``hi.render`` calls this)."""
        from hybrid_integrator.api import renderer

        self.last_result = renderer(scene).render(self.settings, sensor=sensor, spp=spp, seed=int(seed), aovs=aovs)
        return self.last_result

    def render(self, scene: mi.Scene, sensor: int | mi.Sensor = 0, seed: int = 0, spp: int = 0,
               develop: bool = True, evaluate: bool = True) -> mi.TensorXf:
        if not develop:
            raise HybridError("the hybrid integrator always develops the film: develop=False is not supported")
        return self.render_result(scene, sensor=sensor, seed=int(dr.ravel(seed)[0]) if not isinstance(seed, int) else seed,
                                  spp=spp).image

    def traverse(self, callback) -> None:
        for name, value in self._params.items():
            callback.put(name, value, mi.ParamFlags.NonDifferentiable)

    def parameters_changed(self, keys=()) -> None:
        changes = {name: float(dr.ravel(self._params[name])[0]) for name in self._params}
        self.settings = dataclasses.replace(self.settings, **changes)

    def to_string(self) -> str:
        fields = ", ".join(f"{k}={v!r}" for k, v in dataclasses.asdict(self.settings).items())
        return f"HybridIntegrator[{fields}]"


def register() -> None:
    """Register ``hybrid`` for the active Mitsuba variant (again after each ``mi.set_variant``)."""
    mi.register_integrator(NAME, lambda props: HybridIntegrator(props))
