"""Type stubs of the native module (see the package docstring for units and frames)."""

from os import PathLike
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike
Path = Union[str, PathLike]
F64 = npt.NDArray[np.float64]

__version__: str

class Wire:
    """An elastic wire (immutable). c [N·m²] torsion, bending about body y, z; length [m];
    radius [m] < length/2; density [kg/m³]; natural_curvature (κ1, κ2, κ3) [1/m], body frame."""
    def __init__(self, c: ArrayLike, length: float, radius: float = 0.001,
                 density: float = 6450.0, natural_curvature: Optional[ArrayLike] = None,
                 name: str = "wire") -> None: ...
    @staticmethod
    def preset(name: str) -> "Wire":
        """"nitinol-2mm-630", "nitinol-3mm-910", "nitinol-3mm-820" or "cable-3mm-920"."""
    @staticmethod
    def from_toml(path: Path) -> "Wire":
        """A wire file (docs/config.md)."""
    @property
    def name(self) -> str: ...
    @property
    def c(self) -> Tuple[float, float, float]: ...
    @property
    def length(self) -> float: ...
    @property
    def radius(self) -> float: ...
    @property
    def density(self) -> float: ...
    @property
    def natural_curvature(self) -> Tuple[float, float, float]: ...
    def solve(self, a: ArrayLike, points: int = 100,
              gravity: Optional[ArrayLike] = None) -> "Solution":
        """The Kirchhoff model for a (6,) or (N, 6) [N·m, N], torque first, base clamp frame;
        gravity (3,) [m/s²] in the base clamp frame for the loaded model. Batches run in
        parallel with the GIL released. ValueError naming the argument (and row) for bad
        input or a ∉ A; RuntimeError if the integration diverges."""

class Solution:
    """Arrays with a leading axis N for a (N, 6) input, none for (6,)."""
    @property
    def shape(self) -> F64:
        """(N, points, 3) [m] centreline nodes t = 0..L, base clamp frame."""
    @property
    def tip_pose(self) -> F64:
        """(N, 4, 4) Γ(a): the second gripper's clamp pose in the base clamp frame."""
    @property
    def jacobian(self) -> F64:
        """(N, 6, 6) J(L): δb ≈ J δa, rows (δω [rad], δv [m]) body twist at the tip."""
    @property
    def stable(self) -> Any:
        """(N,) bool (a bool for one configuration)."""
    @property
    def self_intersecting(self) -> Any:
        """(N,) bool (a bool for one configuration)."""
    @property
    def det_j_min(self) -> Any:
        """(N,) smallest |det J(t)| along the wire (a float for one configuration)."""

def read_log(path: Path) -> Dict[str, np.ndarray]:
    """A rig's JSON Lines log as arrays: line (N,) int64, time (N,) [s], a (N, 6) torque
    first, base clamp frame; raw (N, 6) force first, sensor frame; b (N, 6) position [m] and
    rotation vector [rad]; gravity (N, 3) [m/s²] sensor frame; markers (N, M, 3) [m] if any.
    Missing values are NaN."""

class Calibration:
    """The learnt F/T calibration: raw (force first, sensor frame) → ã (torque first, base
    clamp frame)."""
    @staticmethod
    def load(path: Path) -> "Calibration": ...
    @property
    def has_drift(self) -> bool: ...
    def apply(self, raw: ArrayLike, time: Optional[ArrayLike] = None) -> F64:
        """(6,) or (N, 6) raw → ã of the same shape; time [s] per reading for the drift term."""

class Mounting:
    """The sensor's mounting: clamp pose in the sensor frame [m, rad], the tool's mass [kg]
    and centre of mass [m, sensor frame]."""
    def __init__(self, clamp_position_in_sensor: Optional[ArrayLike] = None,
                 clamp_rotation_in_sensor: Optional[ArrayLike] = None, tool_mass: float = 0.0,
                 tool_centre_of_mass: Optional[ArrayLike] = None) -> None: ...
    @staticmethod
    def from_toml(path: Path) -> "Mounting": ...
    @property
    def clamp_position_in_sensor(self) -> List[float]: ...
    @property
    def clamp_rotation_in_sensor(self) -> List[float]: ...
    @property
    def tool_mass(self) -> float: ...
    @property
    def tool_centre_of_mass(self) -> List[float]: ...
    def to_configuration(self, raw: ArrayLike, gravity: Optional[ArrayLike] = None) -> F64:
        """raw (force first, sensor frame) → ã (torque first, base clamp frame), uncalibrated;
        gravity [m/s²] in the sensor frame when tool_mass > 0."""
    def to_sensor(self, a: ArrayLike) -> F64:
        """ã → the sensor's reading (without a tool)."""

class ShapeEstimator:
    """Shapes from F/T with flags "confident", "not_stable", "jump", "no_shape"."""
    def __init__(self, wire: Wire, calibration: Optional[Calibration] = None,
                 mounting: Optional[Mounting] = None, points: int = 64,
                 jump_threshold: float = 2.0) -> None: ...
    def reset(self) -> None: ...
    def estimate(self, samples: ArrayLike, time: Optional[ArrayLike] = None) -> Dict[str, Any]:
        """{"a": (N, 6), "shape": (N, points, 3) [m], "flag": [str], "error": [str | None]}."""

class Identification:
    @property
    def wire(self) -> Wire: ...
    @property
    def c(self) -> Tuple[float, float, float]: ...
    @property
    def length(self) -> float: ...
    @property
    def c_std(self) -> Tuple[float, float, float]: ...
    @property
    def length_std(self) -> float: ...
    @property
    def linear_density(self) -> Optional[float]: ...
    @property
    def linear_density_std(self) -> Optional[float]: ...
    @property
    def chi2_per_dof(self) -> float: ...
    @property
    def condition(self) -> float: ...
    @property
    def identified(self) -> bool: ...
    @property
    def flag(self) -> Optional[str]: ...
    @property
    def reason(self) -> Optional[str]: ...
    @property
    def samples(self) -> int: ...

def identify(a: ArrayLike, b: ArrayLike, wire_guess: Optional[Wire] = None,
             form: str = "absolute", isotropic: bool = False,
             torsion_ratio: Optional[float] = None, gravity: Optional[ArrayLike] = None,
             seed: int = 0) -> Identification:
    """(c1, c2, c3, L) from a (N, 6) ã and b (N, 4, 4) | (N, 6) | (N, 7) poses; the GIL is
    released; the same seed gives the same answer."""
