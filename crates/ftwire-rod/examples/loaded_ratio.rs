//! The cost of the loaded model against the unloaded one (the requirement: a full solve under
//! load at most 2× the unloaded one), as ratios that hold on a busy machine: the 64 configurations of
//! `benches/solve.rs` (2 mm nitinol wire, stable, normalised `[−30, 30]⁶`, seed 2024), solved
//! without load and under the wire's weight (gravity along −z of the base clamp frame) in
//! interleaved blocks, 300 pairs of blocks per hot path. Prints, per path, the ratio of the
//! fastest blocks and the quartiles of the per-pair ratios (criterion runs one case after the
//! other, so a change of machine load between them moves its ratios).
//!
//! `cargo run --release -p ftwire-rod --example loaded_ratio`
#![allow(missing_docs)]

use std::hint::black_box;
use std::time::Instant;

use ftwire_rod::{DEFAULT_NODES, Load, Rod, RodError, WireParams, sampling::Sampler};
use nalgebra::{Vector3, Vector6};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// Pairs of timed blocks per hot path.
const PAIRS: usize = 300;

/// Seconds taken by one solve of each configuration with `path`.
fn block(rod: &Rod, configurations: &[Vector6<f64>], path: Path) -> f64 {
    let start = Instant::now();
    for a in configurations {
        let a = black_box(a);
        let _ = match path {
            Path::Full => black_box(rod.solve(a, DEFAULT_NODES).map(|_| ())),
            Path::Jacobian => black_box(rod.jacobian(a).map(|_| ())),
            Path::Shape => black_box(rod.shape(a, DEFAULT_NODES).map(|_| ())),
        };
    }
    start.elapsed().as_secs_f64()
}

#[derive(Clone, Copy)]
enum Path {
    Full,
    Jacobian,
    Shape,
}

fn main() -> Result<(), RodError> {
    let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let sampler = Sampler::default();
    let configurations = (0..64)
        .map(|_| sampler.sample_stable(&rod, &mut rng))
        .collect::<Result<Vec<_>, _>>()?;
    let loaded = rod.with_load(Load::from_gravity(
        6450.0,
        0.001,
        Vector3::new(0.0, 0.0, -9.81),
    )?);
    let per_solve = 1e6 / configurations.len() as f64;
    for (name, path) in [
        ("full solve", Path::Full),
        ("jacobian", Path::Jacobian),
        ("shape", Path::Shape),
    ] {
        let (mut fastest_unloaded, mut fastest_loaded) = (f64::INFINITY, f64::INFINITY);
        let mut ratios = Vec::with_capacity(PAIRS);
        for _ in 0..PAIRS {
            let unloaded = block(&rod, &configurations, path);
            let with_load = block(&loaded, &configurations, path);
            fastest_unloaded = fastest_unloaded.min(unloaded);
            fastest_loaded = fastest_loaded.min(with_load);
            ratios.push(with_load / unloaded);
        }
        ratios.sort_by(f64::total_cmp);
        println!(
            "{name}: loaded / unloaded {:.2} (fastest blocks: {:.2} / {:.2} µs a solve); \
             per-pair quartiles {:.2} {:.2} {:.2}",
            fastest_loaded / fastest_unloaded,
            fastest_loaded * per_solve,
            fastest_unloaded * per_solve,
            ratios[PAIRS / 4],
            ratios[PAIRS / 2],
            ratios[3 * PAIRS / 4],
        );
    }
    Ok(())
}
