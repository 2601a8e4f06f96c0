//! Tests of the motion-capture model.

use approx::assert_abs_diff_eq;
use ftwire_core::CoreError;
use ftwire_sim::markers::uniform_arc_lengths;
use ftwire_sim::{
    MarkerFrame, MarkerParams, MotionCapture, SectionFrames, SensingError, point_at_arc_length,
};
use nalgebra::{Matrix3, Point3, Rotation3, Vector2, Vector3};

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

/// A wire with its material frames at its nodes.
struct FramedWire {
    nodes: Vec<Point3<f64>>,
    /// World from body, columns `(t, m1, m2)`.
    frames: Vec<Rotation3<f64>>,
    arc_lengths: Vec<f64>,
    length: f64,
}

impl FramedWire {
    fn sections(&self) -> SectionFrames<'_> {
        SectionFrames {
            frames: &self.frames,
            arc_lengths: &self.arc_lengths,
        }
    }
}

/// A quarter circle of radius 0.4 m in the xy plane, twisted at `twist` \[rad/m\] about its
/// tangent, with `edges + 1` nodes evenly spaced in arc length.
fn twisted_arc(edges: usize, twist: f64) -> FramedWire {
    let radius = 0.4;
    let length = std::f64::consts::FRAC_PI_2 * radius;
    let arc_lengths = uniform_arc_lengths(edges + 1, length);
    let nodes = arc_lengths.iter().map(|&s| arc_point(radius, s)).collect();
    let frames = arc_lengths
        .iter()
        .map(|&s| {
            let theta = s / radius;
            let t = Vector3::new(theta.cos(), theta.sin(), 0.0);
            let n = Vector3::new(-theta.sin(), theta.cos(), 0.0);
            let (sin, cos) = (twist * s).sin_cos();
            let m1 = cos * n + sin * Vector3::z();
            Rotation3::from_matrix_unchecked(Matrix3::from_columns(&[t, m1, t.cross(&m1)]))
        })
        .collect();
    FramedWire {
        nodes,
        frames,
        arc_lengths,
        length,
    }
}

/// A straight untwisted wire of the same length along x, in the same layout.
fn straight_untwisted(edges: usize) -> FramedWire {
    let length = std::f64::consts::FRAC_PI_2 * 0.4;
    let arc_lengths = uniform_arc_lengths(edges + 1, length);
    FramedWire {
        nodes: arc_lengths
            .iter()
            .map(|&s| Point3::new(s, 0.0, 0.0))
            .collect(),
        frames: vec![Rotation3::identity(); edges + 1],
        arc_lengths,
        length,
    }
}

fn mounted(mount_offset: f64, mount_seed: u64) -> MarkerParams {
    MarkerParams {
        mount_offset,
        mount_seed,
        ..MarkerParams::default()
    }
}

fn bits(v: &[Vector2<f64>]) -> Vec<[u64; 2]> {
    v.iter().map(|o| [o.x.to_bits(), o.y.to_bits()]).collect()
}

/// A marker glued on the wire keeps its offset in the wire's cross-section frame from frame to
/// frame, whatever the wire's shape and twist; its noise comes on top.
#[test]
fn mounting_offsets_are_fixed_per_marker_and_turn_with_the_wire() {
    let config = mounted(0.002, 17);
    let mut m = mocap(config.clone(), 4);
    let offsets = m.mount_offsets().to_vec();
    assert_eq!(offsets.len(), 11);
    assert!(offsets.iter().all(|o| o.norm() > 0.0), "{offsets:?}");
    // The same markers in another rig (another noise seed); another set glued, other offsets.
    assert_eq!(
        bits(mocap(config.clone(), 99).mount_offsets()),
        bits(&offsets)
    );
    assert_ne!(
        bits(mocap(mounted(0.002, 18), 4).mount_offsets()),
        bits(&offsets)
    );

    // Fractions k/10 fall on nodes 10k, where the frames are exact.
    for FramedWire {
        nodes,
        frames,
        arc_lengths,
        length,
    } in [straight_untwisted(100), twisted_arc(100, 9.0)]
    {
        let sections = SectionFrames {
            frames: &frames,
            arc_lengths: &arc_lengths,
        };
        let on_line = ok(m.true_positions(&nodes, &arc_lengths, length));
        let centres = ok(m.mounted_positions(&nodes, &arc_lengths, length, &sections));
        let mut sums = vec![(Vector3::zeros(), 0_u32); 11];
        for k in 0..400 {
            let frame =
                ok(m.observe_mounted(k as f64 * 0.01, &nodes, &arc_lengths, length, &sections));
            for ((p, (sum, n)), q) in frame.positions.iter().zip(&mut sums).zip(&on_line) {
                if let Some(p) = p {
                    *sum += p - q;
                    *n += 1;
                }
            }
        }
        for (i, (o, (sum, n))) in offsets.iter().zip(&sums).enumerate() {
            let frame = frames[10 * i];
            let body = Vector3::new(0.0, o.x, o.y);
            // Exactly the offset in the frame at the marker, without noise...
            assert_abs_diff_eq!(centres[i] - on_line[i], frame * body, epsilon = 1e-12);
            // ... and on average over noisy frames (σ 0.3 mm, 400 frames: 0.015 mm).
            let mean = frame.inverse() * (sum / f64::from(*n));
            assert_abs_diff_eq!(mean, body, epsilon = 1e-4);
        }
    }
}

/// Every marker's centre sits the distance asked for off the centreline, so their RMS is that
/// distance exactly, in directions spread evenly about the wire.
#[test]
fn mounting_offsets_have_the_rms_asked_for() {
    let offset = 0.00175;
    let count = 4001;
    let m = mocap(
        MarkerParams {
            fractions: uniform_arc_lengths(count, 1.0),
            mount_offset: offset,
            mount_seed: 3,
            ..MarkerParams::ideal()
        },
        0,
    );
    // Frames between the markers: their centres come from interpolated frames.
    let wire = twisted_arc(1000, 4.0);
    let (nodes, arc_lengths, length) = (&wire.nodes[..], &wire.arc_lengths[..], wire.length);
    let sections = wire.sections();
    let on_line = ok(m.true_positions(nodes, arc_lengths, length));
    let centres = ok(m.mounted_positions(nodes, arc_lengths, length, &sections));
    let squares: Vec<f64> = centres
        .iter()
        .zip(&on_line)
        .map(|(c, p)| (c - p).norm_squared())
        .collect();
    let rms = (squares.iter().sum::<f64>() / count as f64).sqrt();
    assert_abs_diff_eq!(rms, offset, epsilon = 1e-9 * offset);
    let worst = squares
        .iter()
        .map(|d| (d.sqrt() - offset).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-9 * offset,
        "a marker {worst} m from the others' distance"
    );
    // Uniform directions: per cross-section axis the RMS is offset/√2, the mean 0 (4001
    // draws: standard errors 0.6 % and 1.1 % of the offset).
    let n = count as f64;
    for axis in [0, 1] {
        let values = m.mount_offsets().iter().map(|o| o[axis] / offset);
        let (sum, sum_sq) = values.fold((0.0, 0.0), |(s, q), v| (s + v, q + v * v));
        assert!((sum / n).abs() < 0.04, "axis {axis}: mean {}", sum / n);
        let axis_rms = (sum_sq / n).sqrt();
        assert!(
            (axis_rms * std::f64::consts::SQRT_2 - 1.0).abs() < 0.04,
            "axis {axis}: RMS {axis_rms}"
        );
    }
}

/// Without a mounting offset the frames are the old ones bit for bit: the points on the
/// centreline, then per marker three normal draws of noise and one uniform for the dropout
/// from the rig's stream, whatever the mount seed and the frames.
#[test]
fn no_mounting_offset_reproduces_the_centreline_markers_bit_for_bit() {
    use rand::{RngExt, SeedableRng};
    use rand_distr::StandardNormal;

    let wire = twisted_arc(100, 9.0);
    let (nodes, arc_lengths, length) = (&wire.nodes[..], &wire.arc_lengths[..], wire.length);
    let sections = wire.sections();
    let config = MarkerParams {
        fractions: vec![0.0, 0.0123, 0.2345, 0.5, 0.5555, 0.7891, 0.999, 1.0],
        dropout_probability: 0.3,
        ..mounted(0.0, 12345)
    };
    let mut plain = mocap(config.clone(), 8);
    let mut with_frames = mocap(config.clone(), 8);
    assert!(with_frames.mount_offsets().iter().all(|o| o.norm() == 0.0));
    let truth = ok(plain.true_positions(nodes, arc_lengths, length));
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(8);
    let key = |p: &Option<Point3<f64>>| p.map(|p| p.coords.map(f64::to_bits));
    for k in 0..50 {
        let time = k as f64 * 0.1;
        let expected: Vec<_> = truth
            .iter()
            .map(|p| {
                let noise = Vector3::from_fn(|_, _| rng.sample::<f64, _>(StandardNormal));
                let dropped = rng.random::<f64>() < config.dropout_probability;
                (!dropped).then(|| p + config.noise_std * noise)
            })
            .collect();
        let a = ok(plain.observe(time, nodes, arc_lengths, length));
        let b = ok(with_frames.observe_mounted(time, nodes, arc_lengths, length, &sections));
        let expected: Vec<_> = expected.iter().map(key).collect();
        assert_eq!(a.positions.iter().map(key).collect::<Vec<_>>(), expected);
        assert_eq!(b.positions.iter().map(key).collect::<Vec<_>>(), expected);
    }
}

#[test]
fn a_bad_mounting_is_rejected_with_what_is_allowed() {
    for bad in [-1e-3, 0.0501, f64::NAN, f64::INFINITY] {
        match MotionCapture::new(mounted(bad, 0), 0) {
            Err(e @ SensingError::OutOfRange { field, .. }) => {
                assert_eq!(field, "mount_offset");
                assert!(e.to_string().contains("0 ..= 0.05"), "{e}");
            }
            other => panic!("{bad} accepted: {other:?}"),
        }
    }
    assert!(MotionCapture::new(mounted(0.05, u64::MAX), 0).is_ok());
    // Offsets need the cross-section frames they turn with.
    let FramedWire {
        nodes,
        frames,
        arc_lengths,
        length,
    } = twisted_arc(10, 0.0);
    let mut m = mocap(mounted(0.002, 1), 0);
    assert!(matches!(
        m.observe(0.0, &nodes, &arc_lengths, length),
        Err(SensingError::MountingWithoutFrames { .. })
    ));
    let short = SectionFrames {
        frames: &frames[..3],
        arc_lengths: &arc_lengths,
    };
    assert!(matches!(
        m.observe_mounted(0.0, &nodes, &arc_lengths, length, &short),
        Err(SensingError::SectionFrames {
            frames: 3,
            arc_lengths: 11
        })
    ));
    let partial = SectionFrames {
        frames: &frames[..3],
        arc_lengths: &arc_lengths[..3],
    };
    assert!(matches!(
        m.observe_mounted(0.0, &nodes, &arc_lengths, length, &partial),
        Err(SensingError::MarkerOutsideCentreline { .. })
    ));
    let mut bad = frames.clone();
    bad[4] = Rotation3::from_matrix_unchecked(Matrix3::from_element(f64::NAN));
    let bad = SectionFrames {
        frames: &bad,
        arc_lengths: &arc_lengths,
    };
    assert!(matches!(
        m.observe_mounted(0.0, &nodes, &arc_lengths, length, &bad),
        Err(SensingError::Core(CoreError::NonFinite { index: 4, .. }))
    ));
}
