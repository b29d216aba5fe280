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

from . import _core
from .accel import Accel, Hits
from .brdf import Brdf, load_brdf
from .errors import FormatError
from .fitting import FitResult, compare, fit
from .luminaire import Luminaire, load_luminaire
from .mesh import Mesh, load_mesh
from .render import RenderResult
from .render import render as render_scene
from .scene_file import load_scene
from .validation import validate

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
