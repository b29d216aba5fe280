"""The scene as frozen dataclasses: what `patina.scene.reading` parses a scene file into.

Every default is already filled and every file path is absolute, so the renderer (and the
Mitsuba converter) never consults the format's rules again. Units: metres, degrees in the
file but radians nowhere here except where a method says so; colours are linear RGB.
Conventions (docs/scene.md): right-handed, y up; the camera looks along `look_at -
position`; film x grows to the right, y downwards, from the top-left corner.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

Vec3 = tuple[float, float, float]
RGB = tuple[float, float, float]


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# --- camera and render settings -------------------------------------------------------------


@dataclass(frozen=True)
class Camera:
    """A pinhole or thin-lens camera. `fov` is the vertical field of view in degrees.

    `focus_distance` is measured along the view axis (the plane of focus is perpendicular
    to it); a pinhole keeps `aperture_radius` 0 and `focus_distance` |look_at - position|.
    """

    type: str  # "pinhole" | "thinlens"
    position: Vec3
    look_at: Vec3
    up: Vec3
    fov: float
    width: int
    height: int
    aperture_radius: float
    focus_distance: float

    def basis(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(right, up, forward) unit vectors in world space; right = forward x up."""
        forward = _unit(np.subtract(self.look_at, self.position, dtype=np.float64))
        right = _unit(np.cross(forward, np.asarray(self.up, np.float64)))
        return right, np.cross(right, forward), forward

    def ray_direction(self, x: Any, y: Any) -> np.ndarray:
        """Unit world directions (..., 3) of the pinhole rays through film positions in pixels.

        (0, 0) is the top-left corner of the image, (width, height) the bottom-right; the
        centre of pixel (i, j) is (i + 0.5, j + 0.5).
        """
        right, up, forward = self.basis()
        t = math.tan(math.radians(self.fov) / 2)
        sx = (2 * np.asarray(x, np.float64) / self.width - 1) * t * self.width / self.height
        sy = (1 - 2 * np.asarray(y, np.float64) / self.height) * t
        return _unit(forward + sx[..., None] * right + sy[..., None] * up)


@dataclass(frozen=True)
class CacheParams:
    """The radiance cache's parameters (docs/radiance-cache.md), for the `cache` and
    `cache-guided` integrators."""

    resolution: int = 24  # texels per side of a hemisphere, 8 to 128
    error: float = 0.5  # the reuse criterion's bound, 0.01 to 4
    guide: float = 0.5  # cache-guided: probability of drawing a bounce from the cache points, 0.05 to 0.95
    guide_bounces: int = 1  # cache-guided: the bounces the cache points draw (1: the first hit's), 1 to 16
    block: int = 8  # pixels per side of the blocks whose close points share one reconstruction, 1 to 16
    hit_paths: int = 4  # cache: paths from a cache point's texel hit on a glossy surface, 1 to 16
    light_samples: int = 1  # cache: the light samples a camera sample takes at its first hit, 1 to 16
    train_passes: int = 1  # cache-guided: training passes of the trained guide, 0 (none) to 8
    train_spp: int = 1  # cache-guided: samples a pixel in each training pass, 1 to 16
    train_guide: float = 0.1  # cache-guided: probability of drawing a bounce from the trained guide, 0.05 to 0.95
    train_bounces: int = 1  # cache-guided: the bounces the trained guide draws (1: the first hit's), 1 to 16


@dataclass(frozen=True)
class Render:
    """Sampling settings. `max_depth` counts path segments as Mitsuba 3 does (2 = direct light)."""

    spp: int
    integrator: str  # "direct" | "path" | "cache" | "cache-guided"
    max_depth: int
    seed: int
    aa: str = "uniform"  # the pixel sampler: "uniform" | "adaptive" (docs/antialiasing.md)
    aa_threshold: float = 0.15  # the adaptive sampler's contrast threshold, in [0, 1]
    indirect_illuminance: bool = False  # the illuminance AOV also counts light reflected by the scene
    sampler: str = "sobol"  # the paths' numbers: "sobol" | "independent" (docs/render.md)
    cache: CacheParams = field(default_factory=CacheParams)


# --- materials ------------------------------------------------------------------------------


@dataclass(frozen=True)
class TableMaterial:
    """A tabulated BRDF file (any format `patina.load_brdf` reads), times `scale` and `tint`."""

    file: str
    scale: float
    tint: RGB
    two_sided: bool
    type: str = field(default="table", init=False)


@dataclass(frozen=True)
class RglMaterial:
    """An RGL .bsdf file rendered natively: evaluated by the format's own rule and sampled by
    its own warps (`sampling` "file"), or by the cosine ("cosine", to compare); times `scale`
    and `tint`."""

    file: str
    scale: float
    tint: RGB
    two_sided: bool
    sampling: str = "file"
    type: str = field(default="rgl", init=False)


@dataclass(frozen=True)
class FitMaterial:
    """A fitted analytic model: a fit.json written by `patina fit`, times `scale` and `tint`."""

    file: str
    scale: float
    tint: RGB
    two_sided: bool
    type: str = field(default="fit", init=False)


@dataclass(frozen=True)
class LambertMaterial:
    albedo: RGB
    two_sided: bool
    type: str = field(default="lambert", init=False)


@dataclass(frozen=True)
class ConductorMaterial:
    """GGX rough conductor: `roughness` is (alpha_x, alpha_y); 0 is a mirror. eta and k at R, G, B.

    `metal` names the preset eta and k came from (None when given directly); `tint`
    multiplies the Fresnel reflectance.
    """

    roughness: tuple[float, float]
    eta: RGB
    k: RGB
    tint: RGB
    metal: str | None
    two_sided: bool
    type: str = field(default="conductor", init=False)


@dataclass(frozen=True)
class DielectricMaterial:
    """GGX rough dielectric interface (reflection and refraction); `eta` is inside over outside."""

    roughness: float
    eta: float
    type: str = field(default="dielectric", init=False)


@dataclass(frozen=True)
class Coat:
    """A dielectric clear coat: Fresnel at `eta`, GGX `roughness` (0 = smooth); light that
    crosses it twice is multiplied by `thickness_tint` (absorption in the coat)."""

    eta: float
    roughness: float
    thickness_tint: RGB


BaseMaterial = TableMaterial | RglMaterial | FitMaterial | LambertMaterial


@dataclass(frozen=True)
class CarpaintMaterial:
    """A clear coat over a base BRDF (a table, an RGL file, a fit or Lambert)."""

    base: BaseMaterial
    coat: Coat
    two_sided: bool
    type: str = field(default="carpaint", init=False)


Material = (
    TableMaterial
    | RglMaterial
    | FitMaterial
    | LambertMaterial
    | ConductorMaterial
    | DielectricMaterial
    | CarpaintMaterial
)


# --- shapes ---------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class _Placed:
    """A shape: a material name and a 4x4 float64 object-to-world matrix (read-only)."""

    material: str
    transform: np.ndarray

    def __eq__(self, other: object) -> bool:
        if type(other) is not type(self):
            return NotImplemented
        for f in dataclasses.fields(self):
            a, b = getattr(self, f.name), getattr(other, f.name)
            if not (np.array_equal(a, b) if isinstance(a, np.ndarray) else a == b):
                return False
        return True

    __hash__ = None  # type: ignore[assignment]


@dataclass(frozen=True, eq=False)
class SphereShape(_Placed):
    """A sphere of `radius` about the origin, placed by its transform: triangles
    (`patina.geometry.shapes.sphere`), or with `analytic` the exact sphere the tracer
    intersects as such (its transform then a similarity)."""

    radius: float
    analytic: bool = False
    type: str = field(default="sphere", init=False)


@dataclass(frozen=True, eq=False)
class PlaneShape(_Placed):
    """A rectangle in the xz plane centred at the origin, normal +y; `size` is (x extent, z extent)."""

    size: tuple[float, float]
    type: str = field(default="plane", init=False)


@dataclass(frozen=True, eq=False)
class BallShape(_Placed):
    """The material-preview object (`patina.geometry.shapes.preview_ball()`), placed by its transform."""

    type: str = field(default="ball", init=False)


@dataclass(frozen=True, eq=False)
class PanelShape(_Placed):
    """A curved car-body panel (`patina.geometry.shapes.car_panel(size)`): `size` = (width along x, height along y),
    centred at the origin, convex towards +z (its outside)."""

    size: tuple[float, float]
    type: str = field(default="panel", init=False)


@dataclass(frozen=True, eq=False)
class MeshShape(_Placed):
    """A triangle mesh file (any format `patina.load_mesh` reads)."""

    file: str
    type: str = field(default="mesh", init=False)


Shape = SphereShape | PlaneShape | BallShape | PanelShape | MeshShape


# --- lights and environment -------------------------------------------------------------------


@dataclass(frozen=True)
class PointLight:
    """An isotropic point light; `intensity` in W/sr per channel."""

    position: Vec3
    intensity: RGB
    type: str = field(default="point", init=False)


@dataclass(frozen=True)
class QuadLight:
    """A parallelogram center + s u + t v, s, t in [-1, 1], of uniform `radiance` (W/m^2/sr).

    It emits on the side of `normal` = unit(u x v), and on both sides if `two_sided`.
    """

    center: Vec3
    u: Vec3
    v: Vec3
    radiance: RGB
    two_sided: bool
    type: str = field(default="quad", init=False)

    @property
    def normal(self) -> np.ndarray:
        return _unit(np.cross(self.u, self.v))

    @property
    def area(self) -> float:
        return float(4 * np.linalg.norm(np.cross(self.u, self.v)))


@dataclass(frozen=True)
class SpotLight:
    """A point light limited to a cone about `direction`: full `intensity` (W/sr) within
    `inner_angle` of the axis, falling smoothly to none at `outer_angle` (degrees, half-angles)."""

    position: Vec3
    direction: Vec3  # unit
    intensity: RGB
    inner_angle: float
    outer_angle: float
    type: str = field(default="spot", init=False)


@dataclass(frozen=True)
class DiskLight:
    """A disc of uniform `radiance` (W/m^2/sr), centre, unit normal (the emitting side), radius."""

    center: Vec3
    normal: Vec3
    radius: float
    radiance: RGB
    two_sided: bool
    type: str = field(default="disk", init=False)


@dataclass(frozen=True)
class SphereLight:
    """A sphere of uniform `radiance` (W/m^2/sr) emitting outwards."""

    center: Vec3
    radius: float
    radiance: RGB
    type: str = field(default="sphere", init=False)


@dataclass(frozen=True, eq=False)
class MeshLight(_Placed):
    """A triangle mesh file whose front faces emit uniform `radiance` (W/m^2/sr); `material` is
    unused (""), the transform places it."""

    file: str
    radiance: RGB
    two_sided: bool
    type: str = field(default="mesh", init=False)


@dataclass(frozen=True)
class SunLight:
    """The sun: a disc of uniform radiance at infinity towards unit `direction`, of angular
    diameter `angular_diameter` (degrees), giving `irradiance` (W/m^2 per channel) on a
    surface facing it."""

    direction: Vec3
    angular_diameter: float
    irradiance: RGB
    type: str = field(default="sun", init=False)


@dataclass(frozen=True)
class LuminaireLight:
    """A goniometric point light from a photometric file (IES LM-63 or EULUMDAT; candela as
    the file gives them, times `multiplier`, of colour `color`) at `position`. Its photometric
    axis points along unit `aim` (type C: the nadir, gamma 0; type B: the beam axis), turned
    by `rotation` degrees about it (docs/luminaires.md, docs/scene.md)."""

    file: str
    position: Vec3
    aim: Vec3
    rotation: float
    multiplier: float
    color: RGB
    type: str = field(default="luminaire", init=False)


Light = PointLight | QuadLight | SpotLight | DiskLight | SphereLight | MeshLight | SunLight | LuminaireLight


def rotation_y(degrees: float) -> np.ndarray:
    """3x3 right-handed rotation about +y (counter-clockwise seen from above): x goes to -z at 90."""
    a = math.radians(degrees)
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


@dataclass(frozen=True)
class MapEnvironment:
    """A lat-long HDR map (EXR/HDR) at infinity, rotated about +y by `rotation` degrees, times `intensity`.

    Texel (u, v) in [0, 1]^2 (u to the right, v downwards) shows the direction
    R_y(rotation) (sin phi sin theta, cos theta, -cos phi sin theta), phi = 2 pi u,
    theta = pi v: Mitsuba 3's convention, so the top row is +y and the centre is +z.
    """

    file: str
    rotation: float
    intensity: float
    type: str = field(default="map", init=False)

    def direction(self, u: Any, v: Any) -> np.ndarray:
        """World directions (..., 3) shown at map coordinates (u, v)."""
        phi = 2 * np.pi * np.asarray(u, np.float64)
        theta = np.pi * np.asarray(v, np.float64)
        st = np.sin(theta)
        local = np.stack([np.sin(phi) * st, np.cos(theta), -np.cos(phi) * st], axis=-1)
        return local @ rotation_y(self.rotation).T

    def uv(self, direction: Any) -> np.ndarray:
        """Map coordinates (..., 2) in [0, 1) x [0, 1] of world directions (the inverse of `direction`)."""
        d = _unit(np.asarray(direction, np.float64)) @ rotation_y(self.rotation)
        u = np.mod(np.arctan2(d[..., 0], -d[..., 2]) / (2 * np.pi), 1.0)
        v = np.arccos(np.clip(d[..., 1], -1.0, 1.0)) / np.pi
        return np.stack([u, v], axis=-1)


@dataclass(frozen=True)
class ConstantEnvironment:
    """The same `radiance` (W/m^2/sr) from every direction."""

    radiance: RGB
    type: str = field(default="constant", init=False)


Environment = MapEnvironment | ConstantEnvironment


@dataclass(frozen=True)
class Scene:
    """A parsed scene file (`path`, absolute). `materials` maps names to materials; each
    shape's `material` is one of those names."""

    path: str
    camera: Camera
    render: Render
    materials: dict[str, Material]
    shapes: tuple[Shape, ...]
    lights: tuple[Light, ...]
    environment: Environment | None
    version: int = 1
