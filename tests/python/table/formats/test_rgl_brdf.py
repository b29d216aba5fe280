"""The RGL reference evaluator (python/patina/table/formats/rgl_brdf.py) against analytic
BRDFs written as .bsdf files by python/patina/table/formats/rgl_writer.py: exact (to
float32) at the incident angles the file holds, within the format's interpolation
between them; spectral files through the spectral path; every bad field refused with
one line naming the file and the field; the parser fuzzed."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from patina.errors import FormatError
from patina.synthetic.analytic import plastic
from patina.table.angles import angles_to_directions
from patina.table.formats.rgl_brdf import RglBrdf, read_rgl_brdf
from patina.table.formats.rgl_writer import RglLayout, rgl_arrays, write_rgl
from patina.table.formats.tensor_file import parse_tensor_file, tensor_file_bytes
from reader_fuzz import load_damaged

MODEL = plastic(diffuse=(0.5, 0.3, 0.1), specular=0.04, roughness=0.3)
SMALL_LAYOUT = RglLayout(theta_i=4, ndf=(4, 8), sigma=(4, 8), vndf=(6, 8), values=(6, 6))


def _hemisphere(rng, n: int, min_cos: float = 0.05) -> np.ndarray:
    return angles_to_directions(np.arccos(rng.uniform(min_cos, 1.0, n)), rng.uniform(0, 2 * math.pi, n))


def _relative(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return (np.abs(a - b) / np.maximum(np.abs(b), 1e-2)).max(axis=1)


@pytest.fixture(scope="module")
def iso_arrays() -> dict[str, np.ndarray]:
    return rgl_arrays(MODEL)


@pytest.fixture(scope="module")
def iso(iso_arrays) -> RglBrdf:
    return RglBrdf(parse_tensor_file("iso.bsdf", tensor_file_bytes(iso_arrays)))


def test_exact_at_the_incident_angles_the_file_holds(iso):
    rng = np.random.default_rng(1)
    n = 4000
    theta = iso.theta_i[rng.integers(0, iso.theta_i.size - 3, n)]  # up to 62 deg
    wi = angles_to_directions(theta, rng.uniform(0, 2 * math.pi, n))
    wo = _hemisphere(rng, n, min_cos=0.26)  # below 75 deg
    rel = _relative(iso.eval(wi, wo), MODEL(wi, wo))
    assert np.median(rel) < 2e-3 and np.percentile(rel, 95) < 0.02


def test_between_incident_angles_within_the_formats_interpolation(iso):
    rng = np.random.default_rng(2)
    wi, wo = _hemisphere(rng, 4000, 0.34), _hemisphere(rng, 4000, 0.26)
    rel = _relative(iso.eval(wi, wo), MODEL(wi, wo))
    assert np.median(rel) < 0.01 and np.percentile(rel, 90) < 0.1


def test_below_the_horizon_is_zero_and_isotropy_holds(iso):
    wi = np.array([[0.3, 0.0, 0.954], [0.3, 0.0, -0.954]])
    wo = np.array([[-0.2, 0.1, -0.97], [0.0, 0.0, 1.0]])
    assert np.all(iso.eval(wi, wo) == 0)
    rng = np.random.default_rng(4)
    wi, wo = _hemisphere(rng, 100), _hemisphere(rng, 100)
    c, s = math.cos(1.1), math.sin(1.1)
    rot = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    # (the sigma and ndf tables of the file still hold phi: their quadrature differs by ~1e-6)
    assert np.allclose(iso.eval(wi @ rot.T, wo @ rot.T), iso.eval(wi, wo), rtol=1e-4, atol=1e-9)


def test_spectral_file_is_converted_like_other_spectral_tables():
    wavelengths = np.linspace(380, 780, 21)
    flat = lambda wi, wo: np.repeat(MODEL(wi, wo)[:, 1:2], wavelengths.size, axis=1)  # noqa: E731
    brdf = RglBrdf(parse_tensor_file("s.bsdf", tensor_file_bytes(rgl_arrays(flat, wavelengths, layout=SMALL_LAYOUT))))
    assert brdf.channel_kind == "spectral" and brdf.channels == 3
    rng = np.random.default_rng(5)
    wi, wo = _hemisphere(rng, 300), _hemisphere(rng, 300)
    rgb = brdf.eval(wi, wo)
    # a spectrally flat BRDF is grey: R = G = B (D65 white point, spectral.py; the sRGB matrix to 3e-4)
    assert np.allclose(rgb[:, 0], rgb[:, 1], rtol=1e-3) and np.allclose(rgb[:, 2], rgb[:, 1], rtol=1e-3)


def test_jacobian_flag_off_reads_the_table_directly(iso_arrays):
    arrays = dict(iso_arrays, jacobian=np.array([0], np.uint8))
    off = RglBrdf(parse_tensor_file("j.bsdf", tensor_file_bytes(arrays)))
    on = RglBrdf(parse_tensor_file("j.bsdf", tensor_file_bytes(iso_arrays)))
    rng = np.random.default_rng(6)
    wi, wo = _hemisphere(rng, 50), _hemisphere(rng, 50)
    m = wi + wo
    m /= np.linalg.norm(m, axis=1, keepdims=True)
    ratio = on.eval(wi, wo)[:, 1] / off.eval(wi, wo)[:, 1]
    assert off.jacobian is False and np.ptp(ratio) > 0.1  # the ndf / (4 sigma) factor is not applied


def test_anisotropic_file_with_reduced_azimuth_is_mirrored(tmp_path):
    layout = RglLayout(theta_i=4, phi_i=5, ndf=(8, 8), sigma=(8, 8), vndf=(8, 8), values=(6, 6))
    arrays = rgl_arrays(MODEL, layout=layout)
    full = RglBrdf(parse_tensor_file("a.bsdf", tensor_file_bytes(arrays)))
    assert not full.isotropic and full.reduction == 1
    half = dict(arrays, phi_i=np.linspace(-math.pi, 0, 5, dtype=np.float32))
    reduced = RglBrdf(parse_tensor_file("h.bsdf", tensor_file_bytes(half)))
    assert reduced.reduction == 2
    # phi_i over 180 deg: a pair and the same pair turned by 180 deg about the normal evaluate
    # alike (Mitsuba's `measured` folds both x and y by the sign of wi.y)
    rng = np.random.default_rng(7)
    wi, wo = _hemisphere(rng, 50), _hemisphere(rng, 50)
    flip = np.array([-1.0, -1.0, 1.0])
    assert np.allclose(reduced.eval(wi, wo), reduced.eval(wi * flip, wo * flip), rtol=1e-9)
    odd = dict(arrays, phi_i=np.linspace(-1, 1, 5, dtype=np.float32))  # over 115 deg: no known reduction
    with pytest.raises(FormatError, match=r"phi_i.*expected 360, 180 or 90"):
        RglBrdf(parse_tensor_file("o.bsdf", tensor_file_bytes(odd)))
    path = tmp_path / "a.bsdf"
    write_rgl(path, MODEL, layout=layout)
    assert not read_rgl_brdf(str(path)).isotropic


@pytest.mark.parametrize(
    "change, field, problem",
    [
        (lambda a: a.pop("vndf"), "field table", "no 'vndf' field"),
        (lambda a: a.update(rgb=np.zeros((1, 12, 2, 32, 32), np.float32)), "field 'rgb'", "must be 3"),
        (lambda a: a.update(ndf=a["ndf"].astype(np.float64)), "field 'ndf'", "dtype float64: expected float32"),
        (lambda a: a["sigma"].__setitem__((0, 0), np.nan), "field 'sigma'", "not finite"),
        (
            lambda a: a["vndf"].__setitem__((0, 1, 2, 3), -1.0),
            "field 'vndf'",
            "negative value -1 at index [0, 1, 2, 3]",
        ),
        (lambda a: a.update(theta_i=a["theta_i"][::-1].copy()), "field 'theta_i'", "increase strictly"),
        (lambda a: a.update(luminance=a["luminance"][:, :5]), "field 'luminance'", "must begin with"),
        (lambda a: a.update(jacobian=np.array([1, 1], np.uint8)), "field 'jacobian'", "expected one uint8"),
    ],
)
def test_bad_fields_are_named(iso_arrays, change, field, problem):
    arrays = {k: v.copy() for k, v in iso_arrays.items()}
    change(arrays)
    with pytest.raises(FormatError) as e:
        RglBrdf(parse_tensor_file("bad.bsdf", tensor_file_bytes(arrays)))
    assert field in e.value.where and problem in e.value.problem and str(e.value).startswith("bad.bsdf (")


SMALL = tensor_file_bytes(rgl_arrays(MODEL, layout=SMALL_LAYOUT))
FUZZ = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@FUZZ
@given(at=st.integers(min_value=0, max_value=len(SMALL) - 1), value=st.integers(0, 255), cut=st.booleans())
def test_damaged_files_raise_one_format_error(at, value, cut):
    load_damaged(SMALL, at, value, cut, "f.bsdf", read_rgl_brdf)
