"""Spectra from RGB (python/patina/export/rgb_upsampling.py): Mitsuba's own Jakob-Hanika
spectra, linear in a colour's scale, and back to the same colour through the CIE observer."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from patina.export.rgb_upsampling import WAVELENGTHS, upsample
from patina.table.colour_matching import xyz_to_linear_srgb, xyz_weights

pytest.importorskip("mitsuba")  # the coefficient table is Mitsuba's


@pytest.mark.parametrize("rgb", [(0.2, 0.4, 0.1), (3.0, 1.0, 0.5), (0.0, 0.05, 20.0)])
def test_the_spectrum_is_mitsubas_own(rgb):
    """Mitsuba's `d65` spectrum given a colour is that colour upsampled (unbounded) times D65."""
    import mitsuba as mi

    mi.set_variant("scalar_spectral")
    lam = [450.0, 520.0, 610.0, 700.0]
    si = mi.SurfaceInteraction3f()
    si.wavelengths = mi.Spectrum(lam)
    d65 = np.array(mi.load_dict({"type": "d65"}).eval(si))
    want = np.array(mi.load_dict({"type": "d65", "color": list(rgb)}).eval(si)) / d65
    assert np.allclose(upsample(np.array([rgb]), np.array(lam))[0], want, rtol=1e-4)  # Mitsuba in float32


@settings(max_examples=40, deadline=None)
@given(
    rgb=st.tuples(*[st.floats(0.02, 1.0)] * 3),
    scale=st.floats(1e-3, 1e3),
)
def test_linear_in_scale_and_round_trips_through_the_observer(rgb, scale):
    colour = np.array([rgb])
    spectrum = upsample(colour)
    assert np.allclose(upsample(colour * scale), spectrum * scale, rtol=1e-4)
    back = (xyz_to_linear_srgb() @ xyz_weights(WAVELENGTHS) @ spectrum[0]).ravel()
    # the model's fit to sRGB colours (Jakob & Hanika: within a fraction of a ΔE) at 10 nm steps
    assert np.allclose(back, colour[0], atol=0.02 * colour.max())


def test_black_and_negative_values_give_zero():
    out = upsample(np.array([[0.0, 0.0, 0.0], [-1.0, -0.5, -0.1]]))
    assert out.shape == (2, WAVELENGTHS.size) and np.all(out == 0)
