"""The material an export writes: a Lambert base, GGX or Beckmann lobes with Schlick
Fresnel, an optional clear coat, in Patina's conventions (fit/microfacet.h), evaluable by
Patina's own kernels so the writers' results can be checked against it.

A lobe is D G2 F / (4 cos_i cos_o): D the GGX or Beckmann distribution of roughness alpha
(isotropic), G2 the height-correlated Smith term, F Schlick's f0 + (1 - f0)(1 - cos_d)^5 with
an RGB f0. The coat (GGX alpha, exact dielectric Fresnel of index eta) dims everything under
it by (1 - F(cos_i)) (1 - F(cos_o)) and adds its own reflection. Colours are linear sRGB
(Rec. 709 primaries, D65), as `patina fit` fits them."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from patina.kernel_arrays import as_float32
from patina.native import _core

RGB = tuple[float, float, float]
DISTRIBUTIONS = ("ggx", "beckmann")


@dataclass(frozen=True)
class Lobe:
    distribution: str  # "ggx" or "beckmann"
    alpha: float
    f0: RGB


@dataclass(frozen=True)
class Coat:
    alpha: float
    eta: float


@dataclass(frozen=True)
class AnalyticMaterial:
    """What every writer reads. `model` and `source` say where it came from (fit.json's model
    and path, or the scene's material)."""

    name: str
    diffuse: RGB
    lobes: tuple[Lobe, ...] = ()
    coat: Coat | None = None
    two_sided: bool = False
    model: str = ""
    source: str = ""
    notes: list[str] = field(default_factory=list, compare=False)  # what the export changed, for the sidecar

    @property
    def distribution(self) -> str:
        return self.lobes[0].distribution if self.lobes else "ggx"

    def kernel_params(self) -> tuple[str, list[float]]:
        """The kernel name and parameters _core.mixture_eval takes for this material. Without
        specular lobes, one Ward lobe of zero weight stands in (Ward is linear in its weight,
        so it adds nothing), since the kernels need at least one lobe."""
        params = [float(x) for x in self.diffuse]
        if self.lobes:
            kind = self.distribution
            for lobe in self.lobes:
                params += [lobe.alpha, *lobe.f0]
        else:
            kind = "ward"
            params += [0.5, 0.0, 0.0, 0.0]
        if self.coat:
            kind += "+coat"
            params += [self.coat.alpha, self.coat.eta]
        return kind, params

    def eval(self, wi: np.ndarray, wo: np.ndarray) -> np.ndarray:
        """(n, 3) local-frame direction pairs -> (n, 3) RGB BRDF values in 1/sr (no cosine)."""
        kind, params = self.kernel_params()
        out = np.asarray(_core.mixture_eval(kind, params, as_float32(wi), as_float32(wo)), np.float64)
        if self.two_sided:  # the back side mirrors the front: evaluate with both directions flipped to +z
            back = (wi[:, 2] < 0) & (wo[:, 2] < 0)
            if back.any():
                flip = np.array([1.0, 1.0, -1.0])
                out[back] = _core.mixture_eval(kind, params, as_float32(wi[back] * flip), as_float32(wo[back] * flip))
        return out

    def as_json(self) -> dict:
        out = asdict(self)
        out.pop("notes")
        return out
