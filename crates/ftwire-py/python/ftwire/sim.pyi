"""Type stubs of ftwire.sim (see its docstring for frames and units)."""

from os import PathLike
from typing import Optional, Union

import numpy as np
import numpy.typing as npt

from . import Mounting, Wire

ArrayLike = npt.ArrayLike
F64 = npt.NDArray[np.float64]

class Rig:
    """A simulated rig holding a wire (ground truth). wire: preset, wire file or Wire;
    sensor: "distorted" | "undistorted" | "real-like" | a sensor file; gravity: (0, 0, −9.81)
    m/s² along the base clamp frame's −z, or none; seed: every random choice (same seed, same
    numbers); a0: (6,) start configuration, torque first [N·m, N] (None: a moderate bend);
    rig: a rig file (markers, execution error, speeds)."""
    def __init__(self, wire: Union[str, Wire, None] = None, sensor: str = "distorted",
                 gravity: bool = True, seed: int = 0, a0: Optional[ArrayLike] = None,
                 rig: Union[str, PathLike, None] = None) -> None: ...
    @property
    def wire(self) -> Wire:
        """The true wire."""
    @property
    def gravity(self) -> Optional[F64]:
        """(3,) [m/s²], base clamp frame, or None."""
    @property
    def mounting(self) -> Mounting:
        """The sensor's mounting from the drawings: tared raw → ã (uncalibrated)."""
    @property
    def time(self) -> float:
        """The rig's clock [s]."""
    @property
    def b(self) -> F64:
        """(4, 4) the second gripper's pose in the base clamp frame, as commanded [m]."""
    @property
    def true_b(self) -> F64:
        """(4, 4) ground truth: the actual pose, execution error included [m]."""
    @property
    def true_configuration(self) -> F64:
        """(6,) ground truth: the wire's wrench on the base gripper, torque first [N·m, N],
        base clamp frame."""
    def place(self, b: ArrayLike) -> None:
        """Moves the second gripper to b: (4, 4) | (6,) position [m] + rotation vector [rad] |
        (7,) position + quaternion (x, y, z, w), base clamp frame. ValueError for a bad pose
        or one out of the wire's reach; RuntimeError when the simulator finds no
        equilibrium (nothing moved)."""
    def place_configuration(self, a: ArrayLike, model: str = "weightless") -> F64:
        """Moves to Γ(a) of the true wire's "weightless" or "loaded" model; returns the (4, 4)
        pose."""
    def rest(self, samples: int = 100) -> F64:
        """(6,) mean raw F/T reading over `samples` ticks (≥ 4; dropouts skipped), force first
        [N, N·m], sensor frame, offset and drift included."""
    def tare(self, samples: int = 500) -> F64:
        """(6,) mean raw reading with nothing in the gripper: rest() − tare() is the wire's."""
    def markers(self) -> F64:
        """(M, 3) motion-capture markers [m], base clamp frame; NaN rows for dropouts."""
    def centreline(self) -> F64:
        """(n, 3) ground truth: the wire's centreline, base clamp to second clamp [m]."""
