"""How imperfect the simulated robot is: :class:`NoiseConfig` and its named presets.

Every field is one physical effect with a rate, a probability or a sigma, so a whole
configuration can be scaled to sweep the noise level (:meth:`NoiseConfig.scaled`), and
named presets (``clean``, ``mild``, ``paper``, ``harsh``) let runs be compared under the
same conditions. How a field turns an exact value into a reading is in
:mod:`hero_driver.sim.readings` (sonar), :mod:`hero_driver.sim.odometry` (the base's
pose) and :mod:`hero_driver.sim.camera` (the overhead image); docs/simulator.md lists
every field with the presets' values and the reasoning behind ``paper``.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass, fields
from types import MappingProxyType

# Fields that are probabilities: scaling caps them at 1, world files reject values above 1.
PROBABILITIES = ("outlier_p", "dropout_p", "curved_depth_p", "specular_p", "multipath_p", "crosstalk_p",
                 "scan_dropout_p", "scan_specular_p")
# Fields that are rates or sigmas: scaling multiplies them without a cap.
SIGMAS = ("odometry_frac", "odometry_heading_deg", "odometry_drift", "heading_drift_turn", "heading_drift_travel",
          "camera_yaw_deg", "pixel_sigma", "scan_range_frac")
# On/off imperfections: kept by any positive scale factor, turned off by zero.
SWITCHES = ("sonar", "fisheye")
# ``specular_angle_deg`` is none of these: it is the transducer's geometry (half its
# beam width), not a noise level, so scaling leaves it alone.


@dataclass(frozen=True)
class NoiseConfig:
    """How imperfect the simulated robot is (defaults: the ``mild`` preset).

    Sonar readings (:mod:`hero_driver.sim.readings`):

    ``sonar``: Gaussian error with sigma = error/2, clipped to ±error.
    ``outlier_p``: chance a value is off by 2-5x the expected error (binary: flipped).
    ``dropout_p``: chance a value is missing (None).
    ``curved_depth_p``: chance that a round object lying end-on gives a Depth far too
    small (the paper's curved-surface sonar effect).
    ``specular_p``: chance that a procedure whose beam meets a flat face more than
    ``specular_angle_deg`` off its normal loses the face's echo (the beams read the far
    wall), so its sizes come out at 0-50% of the true ones.
    ``specular_angle_deg``: the incidence beyond which a flat face reflects the beam
    away from the transducer (half the beam width).
    ``multipath_p``: chance a value reads long, as an echo that came back by a second
    bounce: 1.5-2.5x the true value and at least two expected errors over it.
    ``crosstalk_p``: chance a value reads far too short (0-25% of the true value), as
    when an earlier ping or another sonar's echo is taken for this one.

    The base (:mod:`hero_driver.sim.odometry`):

    ``odometry_frac``: sigma of the end-position error per inch driven (the robot sees
    where it stopped).
    ``odometry_heading_deg``: sigma of the heading error after a move without centring.
    ``odometry_drift``: dead-reckoning drift, in/√in: the reported position wanders
    from the true one as a random walk whose sigma per axis after s inches of driving
    is ``odometry_drift`` x √s, accumulating over the episode.
    ``heading_drift_turn``, ``heading_drift_travel``: unsensed heading drift of a base
    without a gyro, deg/√deg turned and deg/√in driven: the reported heading wanders
    from the true one as a random walk whose sigma after turning a degrees and driving
    s inches is √(turn² x a + travel² x s). Only in a world that asks for it
    (``"heading_drift": true``, docs/simulator.md "Homes"): the lab never drifts in heading.

    The overhead camera (:mod:`hero_driver.sim.camera`):

    ``camera_yaw_deg``: sigma of the error in each object's drawn orientation, fixed
    while the object stays put.
    ``pixel_sigma``: pixel noise sigma (clipped to ±12 levels).
    ``fisheye``: render the overhead image through a fish-eye lens.

    The range scan (:mod:`hero_driver.sim.scan`, drawn from a stream of its own):

    ``scan_range_frac``: sigma of a range's error as a share of the range.
    ``scan_dropout_p``: chance a beam hears no echo.
    ``scan_specular_p``: chance, per beam, that a surface met beyond the scanner's
    ``specular_deg`` off its normal reflects the beam away (no echo from it).
    """

    sonar: bool = True
    outlier_p: float = 0.02
    dropout_p: float = 0.01
    curved_depth_p: float = 0.3
    specular_p: float = 0.0
    specular_angle_deg: float = 15.0
    multipath_p: float = 0.0
    crosstalk_p: float = 0.0
    odometry_frac: float = 0.005
    odometry_heading_deg: float = 1.0
    odometry_drift: float = 0.0
    heading_drift_turn: float = 0.0
    heading_drift_travel: float = 0.0
    camera_yaw_deg: float = 0.0
    pixel_sigma: float = 4.0
    fisheye: bool = False
    scan_range_frac: float = 0.005
    scan_dropout_p: float = 0.005
    scan_specular_p: float = 0.0

    @classmethod
    def off(cls) -> NoiseConfig:
        """Exact values everywhere (the ``clean`` preset): for tests and for
        noise-free training probes."""
        return cls(**{name: False for name in SWITCHES}, **{name: 0.0 for name in PROBABILITIES + SIGMAS})

    @classmethod
    def preset(cls, name: str) -> NoiseConfig:
        """A named preset (see :data:`NOISE_PRESETS`)."""
        try:
            return NOISE_PRESETS[name]
        except KeyError:
            raise ValueError(f"unknown noise preset '{name}' (valid: {', '.join(NOISE_PRESETS)})") from None

    def scaled(self, factor: float) -> NoiseConfig:
        """Every probability, rate and sigma multiplied by ``factor`` (probabilities
        capped at 1), to sweep the noise level: ``scaled(0)`` is the clean preset,
        ``scaled(1)`` this configuration. The on/off effects stay on for any positive
        factor; the specular angle is geometry and is kept."""
        if not factor >= 0:
            raise ValueError(f"noise scale factor must be a number >= 0, got {factor!r}")
        changes: dict[str, float | bool] = {name: min(1.0, getattr(self, name) * factor) for name in PROBABILITIES}
        changes.update({name: getattr(self, name) * factor for name in SIGMAS})
        changes.update({name: bool(getattr(self, name)) and factor > 0 for name in SWITCHES})
        return dataclasses.replace(self, **changes)  # type: ignore[arg-type]

    @classmethod
    def from_mapping(cls, data: Mapping[str, object], where: str) -> NoiseConfig:
        """Build from a world file's ``noise`` table: an optional ``preset`` name (else
        the defaults) overridden field by field; unknown or mistyped fields fail."""
        known = {f.name: f for f in fields(cls)}
        base = cls()
        if "preset" in data:
            name = data["preset"]
            if not isinstance(name, str) or name not in NOISE_PRESETS:
                raise ValueError(f"{where}: field 'preset' must be one of {', '.join(NOISE_PRESETS)}, got {name!r}")
            base = NOISE_PRESETS[name]
        values: dict[str, object] = {}
        for key, value in data.items():
            if key == "preset":
                continue
            if key not in known:
                raise ValueError(f"{where}: unknown field '{key}' (known: preset, {', '.join(known)})")
            if known[key].type == "bool":
                if not isinstance(value, bool):
                    raise ValueError(f"{where}: field '{key}' must be true or false, got {value!r}")
            elif isinstance(value, bool) or not isinstance(value, (int, float)) or not value >= 0:
                raise ValueError(f"{where}: field '{key}' must be a number >= 0, got {value!r}")
            elif key in PROBABILITIES and value > 1.0:
                raise ValueError(f"{where}: field '{key}' must be a probability <= 1, got {value!r}")
            values[key] = value
        return dataclasses.replace(base, **values)  # type: ignore[arg-type]


# The presets; docs/simulator.md gives the reasoning for every number of ``paper``.
NOISE_PRESETS: Mapping[str, NoiseConfig] = MappingProxyType({
    "clean": NoiseConfig.off(),
    "mild": NoiseConfig(),
    "paper": NoiseConfig(outlier_p=0.03, dropout_p=0.02, curved_depth_p=0.3, specular_p=0.7,
                         multipath_p=0.03, crosstalk_p=0.01, odometry_frac=0.01, odometry_heading_deg=2.0,
                         odometry_drift=0.03, heading_drift_turn=0.1, heading_drift_travel=0.05,
                         camera_yaw_deg=3.0, pixel_sigma=6.0, fisheye=True,
                         scan_range_frac=0.01, scan_dropout_p=0.02, scan_specular_p=0.5),
    "harsh": NoiseConfig(outlier_p=0.06, dropout_p=0.04, curved_depth_p=0.5, specular_p=1.0,
                         multipath_p=0.08, crosstalk_p=0.04, odometry_frac=0.02, odometry_heading_deg=4.0,
                         odometry_drift=0.08, heading_drift_turn=0.25, heading_drift_travel=0.12,
                         camera_yaw_deg=8.0, pixel_sigma=10.0, fisheye=True,
                         scan_range_frac=0.02, scan_dropout_p=0.05, scan_specular_p=0.9),
})
