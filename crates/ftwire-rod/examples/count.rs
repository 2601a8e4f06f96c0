//! Runs one of the model's hot paths 2000 times on the benchmark's configurations (64 stable
//! configurations of the 2 mm nitinol wire, seed 2024, as `benches/solve.rs`), for counting
//! instructions, which unlike times are the same on every run:
//!
//! ```text
//! cargo build --release -p ftwire-rod --example count
//! valgrind --tool=callgrind --toggle-collect='*count::run' \
//!     target/release/examples/count shape
//! ```
//!
//! then divide the `PROGRAM TOTALS` of `callgrind_annotate` by 2000 (the toggle counts the
//! loop only, not the sampling). Paths: `shape` (64 nodes), `jacobian`, `solve` (64 nodes),
//! `is_stable`. Valgrind 3.19 decodes every instruction of the AVX2 paths built by this
//! toolchain; if yours does not, `FTWIRE_NO_SIMD=1` counts the portable paths.
use std::hint::black_box;

use ftwire_rod::{DEFAULT_NODES, Rod, RodError, WireParams, sampling::Sampler};
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn main() -> Result<(), RodError> {
    let path = std::env::args().nth(1).unwrap_or_else(|| "shape".into());
    let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let sampler = Sampler::default();
    let configurations = (0..64)
        .map(|_| sampler.sample_stable(&rod, &mut rng))
        .collect::<Result<Vec<_>, _>>()?;
    match path.as_str() {
        "shape" | "jacobian" | "solve" | "is_stable" => run(&rod, &configurations, &path),
        other => {
            eprintln!("unknown path {other:?}: expected shape, jacobian, solve or is_stable");
            std::process::exit(2);
        }
    }
}

/// The counted loop.
#[inline(never)]
fn run(rod: &Rod, configurations: &[Vector6<f64>], path: &str) -> Result<(), RodError> {
    for i in 0..2000 {
        let a = black_box(&configurations[i % configurations.len()]);
        match path {
            "shape" => drop(black_box(rod.shape(a, DEFAULT_NODES)?)),
            "jacobian" => drop(black_box(rod.jacobian(a)?)),
            "solve" => drop(black_box(rod.solve(a, DEFAULT_NODES)?)),
            _ => drop(black_box(rod.is_stable(a)?)),
        }
    }
    Ok(())
}
