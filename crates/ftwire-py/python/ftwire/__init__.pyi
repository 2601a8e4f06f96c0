from ._ftwire import (Calibration, Identification, Mounting, ShapeEstimator, Solution, Wire,
                      __version__, identify, read_log)

__all__ = ["Calibration", "Identification", "Mounting", "ShapeEstimator", "Solution", "Wire",
           "__version__", "identify", "read_log"]
