"""Patina: a measured-material appearance workbench.

>>> import patina
>>> brdf = patina.load_brdf("materials/red-plastic-iso.ptab")
>>> brdf.eval(wi, wo)                   # (n, 3) local-frame directions -> (n, channels)
>>> brdf.eval_angles(ti, pi, to, po)    # radians
>>> brdf.save("copy.ptab"); brdf.info()
"""

from __future__ import annotations

from . import _core
from .brdf import Brdf, load_brdf
from .errors import FormatError

__version__ = _core.__version__
__all__ = ["Brdf", "FormatError", "__version__", "load_brdf"]
