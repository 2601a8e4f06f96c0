//! Kinematics of the Yaskawa SDA10F dual-arm robot: FK, IK, joint limits, reachability and coarse collision checks.
