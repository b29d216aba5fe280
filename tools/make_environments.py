#!/usr/bin/env python3
"""Generates the bundled environment maps in materials/env/ from analytic models.

    PYTHONPATH=python .venv/bin/python tools/make_environments.py      # or the venv's python after make setup

studio.exr  a photographic studio: dim grey floor and walls, key, fill and rim soft boxes
            and a top strip (flat rectangular panels with soft edges), 1024 x 512 half float;
sky.exr     a clear sky (Preetham, Shirley and Smits 1999) with a sun disc (blackbody
            5772 K solar spectrum through Rayleigh and Angstrom aerosol extinction) over a
            grey ground (albedo 0.3), 1024 x 512 float (the sun exceeds half range).

Both follow patina.render.envmap's lat-long convention (Mitsuba 3's, y up) and units: linear
Rec.709 tristimulus radiance in W/(m^2 sr), 683 lm/W x Y = luminance in cd/m^2. The
materials/env/*.md provenance files give the parameters and the measured irradiance.
"""

from __future__ import annotations

import argparse
import math
import os
from dataclasses import dataclass

import colour
import numpy as np

from patina.colour_constants import LUMINOUS_EFFICACY
from patina.render.envmap import irradiance, lat_long_direction, pixel_directions, solid_angles
from patina.render.images import write_exr

OUT_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "materials", "env")
WIDTH, HEIGHT = 1024, 512
XYZ_TO_SRGB = np.asarray(colour.RGB_COLOURSPACES["sRGB"].matrix_XYZ_to_RGB)

# ---------------------------------------------------------------- studio


@dataclass(frozen=True)
class SoftBox:
    """A flat rectangular panel seen from the centre: 2 half_width x 2 half_height degrees
    (along the tangent and bitangent of its centre direction), uniform radiance (grey, in
    tristimulus W/(m^2 sr)) with edges blended over `edge` degrees."""

    name: str
    azimuth: float  # degrees, the map's phi: 0 is -z, 90 is +x
    elevation: float  # degrees above the horizon
    half_width: float
    half_height: float
    radiance: float
    edge: float = 4.0


STUDIO_BOXES = (
    SoftBox("key", azimuth=225.0, elevation=30.0, half_width=25.0, half_height=20.0, radiance=4.0),
    SoftBox("fill", azimuth=135.0, elevation=15.0, half_width=30.0, half_height=22.0, radiance=1.2),
    SoftBox("rim", azimuth=40.0, elevation=25.0, half_width=8.0, half_height=30.0, radiance=6.0),
    SoftBox("top", azimuth=0.0, elevation=90.0, half_width=40.0, half_height=5.0, radiance=5.0),
)
# grey background radiance: floor from nadir to horizon, walls from horizon to zenith
FLOOR_NADIR, FLOOR_HORIZON, WALL_HORIZON, WALL_ZENITH = 0.06, 0.03, 0.03, 0.012


def direction(azimuth_deg: float, elevation_deg: float) -> np.ndarray:
    """Unit direction for an azimuth (the map's phi) and an elevation above the horizon."""
    return lat_long_direction(azimuth_deg / 360.0, (90.0 - elevation_deg) / 180.0)


def smoothstep(edge0: float, edge1: float, x: np.ndarray) -> np.ndarray:
    t = np.clip((x - edge0) / (edge1 - edge0), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def soft_box_weight(box: SoftBox, d: np.ndarray) -> np.ndarray:
    """Coverage in [0, 1] of the soft box for directions d (..., 3)."""
    n = direction(box.azimuth, box.elevation)
    # panel axes: horizontal tangent, except for a panel overhead, which lies along x
    t = np.cross([0.0, 1.0, 0.0], n) if abs(n[1]) < 0.99 else np.array([1.0, 0.0, 0.0])
    t /= np.linalg.norm(t)
    b = np.cross(n, t)
    front = d @ n
    # angles from the centre along each axis (a flat panel bounds tan of each independently)
    a = np.degrees(np.arctan2(np.abs(d @ t), front))
    c = np.degrees(np.arctan2(np.abs(d @ b), front))
    inside_a = 1.0 - smoothstep(box.half_width - box.edge / 2, box.half_width + box.edge / 2, a)
    inside_c = 1.0 - smoothstep(box.half_height - box.edge / 2, box.half_height + box.edge / 2, c)
    return np.where(front > 0.0, inside_a * inside_c, 0.0)


def studio(width: int = WIDTH, height: int = HEIGHT) -> np.ndarray:
    """The studio map (height, width, 3), radiance in tristimulus W/(m^2 sr)."""
    d = pixel_directions(height, width)
    y = d[..., 1]
    floor = FLOOR_HORIZON + (FLOOR_NADIR - FLOOR_HORIZON) * np.clip(-y, 0.0, 1.0)
    walls = WALL_HORIZON + (WALL_ZENITH - WALL_HORIZON) * np.clip(y, 0.0, 1.0) ** 0.5
    grey = np.where(y < 0.0, floor, walls)
    for box in STUDIO_BOXES:
        w = soft_box_weight(box, d)
        grey = grey * (1.0 - w) + box.radiance * w
    return np.repeat(grey[..., None], 3, axis=2)


# ---------------------------------------------------------------- sky (Preetham et al. 1999)

TURBIDITY = 3.0
SUN_ELEVATION = 35.0  # degrees
SUN_AZIMUTH = 120.0  # degrees, the map's phi (u = 1/3): from -z towards +x
SUN_ANGULAR_DIAMETER = 0.53  # degrees
SOLAR_CONSTANT = 1361.0  # W/m^2, total solar irradiance at 1 AU (Kopp and Lean 2011)
SUN_TEMPERATURE = 5772.0  # K, the Sun's effective temperature (IAU 2015 B3)
GROUND_ALBEDO = 0.3

# Perez et al. coefficients (A..E) as linear functions of turbidity T: (slope, intercept),
# from Preetham, Shirley and Smits 1999, appendix A.2
PEREZ_Y = ((0.1787, -1.4630), (-0.3554, 0.4275), (-0.0227, 5.3251), (0.1206, -2.5771), (-0.0670, 0.3703))
PEREZ_X = ((-0.0193, -0.2592), (-0.0665, 0.0008), (-0.0004, 0.2125), (-0.0641, -0.8989), (-0.0033, 0.0452))
PEREZ_YC = ((-0.0167, -0.2608), (-0.0950, 0.0092), (-0.0079, 0.2102), (-0.0441, -1.6537), (-0.0109, 0.0529))
# zenith chromaticity: [T^2, T, 1] M [theta_s^3, theta_s^2, theta_s, 1]^T (appendix A.2)
ZENITH_X = np.array(
    [[0.00166, -0.00375, 0.00209, 0.0], [-0.02903, 0.06377, -0.03202, 0.00394], [0.11693, -0.21196, 0.06052, 0.25886]]
)
ZENITH_Y = np.array(
    [[0.00275, -0.00610, 0.00317, 0.0], [-0.04214, 0.08970, -0.04153, 0.00516], [0.15346, -0.26756, 0.06670, 0.26688]]
)


def perez(coefficients: tuple[tuple[float, float], ...], turbidity: float, cos_theta, gamma) -> np.ndarray:
    """The Perez et al. (1993) sky distribution F(theta, gamma)."""
    a, b, c, d, e = (slope * turbidity + intercept for slope, intercept in coefficients)
    return (1.0 + a * np.exp(b / cos_theta)) * (1.0 + c * np.exp(d * gamma) + e * np.cos(gamma) ** 2)


def preetham_xyY(
    cos_theta: np.ndarray, gamma: np.ndarray, theta_sun: float, turbidity: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sky chromaticity x, y and luminance Y (cd/m^2) at view zenith cos_theta, sun angle gamma."""
    chi = (4.0 / 9.0 - turbidity / 120.0) * (math.pi - 2.0 * theta_sun)
    zenith_luminance = 1000.0 * ((4.0453 * turbidity - 4.9710) * math.tan(chi) - 0.2155 * turbidity + 2.4192)
    t_row = np.array([turbidity**2, turbidity, 1.0])
    s_col = np.array([theta_sun**3, theta_sun**2, theta_sun, 1.0])
    zenith = {"x": t_row @ ZENITH_X @ s_col, "y": t_row @ ZENITH_Y @ s_col, "Y": zenith_luminance}
    cos_theta = np.maximum(cos_theta, 1e-3)  # the horizon itself: exp(B / cos) -> 0 either way
    out = []
    for key, coefficients in (("x", PEREZ_X), ("y", PEREZ_YC), ("Y", PEREZ_Y)):
        ratio = perez(coefficients, turbidity, cos_theta, gamma) / perez(coefficients, turbidity, 1.0, theta_sun)
        out.append(zenith[key] * ratio)
    return out[0], out[1], out[2]


def xyY_to_rgb_radiance(x: np.ndarray, y: np.ndarray, luminance: np.ndarray) -> np.ndarray:
    """Linear Rec.709 tristimulus radiance (W/(m^2 sr)) from chromaticity and luminance (cd/m^2)."""
    big_y = luminance / LUMINOUS_EFFICACY
    xyz = np.stack([x * big_y / y, big_y, (1.0 - x - y) * big_y / y], axis=-1)
    return xyz @ XYZ_TO_SRGB.T


def air_mass(zenith_deg: float) -> float:
    """Relative optical air mass, Kasten and Young (1989)."""
    return 1.0 / (math.cos(math.radians(zenith_deg)) + 0.50572 * (96.07995 - zenith_deg) ** -1.6364)


def solar_spectrum(turbidity: float, elevation_deg: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Wavelengths (nm), extraterrestrial and ground-level direct normal spectral irradiance
    (W/(m^2 nm)) from 280 nm to 4000 nm.

    Extraterrestrial: a blackbody at the Sun's effective temperature scaled to the solar
    constant. Extinction along the path (air mass of Kasten and Young): Rayleigh
    exp(-0.008735 lambda^-4.08 m) and Angstrom aerosol exp(-beta lambda^-1.3 m) with
    beta = 0.04608 T - 0.04586 (lambda in um), as in Preetham et al. 1999 appendix; ozone,
    water vapour and mixed-gas absorption are left out (a few per cent in the visible).
    """
    wavelengths = np.arange(280.0, 4000.0 + 0.5, 1.0)
    lam = wavelengths * 1e-9
    h, c, k, sigma = 6.62607015e-34, 2.99792458e8, 1.380649e-23, 5.670374419e-8
    radiance = 2.0 * h * c**2 / lam**5 / np.expm1(h * c / (lam * k * SUN_TEMPERATURE))  # W/(m^2 sr m)
    # pi B is the emitted exitance; scaling sigma T^4 to the solar constant applies (R / d)^2
    outside = math.pi * radiance * 1e-9 * SOLAR_CONSTANT / (sigma * SUN_TEMPERATURE**4)
    m = air_mass(90.0 - elevation_deg)
    um = wavelengths / 1000.0
    beta = 0.04608 * turbidity - 0.04586
    transmittance = np.exp(-0.008735 * um**-4.08 * m) * np.exp(-beta * um**-1.3 * m)
    return wavelengths, outside, outside * transmittance


def spectrum_to_xyz(wavelengths: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Unnormalised CIE 1931 tristimulus values (W/m^2 from W/(m^2 nm)), 1 nm steps."""
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"]
    keep = (wavelengths >= cmfs.wavelengths[0]) & (wavelengths <= cmfs.wavelengths[-1])
    table = np.asarray(cmfs[wavelengths[keep]])
    return values[keep] @ table


def sun_direction() -> np.ndarray:
    return direction(SUN_AZIMUTH, SUN_ELEVATION)


def sun_solid_angle() -> float:
    return 2.0 * math.pi * (1.0 - math.cos(math.radians(SUN_ANGULAR_DIAMETER / 2.0)))


def sun_coverage(height: int, width: int, sun: np.ndarray, radius: float, samples: int = 32) -> np.ndarray:
    """Fraction of each pixel's solid angle inside the sun disc (height, width), from
    samples x samples points per pixel weighted by sin(theta)."""
    coverage = np.zeros((height, width))
    # a pixel can touch the disc only if its centre is within the radius plus its diagonal
    diagonal = math.hypot(math.pi / height, 2.0 * math.pi / width)
    near = pixel_directions(height, width) @ sun >= math.cos(radius + diagonal)
    offsets = (np.arange(samples) + 0.5) / samples
    cos_radius = math.cos(radius)
    for i, j in np.argwhere(near):
        u, v = (j + offsets) / width, (i + offsets) / height
        d = lat_long_direction(u[None, :], v[:, None])
        weight = np.broadcast_to(np.sin(math.pi * v)[:, None], d.shape[:2])
        coverage[i, j] = weight[d @ sun >= cos_radius].sum() / weight.sum()
    return coverage


def sky(width: int = WIDTH, height: int = HEIGHT, with_sun: bool = True) -> tuple[np.ndarray, dict[str, float]]:
    """The sky map (height, width, 3) in tristimulus W/(m^2 sr), and its measured numbers.
    `with_sun=False` leaves the disc out of the sky (the ground is still lit by it)."""
    theta_sun = math.radians(90.0 - SUN_ELEVATION)
    sun = sun_direction()
    d = pixel_directions(height, width)
    up = d[..., 1] > 0.0  # pixel centres are never on the horizon (an even height splits there)
    gamma = np.arccos(np.clip(d @ sun, -1.0, 1.0))
    x, y, big_y = preetham_xyY(d[..., 1], gamma, theta_sun, TURBIDITY)
    rgb = np.where(up[..., None], xyY_to_rgb_radiance(x, y, big_y), 0.0)
    if (rgb < 0.0).any():
        raise AssertionError("the sky model gave negative radiance: parameters out of its range")
    sky_only = irradiance(rgb)

    wavelengths, outside, direct = solar_spectrum(TURBIDITY, SUN_ELEVATION)
    sun_xyz = spectrum_to_xyz(wavelengths, direct)  # direct normal, tristimulus W/m^2
    sun_rgb = XYZ_TO_SRGB @ sun_xyz
    omega = solid_angles(height, width)
    coverage = sun_coverage(height, width, sun, math.radians(SUN_ANGULAR_DIAMETER / 2.0))
    # scale the drawn disc so it carries exactly the sun's normal irradiance at this resolution
    coverage *= sun_solid_angle() / (coverage * omega).sum()
    disc = coverage[..., None] * (sun_rgb / sun_solid_angle())

    # Lambertian ground lit by the sky and the sun (unshadowed, infinite plane)
    ground_irradiance = irradiance(rgb + disc)
    if with_sun:
        rgb += disc
    rgb = np.where(up[..., None], rgb, GROUND_ALBEDO / math.pi * ground_irradiance)

    global_rgb = sky_only + irradiance(disc)
    beam_efficacy = LUMINOUS_EFFICACY * sun_xyz[1] / np.trapezoid(direct, wavelengths)
    lux = LUMINOUS_EFFICACY * float(global_rgb @ [0.2126, 0.7152, 0.0722])
    numbers = {
        "global_horizontal_illuminance_lux": lux,
        "diffuse_horizontal_illuminance_lux": LUMINOUS_EFFICACY * float(sky_only @ [0.2126, 0.7152, 0.0722]),
        "direct_normal_illuminance_lux": LUMINOUS_EFFICACY * float(sun_xyz[1]),
        "direct_normal_irradiance_broadband_w_m2": float(np.trapezoid(direct, wavelengths)),
        "extraterrestrial_illuminance_lux": LUMINOUS_EFFICACY * float(spectrum_to_xyz(wavelengths, outside)[1]),
        "beam_luminous_efficacy_lm_per_w": float(beam_efficacy),
        "global_horizontal_irradiance_broadband_w_m2": lux / float(beam_efficacy),
        "sun_radiance_Y": float(sun_xyz[1] / sun_solid_angle()),
    }
    return rgb, numbers


# ---------------------------------------------------------------- files

SKY_MANTISSA_BITS = 13  # of float32's 23: relative error <= 2^-14 = 6.1e-5; ZIP then packs it under 2 MB


def round_mantissa(values: np.ndarray, bits: int) -> np.ndarray:
    """float32 values rounded to `bits` explicit mantissa bits (positive finite inputs)."""
    raw = np.ascontiguousarray(values, dtype=np.float32).view(np.uint32)
    drop = 23 - bits
    rounded = (raw + np.uint32(1 << (drop - 1))) & np.uint32((0xFFFFFFFF << drop) & 0xFFFFFFFF)
    return rounded.view(np.float32)


COMMON = {
    "patina:convention": "lat-long, Mitsuba 3 envmap, y up: phi = 2 pi u, theta = pi v",
    "patina:units": "linear Rec.709 tristimulus radiance W/(m^2 sr); 683 lm/W x Y = cd/m^2",
    "patina:generator": "tools/make_environments.py",
    "patina:licence": "CC0-1.0",
}


def write_all(out_dir: str = OUT_DIR) -> dict[str, float]:
    os.makedirs(out_dir, exist_ok=True)
    write_exr(
        os.path.join(out_dir, "studio.exr"),
        {"beauty": studio()},
        {**COMMON, "patina:environment": "studio soft boxes"},
        half=True,
    )
    rgb, numbers = sky()
    sun = sun_direction()
    write_exr(
        os.path.join(out_dir, "sky.exr"),
        {"beauty": round_mantissa(rgb, SKY_MANTISSA_BITS)},
        {
            **COMMON,
            "patina:environment": "Preetham 1999 clear sky with sun",
            "patina:turbidity": TURBIDITY,
            "patina:sun_elevation_deg": SUN_ELEVATION,
            "patina:sun_azimuth_deg": SUN_AZIMUTH,
            "patina:sun_direction": f"{sun[0]:.6f} {sun[1]:.6f} {sun[2]:.6f}",
            "patina:ground_albedo": GROUND_ALBEDO,
        },
    )
    return numbers


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=OUT_DIR, help="output directory (default materials/env)")
    numbers = write_all(parser.parse_args().out)
    for key, value in numbers.items():
        print(f"sky {key}: {value:.6g}")


if __name__ == "__main__":
    main()
