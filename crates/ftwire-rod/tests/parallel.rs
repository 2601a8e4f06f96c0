//! The `parallel` feature: batch solves on rayon give the same bits on 1 thread and on many
//! (STYLE.md: same seed, same result, on any thread count). Run with
//! `cargo test -p ftwire-rod --release --features parallel --test parallel`; CI does.
#![cfg(feature = "parallel")]

use ftwire_rod::{Rod, WireParams, batch, sampling::Sampler};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a local thread pool")
}

/// Every number of a result, as text: `{:?}` prints each `f64` in the shortest form that
/// reads back to the same bits (and `-0.0` apart from `0.0`), so equal text is equal bits.
fn bits<T: std::fmt::Debug>(results: &[T]) -> Vec<String> {
    results.iter().map(|r| format!("{r:?}")).collect()
}

#[test]
fn one_thread_and_four_threads_give_identical_bits() {
    let rod = Rod::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("valid wire"));
    let mut rng = ChaCha8Rng::seed_from_u64(12);
    let sampler = Sampler::default();
    // Enough configurations that rayon splits the work across all four threads; every fourth
    // one zero (not in A), so that errors keep their places too.
    let configurations: Vec<_> = (0..64)
        .map(|i| {
            if i % 4 == 3 {
                nalgebra::Vector6::zeros()
            } else {
                sampler.sample_a(&rod, &mut rng)
            }
        })
        .collect();

    let (one, one_stable) = pool(1).install(|| {
        (
            batch::solve_all(&rod, &configurations, 32),
            batch::stable_all(&rod, &configurations),
        )
    });
    let (four, four_stable) = pool(4).install(|| {
        (
            batch::solve_all(&rod, &configurations, 32),
            batch::stable_all(&rod, &configurations),
        )
    });

    assert_eq!(one.len(), configurations.len());
    assert!(one.iter().any(Result::is_ok) && one.iter().any(Result::is_err));
    assert_eq!(bits(&one), bits(&four));
    assert_eq!(bits(&one_stable), bits(&four_stable));
    // And both equal the plain serial solves, in input order.
    for (a, r) in configurations.iter().zip(&one) {
        assert_eq!(format!("{r:?}"), format!("{:?}", rod.solve(a, 32)));
    }
}
