//! Coarse collision checks: distance functions against brute force, postures that obviously
//! collide or do not.

use ftwire_robot::{
    Arm, Contact, EndFrame, IkParams, IkTarget, LinkRadii, OrientedBox, Robot, point_box_distance,
    segment_box_distance, segment_segment_distance,
};
use nalgebra::{Point3, Translation3, UnitQuaternion, Vector3};
use proptest::prelude::*;

fn robot() -> Robot {
    Robot::sda10f().expect("embedded URDF")
}

fn point(v: [f64; 3]) -> Point3<f64> {
    Point3::from(Vector3::from(v))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn segment_distances_match_brute_force(
        a in prop::array::uniform3(-1.0f64..1.0), b in prop::array::uniform3(-1.0f64..1.0),
        c in prop::array::uniform3(-1.0f64..1.0), d in prop::array::uniform3(-1.0f64..1.0),
        h in prop::array::uniform3(0.05f64..0.5), r in prop::array::uniform3(-3.0f64..3.0),
    ) {
        let (a, b, c, d) = (point(a), point(b), point(c), point(d));
        let boxed = OrientedBox::new(
            ftwire_core::Pose::from_parts(Translation3::new(0.1, -0.2, 0.3), UnitQuaternion::from_scaled_axis(Vector3::from(r))),
            Vector3::from(h),
        ).expect("valid box");
        let n = 400;
        let at = |p: &Point3<f64>, q: &Point3<f64>, i: usize| p + (q - p) * (i as f64 / n as f64);
        let mut brute_ss = f64::INFINITY;
        let mut brute_sb = f64::INFINITY;
        for i in 0..=n {
            let p = at(&a, &b, i);
            brute_sb = brute_sb.min(point_box_distance(&p, &boxed));
            for j in 0..=n {
                brute_ss = brute_ss.min((p - at(&c, &d, j)).norm());
            }
        }
        let ss = segment_segment_distance(&a, &b, &c, &d);
        let sb = segment_box_distance(&a, &b, &boxed);
        // Exact minimum ≤ sampled minimum ≤ exact minimum + sampling error.
        let tol = 3.0 * 2.0 / n as f64 + 1e-9;
        prop_assert!(ss <= brute_ss + 1e-12 && brute_ss <= ss + tol, "ss {ss} vs {brute_ss}");
        prop_assert!(sb <= brute_sb + 1e-9 && brute_sb <= sb + tol, "sb {sb} vs {brute_sb}");
    }
}

#[test]
fn preferred_postures_do_not_collide() {
    let robot = robot();
    let contact = robot
        .arms_collision(
            0.0,
            robot.preferred_posture(Arm::Left),
            robot.preferred_posture(Arm::Right),
            &LinkRadii::default(),
        )
        .expect("valid postures");
    assert_eq!(contact, None);
}

#[test]
fn grippers_at_the_same_point_collide() {
    let robot = robot();
    let left = *robot.preferred_posture(Arm::Left);
    let right = *robot.preferred_posture(Arm::Right);
    let base = robot
        .fk(Arm::Left, 0.0, &left, EndFrame::Gripper)
        .expect("fk");
    let tip = robot
        .fk(Arm::Right, 0.0, &right, EndFrame::Gripper)
        .expect("fk");
    // Move the right gripper onto the left gripper's clamp point.
    let target = IkTarget {
        arm: Arm::Right,
        pose: ftwire_core::Pose::from_parts(base.translation, tip.rotation),
        torso: 0.0,
        frame: EndFrame::Gripper,
    };
    let s = robot
        .ik(&target, Some(&right), &IkParams::default())
        .expect("reachable");
    let contact = robot
        .arms_collision(0.0, &left, &s.joints, &LinkRadii::default())
        .expect("valid postures");
    assert!(
        matches!(contact, Some(Contact::Arms { left: 6, .. })),
        "got {contact:?}"
    );
}

#[test]
fn boxes_around_and_away_from_the_gripper() {
    let robot = robot();
    let q = *robot.preferred_posture(Arm::Left);
    let g = robot
        .fk(Arm::Left, 0.0, &q, EndFrame::Gripper)
        .expect("fk")
        .translation
        .vector;
    let radii = LinkRadii::default();
    let around = OrientedBox::aabb(
        Point3::from(g - Vector3::repeat(0.02)),
        Point3::from(g + Vector3::repeat(0.02)),
    )
    .expect("box");
    let away =
        OrientedBox::aabb(Point3::new(1.5, -1.0, -0.5), Point3::new(2.0, 1.0, 0.0)).expect("box");
    // A thin slab just clear of the gripper capsule's surface, then touching it.
    let below = |gap: f64| {
        let top = g.z - radii.radii[6] - gap;
        OrientedBox::aabb(
            Point3::new(g.x - 0.05, g.y - 0.05, top - 0.01),
            Point3::new(g.x + 0.05, g.y + 0.05, top),
        )
        .expect("box")
    };
    let check = |boxes: &[OrientedBox]| {
        robot
            .arm_obstacle_collision(Arm::Left, 0.0, &q, boxes, &radii)
            .expect("valid posture")
    };
    assert_eq!(
        check(&[away, around]),
        Some(Contact::Obstacle {
            arm: Arm::Left,
            link: 6,
            obstacle: 1
        })
    );
    assert_eq!(check(&[away]), None);
    assert_eq!(check(&[below(0.001)]), None);
    assert!(check(&[below(-0.001)]).is_some());
}
