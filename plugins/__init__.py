"""Mitsuba plugins of hybrid_integrator, installed as ``hybrid_integrator.plugins``.

The ``hybrid`` integrator (paper §3.2, §5) lands here; the raster stage it consumes is
:mod:`hybrid_integrator.raster`.
"""
