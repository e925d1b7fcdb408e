"""The 9 sectors where the ball hangs (paper sections II-B, III, Fig. 2): a patch of a sphere
centred on the robot's neck, cut into 3 x 3 cells by azimuth and elevation, and the 5
systematic positions per sector of the post-evaluation (section IV). Degrees for angles,
metres for lengths; the world frame of ``world`` (+x backward, +y to the robot's right, +z up).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

N_SECTORS = 9
POINTS_PER_SECTOR = 5


@dataclass(frozen=True)
class SectorConfig:
    """The 9 sectors of Fig. 2: a patch of the sphere of ``radius`` centred on the neck (the
    origin of ``neck_1`` at the home posture), cut into 3 x 3 cells by azimuth (0 = straight ahead,
    positive to the robot's right) and elevation (0 = neck height, positive up), in degrees.
    Sector k has elevation row k // 3 (0 = lowest) and azimuth column k % 3 (0 = leftmost).
    The paper does not give the bounds (it copies the infant experiments, II-B, III); the
    defaults are the scene study's ``arm-length-shoulder`` scene (docs/model/scene.md):
    the ball at shoulder height, 0-45 deg to the right of the midline, the farthest point at the
    extended arm's length. Every point, corners included, is in front of the right shoulder,
    inside the head camera's field of view at the home posture, 25-34 cm from the eyes (inside
    the 50 cm of the distance sensor, Eq. 3), clear of the resting arm and within the reach of
    the right arm (``dart-reach validate``; docs/model/world.md). Other scenes:
    ``dart_reach.scenes``."""

    radius: float = 0.344
    azimuth_edges: tuple[float, float, float, float] = (0.0, 15.0, 30.0, 45.0)
    elevation_edges: tuple[float, float, float, float] = (-35.9, -20.9, -5.9, 9.1)

    def __post_init__(self):
        r = self.radius
        if isinstance(r, bool) or not isinstance(r, (int, float)) or not 0 < r < math.inf:
            raise ValueError(f"radius must be a positive number of metres, got {r!r}")
        object.__setattr__(self, "radius", float(r))
        for key in ("azimuth_edges", "elevation_edges"):
            edges = getattr(self, key)
            if (not isinstance(edges, (tuple, list)) or len(edges) != 4
                    or any(isinstance(e, bool) or not isinstance(e, (int, float)) for e in edges)
                    or not all(-90 <= e <= 90 for e in edges)
                    or not all(a < b for a, b in zip(edges, edges[1:]))):
                raise ValueError(f"{key} must be 4 increasing angles in [-90, 90] degrees, got "
                                 f"{edges!r}")
            object.__setattr__(self, key, tuple(float(e) for e in edges))


def sector_angles(config: SectorConfig, sector: int, u: float, v: float) -> tuple[float, float]:
    """(azimuth, elevation) in degrees of the point at fractions (u, v) in [0, 1] of a sector's
    azimuth and elevation spans."""
    check_sector(sector)
    row, col = divmod(sector, 3)
    az0, az1 = config.azimuth_edges[col], config.azimuth_edges[col + 1]
    el0, el1 = config.elevation_edges[row], config.elevation_edges[row + 1]
    return az0 + u * (az1 - az0), el0 + v * (el1 - el0)


def sphere_point(centre: np.ndarray, radius: float, azimuth: float, elevation: float) -> np.ndarray:
    """World point (m) at (azimuth, elevation) degrees on the sphere of ``radius`` (m) around
    ``centre`` (m); +x of the world is backward, so straight ahead is -x and the robot's right
    +y. Computed with Python floats (the C library's sine and cosine, one rounding per product
    and sum), never numpy's dispatched kernels: the same bits at every numpy dispatch level."""
    az, el = math.radians(azimuth), math.radians(elevation)
    direction = (-math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el))
    return np.array([c + radius * d for c, d in zip(np.asarray(centre, float).tolist(),
                                                      direction)])


def check_sector(sector) -> None:
    """``ValueError`` unless ``sector`` is an integer (not a bool) in 0..8."""
    if (isinstance(sector, (bool, np.bool_)) or not isinstance(sector, (int, np.integer))
            or not 0 <= sector < N_SECTORS):
        raise ValueError(f"sector must be an integer in 0..{N_SECTORS - 1}, got {sector!r}")


#: Fractions (u, v) of the 5 systematic post-evaluation points of a sector: its centre and the
#: centres of its four quadrants.
SYSTEMATIC_FRACTIONS = ((0.5, 0.5), (0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75))
