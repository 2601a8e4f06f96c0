//! Unit tests of the parent module.

use super::*;
use crate::node::stamp;
use nalgebra::Vector3 as V3;

fn edge(parent: &str, child: &str, pose: &Isometry3<f64>, t: f64) -> TransformStamped {
    let (p, q) = (&pose.translation.vector, pose.rotation.quaternion());
    TransformStamped {
        header: Header {
            stamp: stamp(t),
            frame_id: parent.into(),
        },
        child_frame_id: child.into(),
        transform: Transform {
            translation: Vector3 {
                x: p.x,
                y: p.y,
                z: p.z,
            },
            rotation: RosQuaternion {
                x: q.i,
                y: q.j,
                z: q.k,
                w: q.w,
            },
        },
    }
}

fn pose(x: f64, y: f64, z: f64, axis: [f64; 3], angle: f64) -> Isometry3<f64> {
    Isometry3::new(V3::new(x, y, z), V3::from(axis).normalize() * angle)
}

fn close(a: &Isometry3<f64>, b: &Isometry3<f64>) -> bool {
    (a.translation.vector - b.translation.vector).norm() < 1e-12
        && a.rotation.angle_to(&b.rotation) < 1e-12
}

/// world → torso → left (the base clamp), world → torso → right → tip: the chain's answer is
/// the poses composed directly, either way round.
#[test]
fn a_chain_composes_to_the_direct_pose_either_way_round() {
    let torso = pose(0.1, 0.0, 0.9, [0.0, 0.0, 1.0], 0.3);
    let left = pose(0.3, 0.2, 0.1, [1.0, 0.5, 0.0], 1.1);
    let right = pose(0.3, -0.2, 0.1, [0.2, 1.0, 0.3], -0.7);
    let tip = pose(0.0, 0.0, 0.15, [0.0, 1.0, 0.0], 2.0);
    let mut tf = TfBuffer::new();
    tf.insert(&edge("world", "torso", &torso, 0.0), true)
        .expect("an edge");
    tf.insert(&edge("torso", "left", &left, 1.0), false)
        .expect("an edge");
    tf.insert(&edge("torso", "right", &right, 1.0), false)
        .expect("an edge");
    tf.insert(&edge("right", "tip", &tip, 1.0), false)
        .expect("an edge");
    let direct = (torso * left).inverse() * (torso * right * tip);
    let got = tf.lookup("left", "tip", 1.1, 0.5).expect("a chain");
    assert!(close(&got, &direct), "{got} vs {direct}");
    let back = tf.lookup("tip", "left", 1.1, 0.5).expect("a chain");
    assert!(close(&back, &direct.inverse()), "{back}");
    // Through the root, and a frame in its own frame.
    let world = tf.lookup("world", "tip", 1.1, 0.5).expect("a chain");
    assert!(close(&world, &(torso * right * tip)));
    assert!(close(
        &tf.lookup("tip", "tip", 1.1, 0.5).expect("itself"),
        &Isometry3::identity()
    ));
}

#[test]
fn a_missing_edge_is_not_available_and_an_old_one_stale() {
    let one = pose(1.0, 0.0, 0.0, [0.0, 0.0, 1.0], 0.0);
    let mut tf = TfBuffer::new();
    tf.insert(&edge("world", "base", &one, 0.0), true)
        .expect("an edge");
    assert!(matches!(
        tf.lookup("base", "tip", 0.0, 0.5),
        Err(TfMiss::NotAvailable { .. })
    ));
    // A tip in another tree is not available either.
    tf.insert(&edge("odom", "tip", &one, 2.0), false)
        .expect("an edge");
    assert!(matches!(
        tf.lookup("base", "tip", 2.0, 0.5),
        Err(TfMiss::NotAvailable { .. })
    ));
    tf.insert(&edge("world", "tip", &one, 2.0), false)
        .expect("a re-parenting");
    assert!(tf.lookup("base", "tip", 2.4, 0.5).is_ok());
    match tf.lookup("base", "tip", 2.6, 0.5) {
        Err(TfMiss::Stale { child, age }) => {
            assert_eq!(child, "tip");
            assert!((age - 0.6).abs() < 1e-9);
        }
        other => panic!("stale expected: {other:?}"),
    }
    // The static edge never is.
    assert!(tf.lookup("world", "base", 1e6, 0.5).is_ok());
}

#[test]
fn bad_edges_are_refused_and_change_nothing() {
    let one = pose(1.0, 0.0, 0.0, [0.0, 0.0, 1.0], 0.0);
    let mut tf = TfBuffer::new();
    tf.insert(&edge("a", "b", &one, 1.0), false)
        .expect("an edge");
    tf.insert(&edge("b", "c", &one, 1.0), false)
        .expect("an edge");
    let before = tf.clone();
    let refused = |tf: &mut TfBuffer, e: TransformStamped| {
        tf.insert(&e, false)
            .map_err(|r| r.name())
            .expect_err("refused")
    };
    assert_eq!(refused(&mut tf, edge("c", "a", &one, 2.0)), "tf_loop");
    assert_eq!(refused(&mut tf, edge("c", "c", &one, 2.0)), "tf_loop");
    let mut nan = edge("a", "d", &one, 2.0);
    nan.transform.translation.y = f64::NAN;
    assert_eq!(refused(&mut tf, nan), "tf_non_finite");
    let mut inf = edge("a", "d", &one, 2.0);
    inf.transform.rotation.w = f64::INFINITY;
    assert_eq!(refused(&mut tf, inf), "tf_non_finite");
    let mut skew = edge("a", "d", &one, 2.0);
    skew.transform.rotation.w = 1.5;
    assert_eq!(refused(&mut tf, skew), "tf_rotation");
    assert_eq!(refused(&mut tf, edge("", "d", &one, 2.0)), "tf_frame_id");
    assert_eq!(refused(&mut tf, edge("a", "b", &one, 0.5)), "tf_backwards");
    assert_eq!(tf, before);
    // Close to unit length: normalised.
    let mut near = edge("a", "d", &one, 2.0);
    near.transform.rotation.w = 1.0005;
    tf.insert(&near, false).expect("normalised");
    let d = tf.lookup("a", "d", 2.0, 0.5).expect("a chain");
    assert!((d.rotation.quaternion().norm() - 1.0).abs() < 1e-12);
    // The same stamp again replaces the edge.
    tf.insert(
        &edge("a", "b", &pose(2.0, 0.0, 0.0, [0.0, 0.0, 1.0], 0.0), 1.0),
        false,
    )
    .expect("the same stamp");
    let b = tf.lookup("a", "b", 1.0, 0.5).expect("a chain");
    assert!((b.translation.vector.x - 2.0).abs() < 1e-12);
}

#[test]
fn frames_are_checked() {
    let ok = TfFrames {
        base: "wire_base".into(),
        tip: "wire_tip".into(),
        stale: DEFAULT_STALE,
    };
    assert!(ok.validate().is_ok());
    for bad in [
        TfFrames {
            base: String::new(),
            ..ok.clone()
        },
        TfFrames {
            tip: "/wire_tip".into(),
            ..ok.clone()
        },
        TfFrames {
            tip: "wire base".into(),
            ..ok.clone()
        },
        TfFrames {
            tip: "wire_base".into(),
            ..ok.clone()
        },
        TfFrames {
            stale: 0.0,
            ..ok.clone()
        },
        TfFrames {
            stale: f64::NAN,
            ..ok.clone()
        },
    ] {
        assert!(bad.validate().is_err(), "{bad:?}");
    }
}
