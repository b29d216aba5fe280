"""Patina: a measured-material appearance workbench.

>>> import patina
>>> brdf = patina.load_brdf("materials/red-plastic-iso.ptab")
>>> brdf.eval(wi, wo)                   # (n, 3) local-frame directions -> (n, channels)
>>> brdf.eval_angles(ti, pi, to, po)    # radians
>>> brdf.save("copy.ptab"); brdf.info()
>>> patina.validate(brdf).problems                  # checks; patina.fit(brdf, model="ggx+lambert")
>>> accel = patina.Accel(patina.load_mesh("model.obj"))
>>> hits = accel.intersect(origins, directions, width=8)   # 8-ray packets
>>> scene = patina.load_scene("materials/scenes/preview-ball.json")   # docs/scene.md
>>> result = patina.render_scene(scene)            # result.rgb, .albedo, .normal, .depth, .illuminance
"""

from __future__ import annotations

from patina.errors import FormatError
from patina.fitting import FitResult, compare, fit
from patina.geometry import Accel, Hits, Mesh, load_mesh
from patina.native import _core
from patina.photometry import Luminaire, load_luminaire
from patina.render import RenderResult
from patina.render import render as render_scene
from patina.scene import load_scene
from patina.table import Brdf, load_brdf, validate

__version__ = _core.__version__
__all__ = [
    "Accel",
    "Brdf",
    "FitResult",
    "FormatError",
    "Hits",
    "Luminaire",
    "Mesh",
    "RenderResult",
    "__version__",
    "compare",
    "fit",
    "load_brdf",
    "load_luminaire",
    "load_mesh",
    "load_scene",
    "render_scene",
    "validate",
]
