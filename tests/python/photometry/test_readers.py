"""Photometric files (IES LM-63, EULUMDAT) and luminaires: tables reproduced at their knots and
interpolated bilinearly between, flux of the bundled files against their declared lumens,
every symmetry expanded to the table it was cut from, IES and EULUMDAT of one luminaire
equal, the angle conventions, and bad or damaged files refused with a FormatError naming
the line (hypothesis for both readers)."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import patina
from conftest import ROOT, load_or_format_error
from patina.photometry import angles_of, direction_of, read_photometry
from patina.photometry.writers import format_ies, format_ldt

LUM = os.path.join(ROOT, "materials", "luminaires")
BUNDLED = ["downlight.ies", "streetlight.ies", "streetlight.ldt", "floodlight.ies"]
FLUX_TOLERANCE = 0.005  # the tables sample smooth models every 2.5 deg; measured error <= 0.1 %


def model_c(c: np.ndarray, g: np.ndarray) -> np.ndarray:
    """An asymmetric type C distribution (no symmetry at all)."""
    return (
        100 + 900 * np.cos(np.radians(g / 2)) ** 2 * (1.3 + np.cos(np.radians(c - 30))) + 40 * np.sin(np.radians(2 * c))
    )


def write(tmp_path, name: str, text: str | bytes) -> str:
    path = os.path.join(tmp_path, name)
    with open(path, "wb") as f:
        f.write(text.encode("latin-1") if isinstance(text, str) else text)
    return path


def random_directions(n: int, seed: int = 0) -> np.ndarray:
    d = np.random.default_rng(seed).normal(size=(n, 3))
    return d / np.linalg.norm(d, axis=1, keepdims=True)


# ---------------------------------------------------------------- bundled files, flux, interpolation


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_flux_equals_declared_lumens(name):
    lum = patina.load_luminaire(os.path.join(LUM, name))
    p = lum.photometry
    assert p.lumens is not None  # the bundled luminaires pass all their lamps' light: light output ratio 1
    assert abs(lum.flux() / p.lumens - 1) < FLUX_TOLERANCE
    if p.luminaire_lumens is not None:  # EULUMDAT: lamp flux x LORL, as stated
        assert abs(lum.flux() / p.luminaire_lumens - 1) < FLUX_TOLERANCE
    assert os.path.isfile(os.path.join(LUM, os.path.splitext(name)[0] + ".md"))


@pytest.mark.parametrize("name", BUNDLED)
def test_bundled_poles_have_one_value(name):
    """Straight down (type C gamma 0) every C plane gives the same candela, and the type B poles
    H = +-90 the same across V planes: the generator's models are functions of the direction."""
    p = read_photometry(os.path.join(LUM, name))
    assert p.warnings == []
    if p.type == "C":
        for j in np.flatnonzero(np.isin(p.v_deg, [0.0, 180.0])):
            assert np.ptp(p.candela[:, j]) == 0, (name, p.v_deg[j])
    else:
        for i in np.flatnonzero(np.isin(p.h_deg, [-90.0, 90.0])):
            lit = np.abs(p.v_deg) <= 90  # the file's own V range (dark behind, past |V| = 90)
            assert np.ptp(p.candela[i, lit]) == 0, (name, p.h_deg[i])


def test_flux_is_exact_for_known_distributions(tmp_path):
    # isotropic 100 cd -> 400 pi lm; Lambertian downlight I0 cos(g) on a fine grid -> pi I0
    g = np.linspace(0, 180, 7)
    iso = patina.load_luminaire(write(tmp_path, "iso.ies", format_ies([0], g, np.full((1, 7), 100.0))))
    assert iso.flux() == pytest.approx(400 * np.pi, rel=1e-6)
    g = np.linspace(0, 90, 721)
    lam = patina.load_luminaire(
        write(tmp_path, "lam.ies", format_ies([0], g, [1000 * np.cos(np.radians(g))], fmt="{:.9g}"))
    )
    assert lam.flux() == pytest.approx(1000 * np.pi, rel=1e-5)
    # the type B weights: isotropic front hemisphere, 50 cd
    h, v = np.linspace(-90, 90, 7), np.linspace(-90, 90, 5)
    hemi = patina.load_luminaire(write(tmp_path, "b.ies", format_ies(h, v, np.full((7, 5), 50.0), photometric_type=2)))
    assert hemi.flux() == pytest.approx(50 * 2 * np.pi, rel=1e-4)  # plus the 0.01 deg drop past V = +-90


@pytest.mark.parametrize("kind", ["C", "B"])
def test_flux_equals_brute_force_integration_of_the_interpolated_table(tmp_path, kind):
    rng = np.random.default_rng(11)
    if kind == "C":
        h = np.concatenate([[0], np.sort(rng.uniform(1, 359, 9)), [360]])
        v = np.concatenate([[0], np.sort(rng.uniform(1, 179, 12)), [180]])
    else:
        h = np.concatenate([[-90], np.sort(rng.uniform(-89, 89, 9)), [90]])
        v = np.concatenate([[-90], np.sort(rng.uniform(-89, 89, 12)), [90]])
    table = rng.uniform(0, 1000, (len(h), len(v)))
    if kind == "B":
        table[:, [0, -1]] = 0  # no 0.01 deg drop at V = +-90, which a 0.1 deg grid cannot resolve
    path = write(tmp_path, "r.ies", format_ies(h, v, table, photometric_type=1 if kind == "C" else 2, fmt="{:.9g}"))
    lum = patina.load_luminaire(path)
    # midpoint rule on a 0.1 deg grid in the table's own angles, with the solid-angle density
    step = np.radians(0.1)
    hs = np.arange(0, 2 * np.pi, step) + step / 2 if kind == "C" else np.arange(-np.pi / 2, np.pi / 2, step) + step / 2
    vs = np.arange(0, np.pi, step) + step / 2 if kind == "C" else np.arange(-np.pi, np.pi, step) + step / 2
    hh, vv = np.meshgrid(hs, vs, indexing="ij")
    density = np.sin(vv) if kind == "C" else np.cos(hh)
    brute = float(np.sum(lum.intensity(vv.astype(np.float32), hh.astype(np.float32)) * density)) * step * step
    assert lum.flux() == pytest.approx(brute, rel=2e-5)


def bilinear(hk, vk, table, h, v):
    """Numpy bilinear reference, clamped."""
    i = np.clip(np.searchsorted(hk, h, side="right") - 1, 0, len(hk) - 2)
    j = np.clip(np.searchsorted(vk, v, side="right") - 1, 0, len(vk) - 2)
    s = np.clip((h - hk[i]) / (hk[i + 1] - hk[i]), 0, 1)
    t = np.clip((v - vk[j]) / (vk[j + 1] - vk[j]), 0, 1)
    return (
        table[i, j] * (1 - s) * (1 - t)
        + table[i + 1, j] * s * (1 - t)
        + table[i, j + 1] * (1 - s) * t
        + table[i + 1, j + 1] * s * t
    )


@pytest.mark.parametrize("name", ["streetlight.ies", "floodlight.ies"])
def test_intensity_reproduces_the_table_and_interpolates_bilinearly(name):
    lum = patina.load_luminaire(os.path.join(LUM, name))
    kind, hk, vk, table = lum.grid()
    assert kind == lum.photometry.type and table.dtype == np.float32
    # the file's own numbers at the file's own knots
    raw = read_photometry(os.path.join(LUM, name))
    hh, vv = np.meshgrid(np.radians(raw.file_h_deg), np.radians(raw.file_v_deg), indexing="ij")
    got = lum.intensity(vv.astype(np.float32), hh.astype(np.float32))
    with open(os.path.join(LUM, name)) as f:
        numbers = f.read().split("TILT=NONE")[1].split()
    n_v, n_h = int(numbers[3]), int(numbers[4])
    file_cd = np.array(numbers[13 + n_v + n_h :], float).reshape(n_h, n_v)
    assert np.allclose(got, file_cd, rtol=1e-6, atol=1e-3)
    # between knots: bilinear in (h, v) radians
    rng = np.random.default_rng(1)
    h = rng.uniform(hk[0], hk[-1], 5000).astype(np.float32)
    v = rng.uniform(vk[0], vk[-1], 5000).astype(np.float32)
    ref = bilinear(hk.astype(float), vk.astype(float), table.astype(float), h.astype(float), v.astype(float))
    assert np.abs(lum.intensity(v, h) - ref).max() <= 1e-5 * table.max()


def test_intensity_at_matches_the_angle_conventions():
    lum = patina.load_luminaire(os.path.join(LUM, "streetlight.ldt"))
    d = random_directions(2000)
    h, v = angles_of(d, "C")
    assert np.allclose(lum.intensity_at(d), lum.intensity(v, h))
    # the street side is C0 = +X: brighter at gamma 65 towards +X than towards -X
    dirs = direction_of(np.radians([0, 180]), np.radians([65, 65]), "C")
    street, house = lum.intensity_at(dirs)
    assert street > 2 * house


def test_angle_conventions():
    assert np.allclose(direction_of(0, 0, "C"), [0, 0, -1])  # nadir is -Z
    assert np.allclose(direction_of(0, np.pi / 2, "C"), [1, 0, 0])  # C0 contains +X
    assert np.allclose(direction_of(np.pi / 2, np.pi / 2, "C"), [0, 1, 0])  # C90 contains +Y
    assert np.allclose(direction_of(0, np.pi, "C"), [0, 0, 1])
    assert np.allclose(direction_of(0, 0, "B"), [0, 0, 1])  # the beam axis is +Z
    assert np.allclose(direction_of(0, np.pi / 2, "B"), [0, 1, 0])  # V up
    assert np.allclose(direction_of(np.pi / 2, 0, "B"), [-1, 0, 0])  # H clockwise seen from above
    rng = np.random.default_rng(2)
    for kind, hr, vr in (("C", (0, 2 * np.pi), (0, np.pi)), ("B", (-np.pi / 2, np.pi / 2), (-np.pi, np.pi))):
        h, v = rng.uniform(*hr, 1000), rng.uniform(*vr, 1000)
        d = direction_of(h, v, kind)
        assert np.allclose(np.linalg.norm(d, axis=-1), 1)
        h2, v2 = angles_of(d, kind)
        assert np.allclose(direction_of(h2, v2, kind), d, atol=1e-12)
        assert np.allclose(h2, h) and np.allclose(v2, v)


def test_ies_and_ldt_of_the_street_light_agree():
    a = patina.load_luminaire(os.path.join(LUM, "streetlight.ies"))
    b = patina.load_luminaire(os.path.join(LUM, "streetlight.ldt"))
    d = random_directions(20000, 3)
    ia, ib = a.intensity_at(d), b.intensity_at(d)
    assert np.abs(ia - ib).max() < 1e-5 * ia.max() + 0.01
    assert a.flux() == pytest.approx(b.flux(), rel=1e-5)


def test_type_b_floodlight_is_mirrored_and_dark_behind():
    lum = patina.load_luminaire(os.path.join(LUM, "floodlight.ies"))
    p = lum.photometry
    assert p.type == "B" and p.h_deg[0] == -90 and p.h_deg[-1] == 90 and p.v_deg[0] == -180 and p.v_deg[-1] == 180
    h = np.radians(np.linspace(-80, 80, 33))
    v = np.full_like(h, np.radians(10))
    assert np.allclose(lum.intensity(v, h), lum.intensity(v, -h))
    d = random_directions(1000, 4)
    behind = d[d[:, 2] < -0.01]
    assert np.all(lum.intensity_at(behind) == 0)
    assert lum.intensity_at(np.array([[0.0, 0.0, 1.0]]))[0] > 0.9 * p.candela.max()


# ---------------------------------------------------------------- symmetries


def full_table(step_c=15.0, step_g=10.0):
    c = np.arange(0, 360 + 1e-9, step_c)
    g = np.arange(0, 180 + 1e-9, step_g)
    return c, g


def sym_model(kind: str, c: np.ndarray, g: np.ndarray) -> np.ndarray:
    base = 500 + 400 * np.cos(np.radians(g))
    if kind == "rotational":
        return base + 0 * c
    if kind == "quadrant":  # symmetric about C0-C180 and C90-C270
        return base + 150 * np.cos(np.radians(2 * c)) * np.sin(np.radians(g))
    if kind == "bilateral":  # about C0-C180: I(C) = I(-C)
        return base + 150 * np.cos(np.radians(c)) * np.sin(np.radians(g)) + 60 * np.cos(np.radians(3 * c))
    if kind == "bilateral-90-270":  # about C90-C270: I(C) = I(180 - C)
        return base + 150 * np.sin(np.radians(c)) * np.sin(np.radians(g)) + 60 * np.sin(np.radians(3 * c))
    raise AssertionError(kind)


@pytest.mark.parametrize(
    ("kind", "lo", "hi"),
    [("rotational", 0, 0), ("quadrant", 0, 90), ("bilateral", 0, 180), ("bilateral-90-270", 90, 270)],
)
def test_ies_symmetries_expand_to_the_full_file(tmp_path, kind, lo, hi):
    c, g = full_table()
    cc, gg = np.meshgrid(c, g, indexing="ij")
    table = sym_model(kind, cc, gg)
    full = patina.load_luminaire(write(tmp_path, "full.ies", format_ies(c, g, table, fmt="{:.9g}")))
    keep = (c >= lo) & (c <= hi)
    cut = patina.load_luminaire(write(tmp_path, "cut.ies", format_ies(c[keep], g, table[keep], fmt="{:.9g}")))
    assert cut.photometry.symmetry == kind and full.photometry.symmetry == "none"
    assert cut.photometry.h_deg[0] == 0 and cut.photometry.h_deg[-1] == 360
    d = random_directions(5000, 5)
    assert np.allclose(cut.intensity_at(d), full.intensity_at(d), rtol=1e-5, atol=1e-3)
    assert cut.flux() == pytest.approx(full.flux(), rel=1e-6)


@pytest.mark.parametrize(
    ("isym", "kind"), [(0, None), (1, "rotational"), (2, "bilateral"), (3, "bilateral-90-270"), (4, "quadrant")]
)
def test_ldt_symmetries_expand_to_the_full_table(tmp_path, isym, kind):
    c, g = full_table()
    cc, gg = np.meshgrid(c, g, indexing="ij")
    table = model_c(cc, gg) if kind is None else sym_model(kind, cc, gg)
    table[-1] = table[0]
    ref = patina.load_luminaire(write(tmp_path, "full.ies", format_ies(c, g, table, fmt="{:.9g}")))
    mc = len(c) - 1  # 0..345
    stored = {0: np.arange(mc), 1: [0], 2: np.arange(mc // 2 + 1), 4: np.arange(mc // 4 + 1)}.get(isym)
    if isym == 3:
        stored = (3 * mc // 4 + np.arange(mc // 2 + 1)) % mc
    flux = 2000.0
    ldt = format_ldt(c[:-1], g, table[stored] / (flux / 1000), isym=isym, lamp_flux=flux, fmt="{:.9g}")
    lum = patina.load_luminaire(write(tmp_path, "f.ldt", ldt))
    d = random_directions(5000, 6)
    assert np.allclose(lum.intensity_at(d), ref.intensity_at(d), rtol=1e-5, atol=1e-3)


def test_ies_full_range_without_360_repeats_0(tmp_path):
    c, g = full_table()
    cc, gg = np.meshgrid(c, g, indexing="ij")
    table = model_c(cc, gg)
    table[-1] = table[0]
    a = patina.load_luminaire(write(tmp_path, "a.ies", format_ies(c, g, table, fmt="{:.9g}")))
    b = patina.load_luminaire(write(tmp_path, "b.ies", format_ies(c[:-1], g, table[:-1], fmt="{:.9g}")))
    assert np.array_equal(a.photometry.h_deg, b.photometry.h_deg)
    assert np.array_equal(a.photometry.candela, b.photometry.candela)


def test_half_sphere_tables_are_dark_beyond_their_range(tmp_path):
    g = np.arange(0, 90 + 1e-9, 10)
    lum = patina.load_luminaire(write(tmp_path, "d.ies", format_ies([0], g, [np.full(len(g), 200.0)])))
    gammas = np.radians([0, 45, 90, 90.02, 120, 180])
    assert np.allclose(lum.intensity(gammas, np.zeros(6)), [200, 200, 200, 0, 0, 0])
    up = patina.load_luminaire(write(tmp_path, "u.ies", format_ies([0], g + 90, [np.full(len(g), 50.0)])))
    assert np.allclose(up.intensity(np.radians([0, 89.98, 90, 180]), np.zeros(4)), [0, 0, 50, 50])


# ---------------------------------------------------------------- header variants


def test_versions_keywords_and_multipliers(tmp_path):
    g = np.array([0.0, 45.0, 90.0])
    cd = [[100.0, 80.0, 10.0]]
    kw = {"TEST": "T1", "MANUFAC": "Acme \xe9clairage", "LUMINAIRE": "line one\nline two", "LUMCAT": "X-1"}
    for version, second, applied in (
        ("LM-63-1986", 0.9, 0.9),
        ("LM-63-1991", 0.9, 0.9),
        ("LM-63-1995", 0.9, 0.9),
        ("LM-63-2002", 1.0, 1.0),
        ("LM-63-2019", 1.10000, 1.0),
    ):
        text = format_ies(
            [0],
            g,
            cd,
            version=version,
            keywords=kw,
            lamps=2,
            lumens_per_lamp=500,
            multiplier=1.5,
            ballast=0.8,
            second_factor=second,
            watts=30,
        )
        p = read_photometry(write(tmp_path, f"{version}.ies", text))
        assert p.version == version
        assert p.lumens == 1000 and p.lamps == 2 and p.input_watts == 30
        assert p.multiplier == pytest.approx(1.5 * 0.8 * applied)
        assert p.candela[0, 0] == pytest.approx(100 * 1.5 * 0.8 * applied)
        assert p.luminaire_lumens is None  # LM-63 states no luminaire flux
        assert p.lumens == 1000  # the lamp lumens, never times a candela multiplier
        assert p.manufacturer == "Acme \xe9clairage" and p.catalogue == "X-1"
        assert p.keywords["LUMINAIRE"] == "line one\nline two"  # [MORE] continues the keyword


def test_latin1_crlf_lf_and_commas_read_alike(tmp_path):
    g = np.array([0.0, 30.0, 60.0, 90.0])
    text = format_ies([0, 90], g, [[100, 90, 50, 0], [100, 80, 40, 0]], keywords={"MANUFAC": "Lumi\xe8re"})
    a = read_photometry(write(tmp_path, "a.ies", text))
    b = read_photometry(write(tmp_path, "b.ies", text.replace("\r\n", "\n").replace(" ", ", ")))
    c = read_photometry(write(tmp_path, "c.ies", text.encode("utf-8")))
    assert np.array_equal(a.candela, b.candela) and np.array_equal(a.candela, c.candela)
    assert a.manufacturer == c.manufacturer == "Lumi\xe8re"


def test_absolute_photometry(tmp_path):
    g = np.array([0.0, 45.0, 90.0])
    p = read_photometry(
        write(tmp_path, "abs.ies", format_ies([0], g, [[300, 200, 0]], lumens_per_lamp=-1, multiplier=2))
    )
    assert p.lumens is None and p.luminaire_lumens is None
    assert p.candela[0, 0] == 600
    info = patina.load_luminaire(p.path).info()
    assert info["absolute_photometry"] and info["lumens_integrated"] > 0


def test_tilt_include_and_tilt_file(tmp_path):
    g = np.array([0.0, 45.0, 90.0])
    tilt = (1, [0, 15, 30, 45, 60, 75, 90], [1, 0.98, 0.95, 0.9, 0.85, 0.8, 0.7])
    p = read_photometry(write(tmp_path, "t.ies", format_ies([0], g, [[300, 200, 0]], tilt="INCLUDE", tilt_block=tilt)))
    assert p.tilt is not None and p.tilt.geometry == 1
    assert np.array_equal(p.tilt.angles_deg, tilt[1]) and np.array_equal(p.tilt.factors, tilt[2])
    assert p.candela[0, 0] == 300
    os.makedirs(os.path.join(tmp_path, "sub"))
    write(os.path.join(tmp_path, "sub"), "lamp.tlt", "2\n3\n0 45 90\n1 0.9 0.8\n")
    q = read_photometry(write(os.path.join(tmp_path, "sub"), "f.ies", format_ies([0], g, [[1, 2, 3]], tilt="lamp.tlt")))
    assert q.tilt is not None and q.tilt.geometry == 2 and list(q.tilt.factors) == [1, 0.9, 0.8]
    missing = write(tmp_path, "m.ies", format_ies([0], g, [[1, 2, 3]], tilt="nothere.tlt"))
    with pytest.raises(patina.FormatError) as e:
        read_photometry(missing)
    assert e.value.where == "line 2" and "nothere.tlt" in e.value.problem and "does not exist" in e.value.problem


def test_type_a_is_refused_with_a_reason(tmp_path):
    path = write(tmp_path, "a.ies", format_ies([0, 90], [-90, 0, 90], np.ones((2, 3)), photometric_type=3))
    with pytest.raises(patina.FormatError, match="type A"):
        read_photometry(path)


# ---------------------------------------------------------------- bad files name their line

GOOD_IES = format_ies(
    [0, 90], [0.0, 45.0, 90.0], [[100, 50, 0], [90, 40, 0]], version="LM-63-2002", keywords={"TEST": "x"}
)
# line 1 version, 2 [TEST], 3 TILT, 4 counts, 5 ballast, 6 vertical angles, 7 horizontal, 8-9 candela


def _ies_variant(change: str) -> str:
    lines = GOOD_IES.split("\r\n")
    edits = {
        "truncated": lambda: lines[:8],
        "fewer candela": lambda: [*lines[:8], "90 40"],
        "more candela": lambda: [*lines[:9], "7"],
        "not a number": lambda: [*lines[:8], "90 4O 0"],
        "negative candela": lambda: [*lines[:8], "90 -40 0"],
        "angles not ascending": lambda: [*lines[:5], "0 90 45", *lines[6:]],
        "bad horizontal range": lambda: [*lines[:6], "0 45", *lines[7:]],
        "huge counts": lambda: [*lines[:3], "1 1000 1 3000000 4000000 1 2 0 0 0", *lines[4:]],
        "bad type": lambda: [*lines[:3], "1 1000 1 3 2 7 2 0 0 0", *lines[4:]],
        "no tilt": lambda: [lines[0], lines[1]],
        "nan": lambda: [*lines[:8], "90 nan 0"],
    }
    return "\r\n".join(edits[change]())


@pytest.mark.parametrize(
    ("change", "line", "words"),
    [
        ("truncated", "line 8", "declares 11 values but only 8"),
        ("fewer candela", "line 9", "declares 11 values but only 10"),
        ("more candela", "line 10", "do not match"),
        ("not a number", "line 9", "'4O' is not a number"),
        ("negative candela", "line 9", "negative"),
        ("angles not ascending", "line 6", "must increase"),
        ("bad horizontal range", "line 7", "0-90, 0-180"),
        ("huge counts", "line 9", "only"),
        ("bad type", "line 4", "photometric type 7"),
        ("no tilt", "line 2", "no TILT"),
        ("nan", "line 9", "not a number"),
    ],
)
def test_bad_ies_files_name_the_line(tmp_path, change, line, words):
    path = write(tmp_path, "bad.ies", _ies_variant(change))
    with pytest.raises(patina.FormatError) as e:
        patina.load_luminaire(path)
    assert e.value.path == path and e.value.where == line and words in e.value.problem, str(e.value)


GOOD_LDT = format_ldt(
    [0, 90, 180, 270], [0, 45, 90], np.array([[100, 50, 0], [90, 40, 0], [80, 30, 0]]), isym=2, lamp_flux=1000
)
# lines 1-25 header, 26 sets, 27-32 lamp set, 33-42 direct ratios, 43-46 C angles, 47-49 gamma, 50-58 intensities


def _ldt_variant(line_no: int, text: str | None) -> str:
    lines = GOOD_LDT.split("\r\n")[:-1]
    if text is None:
        return "\r\n".join(lines[: line_no - 1]) + "\r\n"
    lines[line_no - 1] = text
    return "\r\n".join(lines) + "\r\n"


@pytest.mark.parametrize(
    ("line_no", "text", "where", "words"),
    [
        (3, "7", "line 3", "Isym 7"),
        (3, "x", "line 3", "not a number"),
        (4, "5", "line 4", "Mc must be even"),
        (6, "-1", "line 6", "at least 1"),
        (26, "500", "line 26", "lamp sets"),
        (29, "-5", "line 29", "must be positive"),
        (45, "200", "line 45", "Isym 2 needs C plane 3 at 180"),
        (48, "100", "line 49", "90 deg follows 100 deg"),
        (52, "-3", "line 52", "negative"),
        (55, "abc", "line 55", "not a number"),
        (56, None, "line 55", "declares"),
        (20, None, "line 19", "the file ends"),
        (6, "3000000", "line 58", "only"),
    ],
)
def test_bad_ldt_files_name_the_line(tmp_path, line_no, text, where, words):
    path = write(tmp_path, "bad.ldt", _ldt_variant(line_no, text))
    with pytest.raises(patina.FormatError) as e:
        patina.load_luminaire(path)
    assert e.value.path == path and e.value.where == where and words in e.value.problem, str(e.value)


def test_ldt_good_base_reads(tmp_path):
    p = read_photometry(write(tmp_path, "ok.ldt", GOOD_LDT))
    assert p.symmetry == "bilateral" and p.candela[0, 0] == pytest.approx(100.0)  # 100 cd/klm x 1 klm


# ---------------------------------------------------------------- one direction, one value: warnings at the poles


def _streetlight_like(c: np.ndarray, g: np.ndarray) -> np.ndarray:
    """The old bundled street light's mistake: its street-side factor 1 + 0.5 cos C applied
    straight down too (3616 cd at C0, 1205 cd at C180 at gamma 0)."""
    return 2410.95 * (0.35 * np.cos(np.radians(g)) + 0.1) * (1 + 0.5 * np.cos(np.radians(c)))


def test_pole_values_that_differ_across_planes_warn(tmp_path):
    c, g = np.arange(0, 180 + 1e-9, 15.0), np.arange(0, 90 + 1e-9, 10.0)
    cc, gg = np.meshgrid(c, g, indexing="ij")
    path = write(tmp_path, "street.ies", format_ies(c, g, _streetlight_like(cc, gg), fmt="{:.2f}"))
    p = read_photometry(path)
    assert len(p.warnings) == 1
    w = p.warnings[0]
    # one line: the file, the place (the lines of the two extreme values), the problem
    assert "\n" not in w and w.startswith(f"{path} (line ")
    assert "gamma 0 deg" in w and "straight down" in w and "C0" in w and "C180" in w and "13 C planes" in w
    table = _streetlight_like(cc, gg)
    lines = open(path).read().splitlines()
    c0_sweep = 1 + next(i for i, ln in enumerate(lines) if ln.startswith(f"{table[0, 0]:.2f} "))
    assert f"(line {c0_sweep}, " in w  # the brightest value, straight down in C0
    # the same table as EULUMDAT (cd/klm) warns the same way, in absolute candela
    ldt = format_ldt(np.arange(0, 360, 15.0), g, table / 2.0, isym=2, lamp_flux=2000.0, fmt="{:.6g}")
    q = read_photometry(write(tmp_path, "street.ldt", ldt))
    assert len(q.warnings) == 1 and "gamma 0 deg" in q.warnings[0] and f"{table[0, 0]:.6g} cd at C0" in q.warnings[0]


def test_pole_warnings_zenith_type_b_and_the_360_plane(tmp_path):
    # gamma 180 (straight up) differs across planes; gamma 0 agrees
    c, g = np.array([0.0, 90.0, 180.0]), np.array([0.0, 90.0, 180.0])
    up = read_photometry(
        write(tmp_path, "up.ies", format_ies(c, g, [[500, 300, 100], [500, 300, 40], [500, 300, 100]]))
    )
    assert len(up.warnings) == 1 and "gamma 180 deg (straight up)" in up.warnings[0]
    # type B: H = 90 is the luminaire's -X axis whatever V
    h, v = np.array([0.0, 45.0, 90.0]), np.array([-90.0, 0.0, 90.0])
    b = read_photometry(
        write(tmp_path, "b.ies", format_ies(h, v, [[50, 900, 50], [40, 500, 40], [5, 60, 5]], photometric_type=2))
    )
    assert len(b.warnings) == 1 and "H 90 deg" in b.warnings[0] and "-X" in b.warnings[0]
    # a file listing C360 keeps that measured plane even where it differs from C0, and says so
    c = np.array([0.0, 90.0, 180.0, 270.0, 360.0])
    rows = np.array([[800, 400, 0], [800, 300, 0], [800, 200, 0], [800, 300, 0], [800, 450, 0]], float)
    kept = read_photometry(write(tmp_path, "seam.ies", format_ies(c, [0.0, 45.0, 90.0], rows)))
    assert kept.symmetry == "none" and kept.h_deg[-1] == 360
    assert np.array_equal(kept.candela[-1, :3], rows[-1]) and np.array_equal(kept.candela[0, :3], rows[0])
    assert len(kept.warnings) == 1 and "C0 and C360" in kept.warnings[0]


def test_consistent_or_noisy_poles_and_dark_poles_do_not_warn(tmp_path):
    c, g = np.array([0.0, 90.0, 180.0]), np.array([0.0, 45.0, 90.0, 180.0])
    agree = [[1000, 600, 10, 0.0], [1000, 500, 10, 0.0], [1000, 400, 10, 0.0]]
    noisy = [[1000, 600, 10, 0.0], [1004, 500, 10, 0.2], [996, 400, 10, 0.0]]  # 0.8 % at nadir, a dark zenith
    for name, table in (("agree", agree), ("noisy", noisy)):
        assert read_photometry(write(tmp_path, f"{name}.ies", format_ies(c, g, table))).warnings == []
    # one plane (rotational symmetry) has nothing to disagree with
    assert read_photometry(write(tmp_path, "one.ies", format_ies([0], g, [[5, 4, 3, 2]]))).warnings == []


def test_the_generator_writes_pole_consistent_files(tmp_path):
    """tools/make_luminaires.py regenerates the bundled files exactly, and its models give each
    pole one value (the generator refuses to write a table that does not)."""
    import subprocess
    import sys

    r = subprocess.run(
        [sys.executable, os.path.join(ROOT, "tools", "make_luminaires.py"), "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert r.returncode == 0, r.stderr
    for name in BUNDLED:
        with open(os.path.join(tmp_path, name), "rb") as a, open(os.path.join(LUM, name), "rb") as b:
            assert a.read() == b.read(), f"{name}: the bundled file is not what the generator writes"


# ---------------------------------------------------------------- IES headers: legacy versions, keyword values


@pytest.mark.parametrize(
    ("first_line", "version"),
    [
        ("IESNA:LM-63-1995", "LM-63-1995"),
        ("IESNA95", "LM-63-1995"),
        ("IESNA 95", "LM-63-1995"),
        ("IESNA:LM-63-95", "LM-63-1995"),
        ("IESNA91", "LM-63-1991"),
        ("IESNA:LM-63-1991", "LM-63-1991"),
        ("IESNA LM-63-2002", "LM-63-2002"),
        ("iesna:lm-63-2002", "LM-63-2002"),
        ("IES:LM-63-2019", "LM-63-2019"),
    ],
)
def test_legacy_version_lines(tmp_path, first_line, version):
    text = format_ies([0], [0.0, 90.0], [[100.0, 10.0]], version="LM-63-1995", ballast=0.8, second_factor=0.5)
    text = first_line + text[text.index("\r\n") :]
    p = read_photometry(write(tmp_path, "v.ies", text))
    assert p.version == version and p.warnings == [] and "text" not in p.extra
    old = version in ("LM-63-1991", "LM-63-1995")  # the ballast-lamp factor applies before LM-63-2002
    assert p.candela[0, 0] == pytest.approx(100 * 0.8 * (0.5 if old else 1.0))


def test_an_unknown_version_line_is_read_as_1986_and_says_so(tmp_path):
    text = format_ies([0], [0.0, 90.0], [[100.0, 10.0]], version="LM-63-1986", second_factor=0.5)
    p = read_photometry(write(tmp_path, "u.ies", "IESNA:LM-63-XYZ\r\n" + text))
    assert p.version == "LM-63-1986" and p.extra["text"] == "IESNA:LM-63-XYZ"
    assert len(p.warnings) == 1 and "(line 1)" in p.warnings[0] and "LM-63-1986" in p.warnings[0]
    assert p.candela[0, 0] == pytest.approx(50.0)


def test_keyword_values_lose_their_surrounding_blanks(tmp_path):
    text = (
        "IESNA95\r\n[TEST]    T-7  \r\n[MANUFAC]\tAcme Lighting\r\n[LUMINAIRE]   line one\r\n[MORE]    line two \r\n"
        "[LUMCAT]\r\nTILT=NONE\r\n1 1000 1 2 1 1 2 0 0 0\r\n1 1 10\r\n0 90\r\n0\r\n100 10\r\n"
    )
    p = read_photometry(write(tmp_path, "k.ies", text))
    assert p.version == "LM-63-1995"
    assert p.keywords == {"TEST": "T-7", "MANUFAC": "Acme Lighting", "LUMINAIRE": "line one\nline two", "LUMCAT": ""}
    assert p.manufacturer == "Acme Lighting" and p.luminaire == "line one\nline two"


# ---------------------------------------------------------------- flux against the lamp lumens


def test_flux_is_reported_against_the_lamp_lumens_not_times_the_multiplier(tmp_path):
    """A relative file in cd/klm whose multiplier (3 = 3000 lm / 1000) makes the candela absolute:
    the table's flux is compared with the 3000 lamp lumens (light output ratio), never with
    3000 x 3."""
    g = np.linspace(0, 90, 181)
    per_klm = 1000 / np.pi * 0.8 * np.cos(np.radians(g))  # 800 lm of every 1000 lamp lumens leave
    path = write(tmp_path, "klm.ies", format_ies([0], g, [per_klm], lumens_per_lamp=3000, multiplier=3, fmt="{:.9g}"))
    lum = patina.load_luminaire(path)
    p = lum.photometry
    assert p.lumens == 3000 and p.multiplier == 3 and p.luminaire_lumens is None
    assert lum.flux() / p.lumens == pytest.approx(0.8, rel=1e-4)  # the light output ratio
    assert lum.info()["light_output_ratio"] == pytest.approx(0.8, rel=1e-4)
    # EULUMDAT states the luminaire flux itself (lamp flux x LORL); the conversion factor scales
    # the intensities only
    lines = format_ldt([0.0], g, [per_klm], isym=1, lamp_flux=3000, lorl=80).split("\r\n")
    lines[23] = "2"  # line 24: conversion factor
    q = read_photometry(write(tmp_path, "klm.ldt", "\r\n".join(lines)))
    assert q.lumens == 3000 and q.luminaire_lumens == pytest.approx(2400) and q.multiplier == pytest.approx(6)
    assert patina.load_luminaire(q.path).flux() == pytest.approx(2 * 2400, rel=1e-4)


# ---------------------------------------------------------------- the docs say what the code does


def test_docs_luminaires_and_astm_agree_with_the_code(tmp_path):
    lum_doc = open(os.path.join(ROOT, "docs", "luminaires.md"), encoding="utf-8").read()
    astm_doc = open(os.path.join(ROOT, "docs", "astm.md"), encoding="utf-8").read()
    # the 360 plane: repeated from C0 only where the file does not list it (kept otherwise:
    # test_pole_warnings_zenith_type_b_and_the_360_plane)
    assert "(the 360 column repeats 0)" not in lum_doc and "measured C360 plane is kept" in lum_doc
    c, g = full_table()
    cc, gg = np.meshgrid(c, g, indexing="ij")
    short = read_photometry(write(tmp_path, "s.ies", format_ies(c[:-1], g, model_c(cc, gg)[:-1], fmt="{:.9g}")))
    assert short.h_deg[-1] == 360 and np.array_equal(short.candela[-1], short.candela[0])
    # the fields the docs name exist, and lumens_rated is not among them
    p = read_photometry(os.path.join(LUM, "streetlight.ldt"))
    for name in ("lumens", "luminaire_lumens", "warnings"):
        assert f"`{name}`" in lum_doc or f"`Photometry.{name}`" in lum_doc, name
        assert hasattr(p, name)
    assert "light_output_ratio" in lum_doc and "lumens_rated" not in lum_doc.split("## `info()`")[1].split("##")[0]
    # ASTM: scattered rows are resampled by load_brdf (and refused only by read_astm(resample=False))
    from patina.table.formats.astm import read_astm

    rng = np.random.default_rng(3)
    rows = ["VARS theta_i,phi_i,theta_s,phi_s,BRDF"]
    for ti, ts, ps in zip(rng.uniform(0, 1.4, 80), rng.uniform(0, 1.4, 80), rng.uniform(0, np.pi, 80)):
        rows.append(f"{ti:.6f},0,{ts:.6f},{ps:.6f},{0.2 + 0.1 * np.cos(ti) * np.cos(ts):.6f}")
    path = write(tmp_path, "scattered.astm", "#ASTM E1392-96\n" + "\n".join(rows) + "\n")
    with pytest.raises(patina.FormatError, match="not on a tensor grid"):
        read_astm(path)
    brdf = patina.load_brdf(path)
    assert "resampled from 80 scattered points" in brdf.info()["provenance"]
    assert "resampled" in astm_doc and "scattered data is rejected" not in astm_doc.lower()
    flat = " ".join(astm_doc.lower().split())
    assert "only a direct call `read_astm(path)` with the default `resample=false`" in flat


# ---------------------------------------------------------------- fuzz: FormatError and nothing else

FUZZ = settings(max_examples=120, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
STREET_IES = open(os.path.join(LUM, "streetlight.ies"), "rb").read()
SMALL_LDT = GOOD_LDT.encode()
SMALL_IES = GOOD_IES.encode()


def _check_luminaire(lum) -> None:
    out = lum.intensity_at(random_directions(16, 7))
    assert out.shape == (16,) and np.all(out >= 0) and np.isfinite(lum.flux())


def _load_or_format_error(data: bytes, suffix: str) -> None:
    load_or_format_error(data, "f" + suffix, patina.load_luminaire, _check_luminaire)


def _mutate(data: bytes, edits: list[tuple[int, int]]) -> bytes:
    b = bytearray(data)
    for pos, byte in edits:
        b[pos % len(b)] = byte
    return bytes(b)


@FUZZ
@given(st.integers(0, len(SMALL_IES)), st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 255)), max_size=4))
def test_fuzz_ies_truncated_and_mutated(cut, edits):
    _load_or_format_error(_mutate(SMALL_IES[:cut] or b"x", edits), ".ies")


@FUZZ
@given(st.integers(0, len(SMALL_LDT)), st.lists(st.tuples(st.integers(0, 10**6), st.integers(0, 255)), max_size=4))
def test_fuzz_ldt_truncated_and_mutated(cut, edits):
    _load_or_format_error(_mutate(SMALL_LDT[:cut] or b"x", edits), ".ldt")


@FUZZ
@given(st.binary(max_size=600), st.sampled_from([".ies", ".ldt"]))
def test_fuzz_random_bytes(data, suffix):
    _load_or_format_error(data, suffix)


TOKEN = st.sampled_from(
    ["0", "1", "-1", "2", "3", "90", "180", "360", "1e308", "-0", "4.5", "x", "", "1e9", "99999999"]
)


@FUZZ
@given(st.lists(st.tuples(st.integers(0, 80), TOKEN), min_size=1, max_size=6))
def test_fuzz_absurd_numbers_in_place(edits):
    """Whole numbers (counts, types, angles, candela) replaced by absurd ones, in both formats."""
    header, body = GOOD_IES.split("TILT=NONE\r\n")
    toks = body.split()
    for pos, value in edits:
        toks[pos % len(toks)] = value
    _load_or_format_error((header + "TILT=NONE\r\n" + " ".join(toks)).encode(), ".ies")
    lines = GOOD_LDT.split("\r\n")
    for pos, value in edits:
        lines[1 + pos % (len(lines) - 1)] = value
    _load_or_format_error("\r\n".join(lines).encode(), ".ldt")


@settings(max_examples=30, deadline=None)
@given(st.integers(0, len(STREET_IES)))
def test_fuzz_truncated_real_file(cut):
    _load_or_format_error(STREET_IES[:cut], ".ies")
