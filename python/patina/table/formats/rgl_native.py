"""An RGL material (rgl_brdf.RglBrdf, checked and converted to linear sRGB by the reader)
handed to the native evaluator, sampler and pdf (_core.RglBsdf, brdf/rgl/): float32 copies
of its grids and of its warps' normalised CDFs, in the layout the C++ reads."""

from __future__ import annotations

import numpy as np

from patina.native import _core
from patina.table.formats.rgl_brdf import RglBrdf
from patina.table.formats.rgl_warp import Interpolant2D


def _f32(a: np.ndarray) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float32)


def _warp(warp: Interpolant2D) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """data, marginal, conditional as (slices, H, W), (slices, H), (slices, H, W)."""
    shape = (-1, warp.height, warp.width)
    return _f32(warp.data.reshape(shape)), _f32(warp.marginal), _f32(warp.conditional.reshape(shape))


def _grid(grid: Interpolant2D) -> np.ndarray:
    return _f32(grid.data.reshape(grid.height, grid.width))


def native_rgl(brdf: RglBrdf) -> _core.RglBsdf:
    if brdf.channels != 3:
        raise ValueError(f"{brdf.path}: {brdf.channels} channels; the native evaluator takes linear sRGB")
    vndf, vndf_marginal, vndf_conditional = _warp(brdf.vndf)
    luminance, luminance_marginal, luminance_conditional = _warp(brdf.luminance)
    values = brdf.values.data.reshape(brdf.phi_i.size, brdf.theta_i.size, 3, brdf.values.height, brdf.values.width)
    return _core.RglBsdf(
        theta_i=_f32(brdf.theta_i),
        phi_i=_f32(brdf.phi_i),
        ndf=_grid(brdf.ndf),
        sigma=_grid(brdf.sigma),
        vndf=vndf,
        vndf_marginal=vndf_marginal,
        vndf_conditional=vndf_conditional,
        luminance=luminance,
        luminance_marginal=luminance_marginal,
        luminance_conditional=luminance_conditional,
        values=_f32(values),
        isotropic=brdf.isotropic,
        jacobian=brdf.jacobian,
        reduction=brdf.reduction,
    )
