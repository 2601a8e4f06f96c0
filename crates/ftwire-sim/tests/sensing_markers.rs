//! Tests of the motion-capture model.

use approx::assert_abs_diff_eq;
use ftwire_core::CoreError;
use ftwire_sim::markers::uniform_arc_lengths;
use ftwire_sim::{MarkerFrame, MarkerParams, MotionCapture, SensingError, point_at_arc_length};
use nalgebra::{Point3, Vector3};

fn mocap(config: MarkerParams, seed: u64) -> MotionCapture {
    match MotionCapture::new(config, seed) {
        Ok(m) => m,
        Err(e) => panic!("valid configuration rejected: {e}"),
    }
}

fn ok<T>(result: Result<T, SensingError>) -> T {
    match result {
        Ok(value) => value,
        Err(e) => panic!("unexpected error: {e}"),
    }
}

/// A straight wire of length `length` from `start` along `direction`, with `edges` edges.
fn straight(
    start: Point3<f64>,
    direction: Vector3<f64>,
    length: f64,
    edges: usize,
) -> Vec<Point3<f64>> {
    let d = direction.normalize();
    uniform_arc_lengths(edges + 1, length)
        .into_iter()
        .map(|s| start + s * d)
        .collect()
}

/// A planar circular arc of radius `radius` in the xy plane, starting at the origin along x.
fn arc_point(radius: f64, s: f64) -> Point3<f64> {
    let theta = s / radius;
    Point3::new(radius * theta.sin(), radius * (1.0 - theta.cos()), 0.0)
}

#[test]
fn markers_sit_at_their_arc_lengths_on_a_straight_wire() {
    let (start, direction, length) = (
        Point3::new(0.1, -0.2, 0.3),
        Vector3::new(1.0, 2.0, -0.5),
        0.63,
    );
    let nodes = straight(start, direction, length, 100);
    let mut m = mocap(MarkerParams::ideal(), 1);
    let frame = ok(m.observe_uniform(0.5, &nodes, length));
    assert_eq!(frame.time, 0.5);
    assert_eq!(frame.positions.len(), 11);
    for (k, p) in frame.positions.iter().enumerate() {
        let expected = start + (k as f64 * 0.1 * length) * direction.normalize();
        match p {
            Some(p) => assert_abs_diff_eq!(*p, expected, epsilon = 1e-12),
            None => panic!("marker {k} dropped in the ideal configuration"),
        }
    }
}

#[test]
fn markers_sit_on_a_circular_arc() {
    // A quarter circle of radius 0.4 m: L = 0.2π.
    let radius = 0.4;
    let length = std::f64::consts::FRAC_PI_2 * radius;
    let edges = 100;
    let arc_lengths = uniform_arc_lengths(edges + 1, length);
    let nodes: Vec<_> = arc_lengths.iter().map(|&s| arc_point(radius, s)).collect();

    // Fractions k/10 fall on nodes 10k: exact points of the circle.
    let m = mocap(MarkerParams::ideal(), 2);
    let truth = ok(m.true_positions(&nodes, &arc_lengths, length));
    for (k, p) in truth.iter().enumerate() {
        assert_abs_diff_eq!(
            *p,
            arc_point(radius, k as f64 * 0.1 * length),
            epsilon = 1e-12
        );
    }

    // Between nodes the polyline is a chord: within the sagitta h²/(8R) of the circle, and at
    // the right place along the chord.
    let h = length / edges as f64;
    let fractions = vec![0.0123, 0.2345, 0.5555, 0.7891, 0.999];
    let m = mocap(
        MarkerParams {
            fractions: fractions.clone(),
            ..MarkerParams::ideal()
        },
        2,
    );
    let truth = ok(m.true_positions(&nodes, &arc_lengths, length));
    for (p, f) in truth.iter().zip(&fractions) {
        let s = f * length;
        let exact = arc_point(radius, s);
        let distance = (p - exact).norm();
        assert!(
            distance <= h * h / (8.0 * radius) + 1e-15,
            "off the arc by {distance}"
        );
        let j = (s / h).floor();
        let t = s / h - j;
        let chord = arc_point(radius, j * h)
            + t * (arc_point(radius, (j + 1.0) * h) - arc_point(radius, j * h));
        assert_abs_diff_eq!(*p, chord, epsilon = 1e-12);
    }
}

#[test]
fn arc_lengths_may_extend_beyond_the_clamps() {
    // A discretisation whose end nodes lie half an edge outside the wire, as a clamp layout
    // with half-outside end edges has.
    let length = 0.5;
    let h = length / 10.0;
    let arc_lengths: Vec<f64> = (0..12).map(|i| -0.5 * h + i as f64 * h).collect();
    let nodes: Vec<_> = arc_lengths
        .iter()
        .map(|&s| Point3::new(0.0, s, 0.0))
        .collect();
    let m = mocap(MarkerParams::ideal(), 3);
    let truth = ok(m.true_positions(&nodes, &arc_lengths, length));
    for (k, p) in truth.iter().enumerate() {
        assert_abs_diff_eq!(*p, Point3::new(0.0, k as f64 * 0.05, 0.0), epsilon = 1e-14);
    }
}

fn frames(config: MarkerParams, seed: u64, count: usize) -> (Vec<Point3<f64>>, Vec<MarkerFrame>) {
    let length = 0.63;
    let nodes = straight(Point3::origin(), Vector3::new(0.0, 0.0, 1.0), length, 63);
    let mut m = mocap(config, seed);
    let truth = ok(m.true_positions(&nodes, &uniform_arc_lengths(64, length), length));
    let frames = (0..count)
        .map(|k| ok(m.observe_uniform(k as f64 * 0.01, &nodes, length)))
        .collect();
    (truth, frames)
}

#[test]
fn marker_noise_has_the_configured_standard_deviation() {
    let sigma = MarkerParams::default().noise_std;
    let config = MarkerParams {
        dropout_probability: 0.0,
        ..MarkerParams::default()
    };
    let (truth, frames) = frames(config, 4, 3000);
    let mut errors = Vec::new();
    for frame in &frames {
        for (p, t) in frame.positions.iter().zip(&truth) {
            match p {
                Some(p) => errors.extend((p - t).iter().copied()),
                None => panic!("dropout with probability 0"),
            }
        }
    }
    let n = errors.len() as f64;
    let mean = errors.iter().sum::<f64>() / n;
    let std = (errors.iter().map(|e| (e - mean).powi(2)).sum::<f64>() / n).sqrt();
    assert!(mean.abs() < 4.0 * sigma / n.sqrt(), "mean {mean}");
    assert!((std / sigma - 1.0).abs() < 0.03, "std {std}, σ {sigma}");
}

#[test]
fn markers_drop_out_at_the_configured_rate() {
    let p = MarkerParams::default().dropout_probability;
    let (_, frames) = frames(MarkerParams::default(), 5, 20_000);
    let total = frames.iter().map(|f| f.positions.len()).sum::<usize>() as f64;
    let dropped = frames
        .iter()
        .flat_map(|f| &f.positions)
        .filter(|p| p.is_none())
        .count() as f64;
    let expected = p * total;
    let tolerance = 4.0 * (expected * (1.0 - p)).sqrt();
    assert!(
        (dropped - expected).abs() < tolerance,
        "{dropped} dropouts, expected {expected} ± {tolerance}"
    );
}

#[test]
fn the_same_seed_gives_the_same_frames_and_another_seed_does_not() {
    let (_, a) = frames(MarkerParams::default(), 6, 50);
    let (_, b) = frames(MarkerParams::default(), 6, 50);
    let (_, c) = frames(MarkerParams::default(), 7, 50);
    assert_eq!(a, b);
    assert_ne!(a, c);
}

#[test]
fn bad_inputs_give_clear_errors() {
    for (config, field) in [
        (
            MarkerParams {
                fractions: vec![0.0, -0.1],
                ..MarkerParams::default()
            },
            "fractions",
        ),
        (
            MarkerParams {
                fractions: vec![f64::NAN],
                ..MarkerParams::default()
            },
            "fractions",
        ),
        (
            MarkerParams {
                noise_std: -1e-3,
                ..MarkerParams::default()
            },
            "noise_std",
        ),
        (
            MarkerParams {
                dropout_probability: 1.5,
                ..MarkerParams::default()
            },
            "dropout_probability",
        ),
    ] {
        match MotionCapture::new(config, 0) {
            Err(SensingError::OutOfRange { field: f, .. }) => assert_eq!(f, field),
            other => panic!("expected an error naming {field}, got {other:?}"),
        }
    }

    let mut m = mocap(MarkerParams::default(), 8);
    let line = [Point3::origin(), Point3::new(1.0, 0.0, 0.0)];
    assert!(matches!(
        m.observe(0.0, &line[..1], &[0.0], 1.0),
        Err(SensingError::TooFewNodes { nodes: 1, min: 2 })
    ));
    assert!(matches!(
        m.observe_uniform(0.0, &[], 1.0),
        Err(SensingError::TooFewNodes { nodes: 0, .. })
    ));
    let bad_point = [Point3::origin(), Point3::new(1.0, f64::INFINITY, 0.0)];
    assert!(matches!(
        m.observe(0.0, &bad_point, &[0.0, 1.0], 1.0),
        Err(SensingError::Core(CoreError::NonFinite {
            field: "centreline",
            index: 1,
            ..
        }))
    ));
    assert!(matches!(
        m.observe(0.0, &line, &[0.0], 1.0),
        Err(SensingError::ArcLengthCount {
            nodes: 2,
            arc_lengths: 1
        })
    ));
    assert!(matches!(
        m.observe(0.0, &line, &[1.0, 1.0], 1.0),
        Err(SensingError::ArcLengthsNotIncreasing { index: 1, .. })
    ));
    assert!(matches!(
        m.observe(0.0, &line, &[0.0, f64::NAN], 1.0),
        Err(SensingError::Core(_))
    ));
    // The wire is longer than the centreline given: the last markers fall off its end.
    assert!(matches!(
        m.observe(0.0, &line, &[0.0, 1.0], 2.0),
        Err(SensingError::MarkerOutsideCentreline { marker: 6, .. })
    ));
    for length in [0.0, -1.0, f64::NAN] {
        assert!(matches!(
            m.observe(0.0, &line, &[0.0, 1.0], length),
            Err(SensingError::OutOfRange {
                field: "length",
                ..
            })
        ));
    }
    assert!(m.observe(f64::NAN, &line, &[0.0, 1.0], 1.0).is_err());
    assert!(point_at_arc_length(&line, &[0.0, 1.0], 1.5).is_err());
    assert!(point_at_arc_length(&line, &[0.0, 1.0], f64::NAN).is_err());
}
