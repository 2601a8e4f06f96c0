//! A planned path: a sequence of valid configurations with both gripper poses and the joints,
//! and its resampling into `N` waypoints `γ(i/N)` for tracking (paper §III-D).

use nalgebra::SVector;

use crate::validity::{Checker, Invalid, Sample};
use crate::{Space, ZPoint};

/// A path through `Z_free`: consecutive waypoints joined by straight edges that were checked
/// at the resolution of [`crate::validity`].
#[derive(Debug, Clone, PartialEq)]
pub struct Path {
    /// The waypoints, start first: each `a`, both gripper poses (`config.base`, `tip`) and
    /// the joints.
    pub waypoints: Vec<Sample>,
    /// The smallest clearance \[m\] over the checked samples of each edge (one fewer than the
    /// waypoints; capped as [`Sample::clearance`]).
    pub edge_clearance: Vec<f64>,
    /// The planner's cost of the path (its length in the planning space's metric, plus the
    /// clearance penalty if one was set).
    pub cost: f64,
}

impl Path {
    /// Length of the path in normalised `a` (the sum of the edges' Euclidean lengths in units
    /// of `c2/L` and `c2/L²`).
    pub fn length(&self, checker: &Checker) -> f64 {
        let wire = checker.rod().wire();
        self.waypoints
            .windows(2)
            .map(|w| {
                (ftwire_rod::to_normalised(wire, &w[1].config.a)
                    - ftwire_rod::to_normalised(wire, &w[0].config.a))
                .norm()
            })
            .sum()
    }

    /// The smallest clearance \[m\] along the whole path (edges and waypoints).
    pub fn min_clearance(&self) -> f64 {
        self.edge_clearance
            .iter()
            .copied()
            .chain(self.waypoints.iter().map(|w| w.clearance))
            .fold(f64::INFINITY, f64::min)
    }

    /// How far the base gripper travels along the path \[m\].
    pub fn base_travel(&self) -> f64 {
        self.waypoints
            .windows(2)
            .map(|w| {
                (w[1].config.base.translation.vector - w[0].config.base.translation.vector).norm()
            })
            .sum()
    }

    /// `n + 1` waypoints `γ(i/n)`, `i = 0..=n`, equally spaced in the space's metric along the
    /// path, each checked (seeded by the previous one, so the joints stay continuous).
    ///
    /// # Errors
    /// The reason a resampled point is invalid (rare: the edges were checked at a finer
    /// step, but the seeded IK may fail where the planner's succeeded from another seed).
    pub fn resample<const D: usize, S: Space<D>>(
        &self,
        space: &S,
        checker: &Checker,
        n: usize,
    ) -> Result<Vec<Sample>, Invalid> {
        let Some(first) = self.waypoints.first() else {
            return Ok(Vec::new());
        };
        let states: Vec<SVector<f64, D>> = self
            .waypoints
            .iter()
            .map(|w| space.state(&w.config))
            .collect();
        let mut cumulative = vec![0.0];
        for w in states.windows(2) {
            let last = cumulative.last().copied().unwrap_or(0.0);
            cumulative.push(last + (w[1] - w[0]).norm());
        }
        let total = cumulative.last().copied().unwrap_or(0.0);
        let n = n.max(1);
        let mut out = vec![first.clone()];
        let mut segment = 0;
        for i in 1..=n {
            let target = total * i as f64 / n as f64;
            while segment + 2 < cumulative.len() && cumulative[segment + 1] < target {
                segment += 1;
            }
            let (a, b) = (
                self.waypoints.get(segment).unwrap_or(first),
                self.waypoints.get(segment + 1).unwrap_or(first),
            );
            let span = cumulative.get(segment + 1).copied().unwrap_or(0.0)
                - cumulative.get(segment).copied().unwrap_or(0.0);
            let s = if span > 0.0 {
                ((target - cumulative[segment]) / span).clamp(0.0, 1.0)
            } else {
                1.0
            };
            let config: ZPoint = a.config.interpolate(&b.config, s);
            // The arms' IK seeded from the last resampled point, then from the planned
            // waypoints either side (each checked with IK when planned), then the full
            // search: a seeded solve can miss a pose the arms do reach.
            let last = out.last().map_or(first.joints, |s: &Sample| s.joints);
            let sample = checker
                .sample(&config, &last)
                .or_else(|_| checker.sample(&config, &a.joints))
                .or_else(|_| checker.sample(&config, &b.joints))
                .or_else(|e| match e {
                    Invalid::Unreachable { .. } | Invalid::ArmsCollide => checker.endpoint(&config),
                    other => Err(other),
                })?;
            out.push(sample);
        }
        Ok(out)
    }
}
