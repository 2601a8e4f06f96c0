//! Scene files: the shipped passage scene, every bad-input error, and tip configurations.

mod common;

use ftwire_plan::{
    ConfigurationSpec, PlanError, Scene, configuration_for_tip, scene_configuration,
};
use nalgebra::Vector6;

const GOOD: &str = "\
[base]
position = [0.6, 0.35, 0.35]
rotation = [0.0, 0.0, -1.57]

[floor]
height = -0.5

[[obstacle]]
name = \"wall\"
centre = [0.8, 0.0, 0.3]
half_extents = [0.1, 0.02, 0.1]

[configuration.start]
a = [0.0, 0.1, 0.0, -0.1, 0.0, 0.2]
";

fn error(text: &str) -> String {
    match Scene::from_toml(text, "bad.toml") {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(e) => {
            assert!(matches!(e, PlanError::Scene { .. }), "{e:?}");
            e.to_string()
        }
    }
}

#[test]
fn the_passage_scene_parses() {
    let scene = common::shipped_passage();
    assert_eq!(scene.boxes.len(), 2);
    assert_eq!(scene.boxes[0].name, "front block");
    assert!(scene.configuration("start").is_ok());
    assert!(scene.configuration("goal").is_ok());
    // The gap between the boxes is 50 mm.
    let (front, back) = (&scene.boxes[0].geometry, &scene.boxes[1].geometry);
    let gap = (front.pose().translation.x - front.half_extents().x)
        - (back.pose().translation.x + back.half_extents().x);
    approx::assert_abs_diff_eq!(gap, 0.05, epsilon = 1e-12);
}

#[test]
fn a_good_scene_reads_every_field() {
    let scene = Scene::from_toml(GOOD, "good.toml").expect("valid");
    assert_eq!(scene.floor, Some(-0.5));
    assert_eq!(scene.boxes[0].name, "wall");
    assert!(matches!(scene.configurations["start"], ConfigurationSpec::A(a) if a[5] == 0.2));
}

#[test]
fn an_unknown_key_names_the_file_the_line_and_the_key() {
    let m = error(&GOOD.replace("name = \"wall\"", "name = \"wall\"\ncolour = \"red\""));
    assert!(
        m.contains("bad.toml") && m.contains("line 10") && m.contains("colour"),
        "{m}"
    );
    let m = error(&format!("{GOOD}\nspeed = 3\n"));
    assert!(m.contains("speed"), "{m}");
}

#[test]
fn non_positive_extents_name_the_obstacle_and_the_line() {
    for bad in ["0.0", "-0.1"] {
        let m = error(&GOOD.replace("[0.1, 0.02, 0.1]", &format!("[0.1, {bad}, 0.1]")));
        assert!(
            m.contains("line 8") && m.contains("\"wall\"") && m.contains("half_extents[1]"),
            "{m}"
        );
        assert!(m.contains("positive"), "{m}");
    }
}

#[test]
fn non_finite_numbers_are_named() {
    let m = error(&GOOD.replace("[0.8, 0.0, 0.3]", "[0.8, nan, 0.3]"));
    assert!(m.contains("centre[1]") && m.contains("finite"), "{m}");
    let m = error(&GOOD.replace("height = -0.5", "height = inf"));
    assert!(m.contains("height") && m.contains("finite"), "{m}");
    let m = error(&GOOD.replace("-0.1, 0.0, 0.2]", "-0.1, 0.0, -inf]"));
    assert!(m.contains("\"start\"") && m.contains("a[5]"), "{m}");
}

#[test]
fn an_over_large_rotation_vector_is_named_with_its_value_and_the_bound() {
    let m = error(&GOOD.replace("[0.0, 0.0, -1.57]", "[1e300, 0.0, 0.0]"));
    assert!(
        m.contains("line 1")
            && m.contains("[base]")
            && m.contains("1e300")
            && m.contains("at most 1e6 rad"),
        "{m}"
    );
    assert!(!m.contains("NaN"), "{m}");
    let m = error(&GOOD.replace(
        "half_extents = [0.1, 0.02, 0.1]",
        "half_extents = [0.1, 0.02, 0.1]\nrotation = [0.0, 2e6, 0.0]",
    ));
    assert!(m.contains("\"wall\"") && m.contains("rotation"), "{m}");
    // Whole turns are still a rotation: 1000 rad is accepted.
    assert!(
        Scene::from_toml(
            &GOOD.replace("[0.0, 0.0, -1.57]", "[0.0, 0.0, 1000.0]"),
            "t"
        )
        .is_ok()
    );
}

#[test]
fn a_file_with_a_bom_reads_and_invalid_utf8_is_located() {
    let dir = std::env::temp_dir().join(format!("ftwire-plan-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    let with_bom = dir.join("bom.toml");
    std::fs::write(
        &with_bom,
        [b"\xEF\xBB\xBF".as_slice(), GOOD.as_bytes()].concat(),
    )
    .expect("writes");
    let plain = Scene::from_toml(GOOD, "good.toml").expect("valid");
    assert_eq!(Scene::load(&with_bom).expect("a BOM is allowed"), plain);
    let latin1 = dir.join("latin1.toml");
    // "métal" in Latin-1: its é is the single byte 0xE9.
    let text = GOOD.replace("\"wall\"", "\"m@tal\"");
    let bytes: Vec<u8> = text
        .bytes()
        .map(|b| if b == b'@' { 0xE9 } else { b })
        .collect();
    std::fs::write(&latin1, bytes).expect("writes");
    let m = Scene::load(&latin1).expect_err("not UTF-8").to_string();
    assert!(
        m.contains("latin1.toml") && m.contains("line 9, column 10") && m.contains("0xE9"),
        "{m}"
    );
    std::fs::remove_dir_all(&dir).expect("cleans up");
}

#[test]
fn a_configuration_gives_exactly_one_form() {
    let m = error(&GOOD.replace("a = [0.0,", "a_normalised = [1, 1, 1, 1, 1, 1]\na = [0.0,"));
    assert!(m.contains("exactly one") && m.contains("\"start\""), "{m}");
    let m = error(&format!("{GOOD}\n[configuration.empty]\n"));
    assert!(m.contains("\"empty\""), "{m}");
}

#[test]
fn missing_and_malformed_keys_are_errors() {
    let m = error("[floor]\nheight = 0.0\n");
    assert!(m.contains("base"), "{m}");
    let m = error(&GOOD.replace("[0.6, 0.35, 0.35]", "[0.6, 0.35]"));
    assert!(m.contains("line 2"), "{m}");
    let m = error("[base\n");
    assert!(m.contains("line 1"), "{m}");
}

#[test]
fn an_unreadable_file_is_named() {
    let e = Scene::load("/nonexistent/scene.toml").expect_err("no such file");
    assert!(matches!(e, PlanError::Read { .. }));
    assert!(e.to_string().contains("/nonexistent/scene.toml"));
}

#[test]
fn an_unknown_configuration_lists_the_names() {
    let scene = Scene::from_toml(GOOD, "good.toml").expect("valid");
    let m = scene
        .configuration("goal")
        .expect_err("no goal")
        .to_string();
    assert!(m.contains("\"goal\"") && m.contains("start"), "{m}");
}

#[test]
fn a_tip_configuration_is_solved_for_its_a() {
    let rod = common::rod();
    let a = ftwire_rod::from_normalised(rod.wire(), &Vector6::new(0.5, -1.0, 1.5, -2.0, 1.0, 2.0));
    assert!(rod.is_stable(&a).expect("finite"));
    let scene = common::passage();
    let tip = scene.base * rod.tip(&a).expect("solves");
    let (t, r) = (tip.translation.vector, tip.rotation.scaled_axis());
    let text = format!(
        "[base]\nposition = [0.60, 0.35, 0.35]\nrotation = [0.0, 0.0, -1.5707963267948966]\n\
         [configuration.there]\ntip = {{ position = [{}, {}, {}], rotation = [{}, {}, {}] }}\n",
        t.x, t.y, t.z, r.x, r.y, r.z
    );
    let scene = Scene::from_toml(&text, "tip.toml").expect("valid");
    let found = scene_configuration(&scene, &rod, "there").expect("a configuration exists");
    let reached = found.base * rod.tip(&found.a).expect("solves");
    assert!((reached.translation.vector - t).norm() < 1e-6);
    assert!(reached.rotation.angle_to(&tip.rotation) < 1e-6);
    assert!(rod.is_stable(&found.a).expect("finite"));
    // An unreachable pose (3 m away from a 0.82 m wire's base) has no configuration.
    let far = ftwire_core::Pose::translation(3.0, 0.0, 0.0);
    assert!(matches!(
        configuration_for_tip(&rod, &far, "far", 0),
        Err(PlanError::NoConfigurationForTip { .. })
    ));
}
