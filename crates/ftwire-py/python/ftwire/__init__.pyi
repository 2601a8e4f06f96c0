from . import sim as sim
from ._ftwire import (Calibration, Controller, Identification, Mounting, ShapeEstimator,
                      Solution, Wire, __version__, identify, plan, read_log)

__all__ = ["Calibration", "Controller", "Identification", "Mounting", "ShapeEstimator",
           "Solution", "Wire", "__version__", "identify", "plan", "read_log", "sim"]
