"""Patina: a measured-material appearance workbench.

>>> import patina
>>> brdf = patina.load_brdf("materials/red-plastic-iso.ptab")
>>> brdf.eval(wi, wo)                   # (n, 3) local-frame directions -> (n, channels)
>>> brdf.eval_angles(ti, pi, to, po)    # radians
>>> brdf.save("copy.ptab"); brdf.info()
>>> patina.validate(brdf).problems                  # checks; patina.fit(brdf, model="ggx+lambert")
>>> accel = patina.Accel(patina.load_mesh("model.obj"))
>>> hits = accel.intersect(origins, directions, width=8)   # 8-ray packets
"""

from __future__ import annotations

from . import _core
from .accel import Accel, Hits
from .brdf import Brdf, load_brdf
from .errors import FormatError
from .fitting import FitResult, compare, fit
from .mesh import Mesh, load_mesh
from .validation import validate

__version__ = _core.__version__
__all__ = [
    "Accel",
    "Brdf",
    "FitResult",
    "FormatError",
    "Hits",
    "Mesh",
    "__version__",
    "compare",
    "fit",
    "load_brdf",
    "load_mesh",
    "validate",
]
