// Scratch measurement program of parry.md (not built by the workspace). Cargo.toml deps:
// parry3d-f64 = "0.31", ftwire-core/ftwire-robot (path), nalgebra = "0.35", rand = "0.10",
// rand_chacha = "0.10"; run with `cargo run --release` in a scratch crate.
//! Scratch measurement (not part of ftwire): parry3d-f64 0.31 against ftwire's own
//! segment–segment and segment–box distances on random pairs. Seeded.
use std::hint::black_box;
use std::time::Instant;

use ftwire_robot::{OrientedBox, segment_box_distance};
use nalgebra::{Point3, Translation3, UnitQuaternion, Vector3};
use parry3d_f64::math::{Pose, Rot3, Vector};
use parry3d_f64::query;
use parry3d_f64::shape::{Cuboid, Segment};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn dv(v: &Vector3<f64>) -> Vector {
    Vector::new(v.x, v.y, v.z)
}

fn main() {
    let mut rng = ChaCha8Rng::seed_from_u64(7);
    let n = 20_000;
    let mut u = |lo: f64, hi: f64| lo + (hi - lo) * rng.random::<f64>();
    // Random segment/box pairs in the robot's scale: segments in [-1, 1]^3, boxes with half
    // extents 0.05–0.5 m, random orientation, centre near the origin.
    let mut segs = Vec::new();
    let mut boxes = Vec::new();
    for _ in 0..n {
        let a = Vector3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0));
        let b = Vector3::new(u(-1.0, 1.0), u(-1.0, 1.0), u(-1.0, 1.0));
        let h = Vector3::new(u(0.05, 0.5), u(0.05, 0.5), u(0.05, 0.5));
        let r = Vector3::new(u(-3.0, 3.0), u(-3.0, 3.0), u(-3.0, 3.0));
        let t = Vector3::new(u(-0.3, 0.3), u(-0.3, 0.3), u(-0.3, 0.3));
        let q = UnitQuaternion::from_scaled_axis(r);
        let pose = nalgebra::Isometry3::from_parts(Translation3::from(t), q);
        let ob = OrientedBox::new(pose, h).unwrap();
        let ppose = Pose::from_parts(dv(&t), Rot3::from_xyzw(q.i, q.j, q.k, q.w));
        segs.push((a, b));
        boxes.push((ob, ppose, Cuboid::new(dv(&h))));
    }
    // Accuracy: ours vs parry; separated pairs only (both are 0 when they meet).
    let (mut max_diff, mut sep, mut both_zero, mut disagree_zero) = (0.0f64, 0, 0, 0);
    let mut worst = (0.0, 0.0);
    for ((a, b), (ob, pp, cub)) in segs.iter().zip(&boxes) {
        let ours = segment_box_distance(&Point3::from(*a), &Point3::from(*b), ob);
        let theirs = query::distance(&Pose::identity(), &Segment::new(dv(a), dv(b)), pp, cub)
            .unwrap()
            .distance;
        if ours > 1e-6 && theirs > 1e-6 {
            sep += 1;
            let d = (ours - theirs).abs();
            if d > max_diff {
                max_diff = d;
                worst = (ours, theirs);
            }
        } else if ours <= 1e-6 && theirs <= 1e-6 {
            both_zero += 1;
        } else {
            disagree_zero += 1;
        }
    }
    println!(
        "segment-box: {sep} separated pairs, max |ours - parry| = {max_diff:.3e} (at {:.9} vs {:.9}); {both_zero} both ~0; {disagree_zero} disagree on contact",
        worst.0, worst.1
    );
    // Time per query.
    let reps = 5;
    let t0 = Instant::now();
    let mut acc = 0.0;
    for _ in 0..reps {
        for ((a, b), (ob, _, _)) in segs.iter().zip(&boxes) {
            acc += segment_box_distance(black_box(&Point3::from(*a)), &Point3::from(*b), ob);
        }
    }
    let ours_t = t0.elapsed().as_secs_f64() / (reps * n) as f64;
    let t0 = Instant::now();
    for _ in 0..reps {
        for ((a, b), (_, pp, cub)) in segs.iter().zip(&boxes) {
            let s = Segment::new(dv(black_box(a)), dv(b));
            acc += query::distance(&Pose::identity(), &s, pp, cub).unwrap().distance;
        }
    }
    let parry_t = t0.elapsed().as_secs_f64() / (reps * n) as f64;
    println!(
        "segment-box time per query: ours (golden section) {:.0} ns, parry (GJK, with conversion) {:.0} ns",
        ours_t * 1e9,
        parry_t * 1e9
    );
    // Segment-segment: short wire-like segments (1 cm) and arm-like segments.
    for (label, scale) in [("wire 1 cm", 0.01), ("arm 1 m", 1.0)] {
        let pairs: Vec<_> = segs
            .iter()
            .zip(segs.iter().skip(1))
            .map(|((a, b), (c, d))| (a * scale, a * scale + (b - a) * scale * 0.5, c * scale, c * scale + (d - c) * scale * 0.5))
            .collect();
        let mut max_diff = 0.0f64;
        for (a, b, c, d) in &pairs {
            let ours = ftwire_core::geometry::segment_distance(a, b, c, d);
            let theirs = query::details::distance_segment_segment(
                &Pose::identity(),
                &Segment::new(dv(a), dv(b)),
                &Segment::new(dv(c), dv(d)),
            );
            max_diff = max_diff.max((ours - theirs).abs() / scale);
        }
        let reps = 50;
        let t0 = Instant::now();
        for _ in 0..reps {
            for (a, b, c, d) in &pairs {
                acc += ftwire_core::geometry::segment_distance(black_box(a), b, c, d);
            }
        }
        let ours_t = t0.elapsed().as_secs_f64() / (reps * pairs.len()) as f64;
        let t0 = Instant::now();
        for _ in 0..reps {
            for (a, b, c, d) in &pairs {
                acc += query::details::distance_segment_segment(
                    &Pose::identity(),
                    &Segment::new(dv(black_box(a)), dv(b)),
                    &Segment::new(dv(c), dv(d)),
                );
            }
        }
        let parry_t = t0.elapsed().as_secs_f64() / (reps * pairs.len()) as f64;
        println!(
            "segment-segment ({label}): max |ours - parry| / scale = {max_diff:.3e}; ours {:.1} ns, parry {:.1} ns per query",
            ours_t * 1e9,
            parry_t * 1e9
        );
    }
    black_box(acc);
}
