//! Times pure solves (no JSON) of configurations read from stdin, one per line as six
//! whitespace- or comma-separated numbers, for the 2 mm nitinol wire (c = (0.042, 0.055,
//! 0.055), L = 0.63 m, radius 1 mm) at 64 nodes. Used to measure the JSON share of
//! `ftwire solve --batch`:
//!
//! `cargo run --release -p ftwire-rod --example solve_many < configurations.txt`
use std::io::BufRead;
use std::time::Instant;

use ftwire_rod::{DEFAULT_NODES, Rod, RodError, WireParams};
use nalgebra::Vector6;

fn main() -> Result<(), RodError> {
    let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001)?);
    let configurations: Vec<Vector6<f64>> = std::io::stdin()
        .lock()
        .lines()
        .map_while(Result::ok)
        .filter_map(|line| {
            let v: Vec<f64> = line
                .split([',', ' '])
                .filter_map(|x| x.trim().parse().ok())
                .collect();
            (v.len() == 6).then(|| Vector6::from_column_slice(&v))
        })
        .collect();
    let start = Instant::now();
    let mut stable = 0usize;
    for a in &configurations {
        if let Ok(s) = rod.solve(a, DEFAULT_NODES) {
            stable += usize::from(s.jacobian.stability.stable);
        }
    }
    let elapsed = start.elapsed();
    println!(
        "{} solves in {:.2} s ({:.1} µs each), {stable} stable",
        configurations.len(),
        elapsed.as_secs_f64(),
        elapsed.as_secs_f64() * 1e6 / configurations.len().max(1) as f64
    );
    Ok(())
}
