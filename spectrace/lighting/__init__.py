"""Lighting-design results (the library of ``spectrace lux`` beyond the lux map): one
study or measurement per module.

* :mod:`~spectrace.lighting.points`: illuminance at sensor points (planar, vertical,
  cylindrical, semi-cylindrical) with its standard error, and the points CSV files;
* :mod:`~spectrace.lighting.grids`: EN 12464-1 calculation grids on a horizontal plane,
  their statistics, the task requirements table and the plan-view figure;
* :mod:`~spectrace.lighting.luminance`: luminance in cd/m^2 of a camera's view or along
  given rays;
* :mod:`~spectrace.lighting.glare`: the unified glare rating UGR of CIE 117-1995 from a
  luminance image;
* :mod:`~spectrace.lighting.report`: the Markdown report of a study.

Nothing here is imported by ``import spectrace``.
"""
