//! A calibration trained once carries over to wires of other wrench scales: the sensor's map
//! does not depend on the wire (docs/calibration.md, "Across wrench scales").

use ftwire_estimate::calibration::{Calibration, Dataset, TrainParams};
use ftwire_lab::experiment::calibration::{rig_seed, run, train_params};
use ftwire_lab::experiment::rig::{measure, mounting, pipeline, place_wire, tare};
use ftwire_lab::experiment::{Gravity, ModelKind};
use ftwire_lab::setup::SimSetup;
use ftwire_lab::wire::WireSpec;
use ftwire_rod::Rod;
use ftwire_rod::sampling::Sampler;
use ftwire_sim::FtSensor;
use nalgebra::Vector6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// One rest on a wire: the tared raw reading (force first, sensor frame) and the true base
/// wrench (torque first, base clamp frame).
struct Rest {
    raw: Vector6<f64>,
    truth: Vector6<f64>,
}

/// `count` rests of `wire` at seeded configurations of its `A_free`, each placed anew after a
/// tare, as the calibration and shape experiments measure them.
fn rests(wire: &WireSpec, gravity: Gravity, count: usize, seed: u64) -> Vec<Rest> {
    let setup = SimSetup::default();
    let rod = Rod::new(wire.wire_params().expect("a valid wire"));
    let sampler = Sampler::default();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut out = Vec::new();
    for k in 0..count {
        let placed = sampler.sample_free(&rod, &mut rng).expect("A_free sampled");
        let config = setup.rig_config(rig_seed(seed, k));
        let Ok(mut rig) = place_wire(wire, gravity, &placed, config.clone()) else {
            continue;
        };
        let tared = pipeline(
            tare(&mut rig).expect("tared"),
            mounting(&config).expect("mounting"),
        )
        .expect("pipeline");
        let Ok(measured) = measure(&mut rig, &tared) else {
            continue;
        };
        out.push(Rest {
            raw: tared.tare().apply(&measured.raw.mean),
            truth: rig.equilibrium().base_wrench.to_vector(),
        });
    }
    out
}

/// Mean relative error of the torque and force parts of `a_of(raw)` against the truth.
fn relative(rests: &[Rest], a_of: impl Fn(&Vector6<f64>) -> Vector6<f64>) -> (f64, f64) {
    let n = rests.len().max(1) as f64;
    let part = |a: &Vector6<f64>, t: &Vector6<f64>, i: usize| {
        (a.fixed_rows::<3>(i) - t.fixed_rows::<3>(i)).norm() / t.fixed_rows::<3>(i).norm()
    };
    let (mut torque, mut force) = (0.0, 0.0);
    for rest in rests {
        let a = a_of(&rest.raw);
        torque += part(&a, &rest.truth, 0);
        force += part(&a, &rest.truth, 3);
    }
    (torque / n, force / n)
}

/// Mean relative error of the torque and force parts of `a_of(raw)` against `reference(raw)`.
fn relative_to(
    rests: &[Rest],
    a_of: impl Fn(&Vector6<f64>) -> Vector6<f64>,
    reference: impl Fn(&Vector6<f64>) -> Vector6<f64>,
) -> (f64, f64) {
    let shifted: Vec<Rest> = rests
        .iter()
        .map(|r| Rest {
            raw: r.raw,
            truth: reference(&r.raw),
        })
        .collect();
    relative(&shifted, a_of)
}

/// The parts of a calibration `F(raw) = μ_a + σ_a ⊙ (A z + c + f(z))`: the affine part alone,
/// and its value at a zero reading.
fn affine_part(calibration: &Calibration, raw: &Vector6<f64>) -> Vector6<f64> {
    let z = calibration.input_normaliser().normalise(raw);
    let y = calibration
        .affine()
        .map_or(Vector6::zeros(), |affine| affine.apply(&z));
    calibration.output_normaliser().denormalise(&y)
}

/// The unseen soft wire of docs/calibration.md (`docs/wires/soft-2mm-910.toml`): `c2/L²` ≈
/// 51 mN, a tenth of the calibration wire's.
fn soft_wire() -> WireSpec {
    WireSpec::from_toml(
        "name = \"soft-2mm-910\"\nc = [0.0315, 0.042, 0.042]\nlength = 0.91\nradius = 0.001\ndensity = 6450.0\n",
        "soft-2mm-910.toml",
    )
    .expect("soft wire")
}

/// One calibration from the experiment (240 configurations of the 3 mm / 820 mm wire, gravity
/// off) carries over to the soft wire: against the sensor's exact inverse of the same readings
/// (so that the noise of the rest and of the tare, the same for both, drops out), its error on
/// the soft wire is within twice its error on its own wire plus 0.03 % points. Measured (600
/// configurations, docs/calibration.md): 0.05 / 0.08 % on both wires, where the map with an
/// intercept and an ungated network gave 0.16 / 0.39 % on the soft wire (its intercept, a few
/// mN, is a per cent of the soft wire's smallest forces). The same data trained with that free
/// map does worse on the soft wire here too.
#[test]
fn a_calibration_carries_over_to_a_soft_wire() {
    let known = WireSpec::preset("nitinol-3mm-820").expect("preset");
    let calibration = run(
        &known,
        (Gravity::Off, ModelKind::Weightless),
        &SimSetup::default(),
        240,
        3,
        |_| {},
    )
    .expect("calibration run");
    let data = Dataset::new(
        calibration.samples.iter().map(|s| s.raw).collect(),
        calibration.samples.iter().map(|s| s.label).collect(),
    )
    .expect("dataset");
    assert_eq!(calibration.calibration.record().config, train_params());
    let free = Calibration::train(&data, &TrainParams::default(), 3).expect("free map");
    let sensor = FtSensor::new(SimSetup::default().rig_config(0).sensor, 0).expect("sensor");
    let exact = |r: &Vector6<f64>| {
        sensor
            .invert_deterministic(r, &Vector6::zeros())
            .expect("invertible")
            .to_vector()
    };
    let own = rests(&known, Gravity::Off, 20, 11);
    let soft = rests(&soft_wire(), Gravity::Off, 20, 11);
    let map = &calibration.calibration;
    let (own_t, own_f) = relative_to(&own, |r| map.apply(r), exact);
    let (soft_t, soft_f) = relative_to(&soft, |r| map.apply(r), exact);
    let (free_t, free_f) = relative_to(&soft, |r| free.apply(r), exact);
    let (truth_t, truth_f) = relative(&soft, |r| map.apply(r));
    let (floor_t, floor_f) = relative(&soft, exact);
    eprintln!(
        "against the exact inverse, torque / force %: own wire {:.3} / {:.3}, soft wire {:.3} / \
         {:.3}, soft wire with the free map {:.3} / {:.3}; against the truth on the soft wire: \
         {:.3} / {:.3} (the exact inverse {:.3} / {:.3})",
        100.0 * own_t,
        100.0 * own_f,
        100.0 * soft_t,
        100.0 * soft_f,
        100.0 * free_t,
        100.0 * free_f,
        100.0 * truth_t,
        100.0 * truth_f,
        100.0 * floor_t,
        100.0 * floor_f
    );
    assert!(
        soft_t < 2.0 * own_t + 3e-4,
        "torque: soft {soft_t}, own {own_t}"
    );
    assert!(
        soft_f < 2.0 * own_f + 3e-4,
        "force: soft {soft_f}, own {own_f}"
    );
    assert!(
        soft_t < free_t && soft_f < free_f,
        "the free map: {free_t} {free_f}"
    );
    // Against the truth, the soft wire's error is the noise floor the exact inverse has too.
    assert!(truth_t < floor_t + 1e-3 && truth_f < floor_f + 1e-3);
}

/// Where a calibration's error on a wire comes from: the whole map, the affine part alone, the
/// affine part without its value at zero, the whole map without its value at zero, and the
/// sensor's exact inverse. `FTWIRE_CAL=calibration.json FTWIRE_GRAVITY=on|off cargo test
/// --release -p ftwire-lab --test calibration_scales -- --ignored --nocapture`.
#[test]
#[ignore = "a diagnosis: reads FTWIRE_CAL"]
fn diagnose_the_carry_over() {
    let path = std::env::var("FTWIRE_CAL").expect("FTWIRE_CAL=calibration.json");
    let gravity = match std::env::var("FTWIRE_GRAVITY").as_deref() {
        Ok("off") => Gravity::Off,
        _ => Gravity::On,
    };
    let count: usize = std::env::var("FTWIRE_RESTS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(40);
    let calibration = Calibration::load(std::path::Path::new(&path)).expect("calibration");
    let sensor = FtSensor::new(SimSetup::default().rig_config(0).sensor, 0).expect("sensor");
    let zero = Vector6::zeros();
    let f0 = calibration.apply(&zero);
    let affine0 = affine_part(&calibration, &zero);
    eprintln!("F(0) = {f0:.5?}\naffine(0) = {affine0:.5?}");
    let soft = soft_wire();
    let wires = [
        WireSpec::preset("nitinol-3mm-820").expect("preset"),
        WireSpec::preset("nitinol-2mm-630").expect("preset"),
        WireSpec::preset("cable-3mm-920").expect("preset"),
        soft,
    ];
    for wire in &wires {
        let rests = rests(wire, gravity, count, 1);
        let scale = rests
            .iter()
            .map(|r| r.truth.fixed_rows::<3>(3).norm())
            .sum::<f64>()
            / rests.len().max(1) as f64;
        let mlp = rests
            .iter()
            .map(|r| (calibration.apply(&r.raw) - affine_part(&calibration, &r.raw)).norm())
            .sum::<f64>()
            / rests.len().max(1) as f64;
        let show = |what: &str, (t, f): (f64, f64)| {
            eprintln!(
                "  {what:<28} torque {:.4} %  force {:.4} %",
                100.0 * t,
                100.0 * f
            );
        };
        eprintln!(
            "{} ({} rests, mean |f| {scale:.4} N, mean |network part| {mlp:.2e}):",
            wire.name,
            rests.len()
        );
        show("calibration", relative(&rests, |r| calibration.apply(r)));
        show(
            "affine part",
            relative(&rests, |r| affine_part(&calibration, r)),
        );
        show(
            "affine part − affine(0)",
            relative(&rests, |r| affine_part(&calibration, r) - affine0),
        );
        show(
            "calibration − F(0)",
            relative(&rests, |r| calibration.apply(r) - f0),
        );
        show(
            "calibration vs exact inverse",
            relative_to(
                &rests,
                |r| calibration.apply(r),
                |r| {
                    sensor
                        .invert_deterministic(r, &zero)
                        .expect("invertible")
                        .to_vector()
                },
            ),
        );
        show(
            "exact inverse",
            relative(&rests, |r| {
                sensor
                    .invert_deterministic(r, &zero)
                    .expect("invertible")
                    .to_vector()
            }),
        );
    }
}
