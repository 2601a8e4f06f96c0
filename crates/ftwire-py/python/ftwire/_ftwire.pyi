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
                 mounting: Optional[Mounting] = None, points: int = 100,
                 jump_threshold: float = 2.0, gravity: Optional[ArrayLike] = None) -> None: ...
    def reset(self) -> None: ...
    def estimate(self, samples: ArrayLike, time: Optional[ArrayLike] = None,
                 tool_gravity: Optional[ArrayLike] = None) -> Dict[str, Any]:
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
    def covariance(self) -> Optional[F64]:
        """(4, 4), or (5, 5) with gravity: the first-order covariance of (c1, c2, c3, L[, λ])
        [N·m², m, kg/m products]; None where the fit has none."""
    @property
    def interval95(self) -> Optional[F64]:
        """(4, 2) or (5, 2): [low, high] = value ∓ 1.96 σ of each parameter, in the
        covariance's order; None without a covariance."""
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
             seed: int = 0, sensor: Optional[str] = None,
             times: Optional[ArrayLike] = None, tare_time: Optional[float] = None,
             rest_samples: int = 400, tare_samples: int = 500,
             pose_noise_deg: Optional[float] = None, pose_noise_mm: Optional[float] = None,
             gain_error: Optional[float] = None,
             model_floor: Optional[float] = None) -> Identification:
    """(c1, c2, c3, L) from a (N, 6) ã and b (N, 4, 4) | (N, 6) | (N, 7) poses; the GIL is
    released; the same seed gives the same answer. With sensor (a preset or a sensor TOML
    file) and times (N,) [s], the bias all samples share (the tare's offset and its drift since
    tare_time, default the first sample's time) is estimated with the wire. pose_noise_deg,
    pose_noise_mm: the robot's repeatability [°, mm] (default 0.05, 0.1); gain_error: the
    calibration's accuracy [%], a relative error of ã that every sample shares (default 0);
    model_floor: the wire model's own error [% of each parameter], added to every interval
    (default 0)."""

class Controller:
    """The paper's Jacobian controller (eq. 13–14): δb = s K J(ã)(a_g − ã), b' = b M(δb),
    s ≤ 1 from the step limits and the stability guard. gain K in (0, 1]; epsilon [normalised:
    torque in c2/L, force in c2/L²]; max_translation [m]; max_rotation [rad]; gravity (3,)
    [m/s²] base clamp frame for the loaded model, None: weightless."""
    def __init__(self, wire: Wire, gain: float = 0.2, epsilon: float = 0.05,
                 max_translation: float = 0.05, max_rotation: float = 0.3,
                 max_shrinks: int = 6, gravity: Optional[ArrayLike] = None) -> None: ...
    @property
    def gain(self) -> float: ...
    @property
    def epsilon(self) -> float: ...
    def step(self, a_measured: ArrayLike, a_goal: ArrayLike,
             b: Optional[ArrayLike] = None) -> F64:
        """(4, 4) the second gripper's next pose in the base clamp frame [m]; a_measured,
        a_goal (6,) torque first [N·m, N]; b the pose now ((4, 4) | (6,) | (7,); None:
        Γ(a_measured) of the model). RuntimeError when no step passes the stability guard."""
    def plan_step(self, a_measured: ArrayLike, a_goal: ArrayLike,
                  b: Optional[ArrayLike] = None) -> Optional[Dict[str, Any]]:
        """{"b": (4, 4), "delta_b": (6,) [rad, m] body twist, "predicted_da": (6,) [N·m, N],
        "scale": float}, or None when no step passes the stability guard."""
    def distance(self, a: ArrayLike, a_goal: ArrayLike) -> float:
        """‖a_goal − a‖ [normalised]."""
    def reached(self, a: ArrayLike, a_goal: ArrayLike) -> bool:
        """distance < epsilon."""
    def check_goal(self, a_goal: ArrayLike) -> None:
        """ValueError unless a_goal is finite and in the model's A_stable."""

def plan(scene: Path, wire: str = "nitinol-3mm-820", seed: int = 0,
         iterations: int = 1000000, time_budget: float = 2.0, margin: float = 0.005,
         max_span: float = 1.0, start: str = "start", goal: str = "goal", first: bool = False,
         planner: str = "fixed", clearance_weight: float = 0.0,
         clearance_reference: float = 0.02, resample: Optional[int] = None) -> Dict[str, Any]:
    """RRT* from the scene's start to goal (`ftwire plan --json`): "waypoints" (N, 6) a
    [N·m, N] torque first, base clamp frame; "waypoints_normalised" (N, 6); "base", "tip"
    (N, 6) world frame, position [m] + rotation vector [rad]; "joints" (N, 15) [rad];
    "clearance" (N,) [m]; "length" [normalised a]; "cost"; "base_travel" [m];
    "min_clearance" [m]; "iterations"; "nodes"; "first_path_iteration"; "seconds";
    "first_path_seconds"; "resampled" (a dict of the per-waypoint arrays, or None). The same
    seed and an iteration budget the time budget does not cut give the same path."""

class Rig:
    """ftwire.sim.Rig (see ftwire/sim.pyi)."""
