//! Tests of the F/T sensor model.

use approx::assert_abs_diff_eq;
use ftwire_core::{CoreError, Wrench};
use ftwire_sim::{FtSensor, FtSensorParams, SensingError};
use nalgebra::{Vector3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn wrench(t: [f64; 3], f: [f64; 3]) -> Wrench {
    Wrench::new(Vector3::from(t), Vector3::from(f))
}

fn sensor(config: FtSensorParams, seed: u64) -> FtSensor {
    match FtSensor::new(config, seed) {
        Ok(sensor) => sensor,
        Err(e) => panic!("valid configuration rejected: {e}"),
    }
}

/// Reads until a sample arrives (dropouts are rare with the default configuration).
fn read(sensor: &mut FtSensor, w: &Wrench, time: f64) -> ftwire_core::FtSample {
    for _ in 0..100 {
        match sensor.read(w, time) {
            Ok(reading) => return reading,
            Err(SensingError::Dropout { .. }) => continue,
            Err(e) => panic!("read failed: {e}"),
        }
    }
    panic!("100 dropouts in a row");
}

fn random_wrench(rng: &mut ChaCha8Rng, torque: f64, force: f64) -> Wrench {
    let mut u = || rng.random_range(-1.0..1.0);
    wrench(
        [torque * u(), torque * u(), torque * u()],
        [force * u(), force * u(), force * u()],
    )
}

#[test]
fn ideal_sensor_returns_the_true_wrench_force_first() {
    let mut s = sensor(FtSensorParams::ideal(), 11);
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    for k in 0..200 {
        let w = random_wrench(&mut rng, 2.0, 50.0);
        let reading = read(&mut s, &w, k as f64 * 0.01);
        let expected = Vector6::new(
            w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z,
        );
        // Exactness is the claim here: every distortion is switched off.
        assert_eq!(reading.raw, expected);
        assert!(!reading.is_saturated());
    }
}

#[test]
fn an_offset_mount_turns_a_clamp_force_into_a_sensor_torque() {
    // Sensor origin 80 mm behind the clamp along sensor z, axes aligned.
    let config = FtSensorParams {
        clamp_position_in_sensor: [0.0, 0.0, 0.08],
        ..FtSensorParams::ideal()
    };
    let mut s = sensor(config, 2);
    let raw = read(&mut s, &wrench([0.0; 3], [1.0, 0.0, 0.0]), 0.0).raw;
    // τ = t × f = (0, 0, 0.08) × (1, 0, 0) = (0, 0.08, 0).
    assert_abs_diff_eq!(
        raw,
        Vector6::new(1.0, 0.0, 0.0, 0.0, 0.08, 0.0),
        epsilon = 1e-15
    );
}

#[test]
fn the_default_mount_rotates_clamp_axes_onto_sensor_axes() {
    let defaults = FtSensorParams::default();
    let config = FtSensorParams {
        clamp_position_in_sensor: defaults.clamp_position_in_sensor,
        clamp_rotation_in_sensor: defaults.clamp_rotation_in_sensor,
        ..FtSensorParams::ideal()
    };
    let rotation = config.sensor_from_clamp().rotation;
    assert_abs_diff_eq!(rotation * Vector3::x(), Vector3::z(), epsilon = 1e-15);
    assert_abs_diff_eq!(rotation * Vector3::y(), Vector3::x(), epsilon = 1e-15);
    assert_abs_diff_eq!(rotation * Vector3::z(), Vector3::y(), epsilon = 1e-15);

    let mut s = sensor(config, 3);
    // Clamp: twist 0.1 N·m about the wire, 2 N along it, 3 N along clamp y.
    let raw = read(&mut s, &wrench([0.1, 0.0, 0.0], [2.0, 3.0, 0.0]), 0.0).raw;
    // Sensor: f = (3, 0, 2); τ = (0, 0, 0.1) + (0, 0, 0.08) × (3, 0, 2) = (0, 0.24, 0.1).
    assert_abs_diff_eq!(
        raw,
        Vector6::new(3.0, 0.0, 2.0, 0.0, 0.24, 0.1),
        epsilon = 1e-14
    );
}

#[test]
fn gain_cross_talk_and_nonlinearity_act_as_specified() {
    let mut config = FtSensorParams::ideal();
    config.gain[0] = [1.01, 0.02, 0.0, 0.0, 0.0, 0.5];
    config.cubic_nonlinearity[2] = 0.004;
    let s = sensor(config, 4);
    let r = s.deterministic_response(&wrench([0.0, 0.0, 0.2], [1.0, 2.0, 400.0]));
    // f1: 1.01·1 + 0.02·2 + 0.5·0.2 = 1.15.
    assert_abs_diff_eq!(r[0], 1.15, epsilon = 1e-13);
    // f3 at 400 N of 900 N full scale: 400 (1 + 0.004 (400/900)²).
    assert_abs_diff_eq!(
        r[2],
        400.0 * (1.0 + 0.004 * (400.0_f64 / 900.0).powi(2)),
        epsilon = 1e-12
    );
    assert_abs_diff_eq!(r[1], 2.0, epsilon = 0.0);
}

#[test]
fn the_ground_truth_inverse_recovers_the_wrench() {
    // Default distortions (mount, gain, nonlinearity, bias) but no noise, drift or dropout.
    let config = FtSensorParams {
        noise_std: [0.0; 6],
        bias_random_walk: [0.0; 6],
        dropout_probability: 0.0,
        ..FtSensorParams::default()
    };
    let mut s = sensor(config, 5);
    let mut rng = ChaCha8Rng::seed_from_u64(2);
    for (k, (torque, force)) in [(0.1, 1.0), (5.0, 200.0), (6.0, 100.0)]
        .into_iter()
        .cycle()
        .take(300)
        .enumerate()
    {
        let w = random_wrench(&mut rng, torque, force);
        let reading = read(&mut s, &w, k as f64 * 1e-3);
        assert!(!reading.is_saturated());
        let back = match s.invert_deterministic(&reading.raw, &s.bias()) {
            Ok(back) => back,
            Err(e) => panic!("inverse failed: {e}"),
        };
        let scale = w.to_vector().amax().max(1.0);
        assert_abs_diff_eq!(back.to_vector(), w.to_vector(), epsilon = 1e-12 * scale);
        // And the distortions are real: the raw reading is not the wrench.
        let naive = Vector6::new(
            w.force.x, w.force.y, w.force.z, w.torque.x, w.torque.y, w.torque.z,
        );
        assert!((reading.raw - naive).amax() > 1e-3);
    }
}

#[test]
fn white_noise_has_the_configured_standard_deviation() {
    let sigma = FtSensorParams::default().noise_std;
    let config = FtSensorParams {
        noise_std: sigma,
        ..FtSensorParams::ideal()
    };
    let mut s = sensor(config, 6);
    let w = wrench([0.3, -0.2, 0.1], [1.0, 2.0, -3.0]);
    let truth = s.deterministic_response(&w);
    let n = 20_000;
    let mut sum = Vector6::zeros();
    let mut sum_sq = Vector6::zeros();
    for k in 0..n {
        let e = read(&mut s, &w, k as f64 * 1e-3).raw - truth;
        sum += e;
        sum_sq += e.component_mul(&e);
    }
    for i in 0..6 {
        let mean = sum[i] / n as f64;
        let std = (sum_sq[i] / n as f64 - mean * mean).sqrt();
        assert!(
            mean.abs() < 4.0 * sigma[i] / (n as f64).sqrt(),
            "channel {i} mean {mean}"
        );
        assert!(
            (std / sigma[i] - 1.0).abs() < 0.03,
            "channel {i}: std {std}, σ {}",
            sigma[i]
        );
    }
}

/// Bias of channel `channel` at the sample nearest `time` for `runs` independent sensors.
fn bias_samples(config: &FtSensorParams, times: &[f64], runs: u64) -> Vec<Vec<f64>> {
    let mut out = vec![Vec::new(); times.len()];
    for seed in 0..runs {
        let mut s = sensor(config.clone(), 1000 + seed);
        for (column, &t) in out.iter_mut().zip(times) {
            let reading = read(&mut s, &Wrench::default(), t);
            // With no noise, the raw reading of a zero wrench is the bias itself.
            assert_eq!(reading.raw, s.bias());
            column.push(reading.raw[0]);
        }
    }
    out
}

fn variance_about(values: &[f64], centre: f64) -> f64 {
    values.iter().map(|v| (v - centre).powi(2)).sum::<f64>() / values.len() as f64
}

#[test]
fn bias_drift_is_a_random_walk_with_variance_growing_linearly_in_time() {
    let q = 0.01;
    let b0 = 0.3;
    let config = FtSensorParams {
        initial_bias: [b0, 0.0, 0.0, 0.0, 0.0, 0.0],
        bias_random_walk: [q; 6],
        bias_time_constant: f64::INFINITY,
        ..FtSensorParams::ideal()
    };
    let times = [1.0, 4.0, 16.0];
    let samples = bias_samples(&config, &times, 2000);
    let mut variances = Vec::new();
    for (values, &t) in samples.iter().zip(&times) {
        let variance = variance_about(values, b0);
        let ratio = variance / (q * q * t);
        assert!((ratio - 1.0).abs() < 0.15, "t = {t}: var/(q² t) = {ratio}");
        variances.push(variance);
    }
    let growth = variances[2] / variances[0];
    assert!((8.0..32.0).contains(&growth), "var(16)/var(1) = {growth}");
}

#[test]
fn a_gauss_markov_bias_settles_at_its_stationary_spread() {
    let q = 0.01;
    let t_c = 1.0;
    let config = FtSensorParams {
        bias_random_walk: [q; 6],
        bias_time_constant: t_c,
        ..FtSensorParams::ideal()
    };
    let samples = bias_samples(&config, &[30.0], 2000);
    let variance = variance_about(&samples[0], 0.0);
    let ratio = variance / (q * q * t_c / 2.0);
    assert!((ratio - 1.0).abs() < 0.15, "var/(q² T/2) = {ratio}");
}

#[test]
fn saturation_clips_and_flags_only_the_channels_beyond_full_scale() {
    let config = FtSensorParams {
        saturation: true,
        ..FtSensorParams::ideal()
    };
    let mut s = sensor(config.clone(), 7);
    let reading = read(&mut s, &wrench([0.0, -25.0, 1.0], [10.0, 0.0, 1000.0]), 0.0);
    assert_eq!(reading.raw, Vector6::new(10.0, 0.0, 900.0, 0.0, -20.0, 1.0));
    assert_eq!(reading.saturated, [false, false, true, false, true, false]);
    assert!(reading.is_saturated());

    let mut unclipped = sensor(
        FtSensorParams {
            saturation: false,
            ..config
        },
        7,
    );
    let reading = read(&mut unclipped, &wrench([0.0; 3], [0.0, 0.0, 1000.0]), 0.0);
    assert_eq!(reading.raw[2], 1000.0);
    assert!(!reading.is_saturated());
}

#[test]
fn samples_fall_on_the_next_clock_tick() {
    let mut s = sensor(FtSensorParams::ideal(), 8);
    let w = Wrench::default();
    let times: Vec<f64> = [0.0, 0.0003, 0.0003, 0.0105, 0.011, 0.5]
        .iter()
        .map(|&t| read(&mut s, &w, t).time)
        .collect();
    let expected = [0.0, 0.001, 0.002, 0.011, 0.012, 0.5];
    for (t, e) in times.iter().zip(expected) {
        assert_abs_diff_eq!(*t, e, epsilon = 1e-12);
    }

    let config = FtSensorParams {
        rate: 800.0,
        clock_offset: 2e-4,
        ..FtSensorParams::ideal()
    };
    let mut s = sensor(config, 8);
    let mut previous = f64::NEG_INFINITY;
    for k in 0..2000 {
        let t = 1e-4 + k as f64 * 7.3e-4;
        let sample_time = read(&mut s, &w, t).time;
        let ticks = (sample_time - 2e-4) * 800.0;
        assert_abs_diff_eq!(ticks, ticks.round(), epsilon = 1e-6);
        assert!(sample_time >= t - 1e-12 && sample_time > previous);
        assert!(sample_time < t.max(previous) + 1.0 / 800.0 + 1e-12);
        previous = sample_time;
    }
}

#[test]
fn dropouts_happen_at_the_configured_rate_and_consume_their_tick() {
    let p = 0.05;
    let config = FtSensorParams {
        dropout_probability: p,
        ..FtSensorParams::ideal()
    };
    let mut s = sensor(config, 9);
    let n = 100_000;
    let mut dropouts = 0;
    for k in 0..n {
        let t = k as f64 * 1e-3;
        match s.read(&Wrench::default(), t) {
            Ok(reading) => assert_abs_diff_eq!(reading.time, t, epsilon = 1e-12),
            Err(SensingError::Dropout { time }) => {
                assert_abs_diff_eq!(time, t, epsilon = 1e-12);
                assert_eq!(s.last_sample_time(), Some(time));
                dropouts += 1;
            }
            Err(e) => panic!("unexpected error {e}"),
        }
    }
    let expected = p * n as f64;
    let tolerance = 4.0 * (expected * (1.0 - p)).sqrt();
    assert!(
        (dropouts as f64 - expected).abs() < tolerance,
        "{dropouts} dropouts, expected {expected} ± {tolerance}"
    );
}

#[test]
fn the_same_seed_gives_the_same_readings_and_another_seed_does_not() {
    let run = |seed| {
        let mut s = sensor(
            FtSensorParams {
                dropout_probability: 0.01,
                ..FtSensorParams::default()
            },
            seed,
        );
        (0..500)
            .map(|k| s.read(&wrench([0.01, 0.02, 0.03], [0.1, 0.2, 0.3]), k as f64 * 0.1))
            .collect::<Vec<_>>()
    };
    assert_eq!(run(1), run(1));
    assert_ne!(run(1), run(2));
}

#[test]
fn bad_configurations_are_rejected_with_the_field_named() {
    let field_of = |config: FtSensorParams| match FtSensor::new(config, 0) {
        Err(SensingError::OutOfRange { field, .. }) => field,
        Err(SensingError::TimeConstant { field, .. }) => field,
        Err(SensingError::Core(CoreError::NonFinite { field, .. })) => field,
        Err(SensingError::Core(CoreError::RotationTooLarge { field, .. })) => field,
        Err(SensingError::SingularGain { .. }) => "gain (singular)",
        other => panic!("expected an error, got {other:?}"),
    };
    let d = FtSensorParams::default;
    let mut singular = d();
    singular.gain[3] = [0.0; 6];
    let mut nan_gain = d();
    nan_gain.gain[1][4] = f64::NAN;
    let cases = [
        (
            FtSensorParams {
                clamp_position_in_sensor: [0.0, f64::NAN, 0.0],
                ..d()
            },
            "clamp_position_in_sensor",
        ),
        (
            FtSensorParams {
                clamp_rotation_in_sensor: [f64::INFINITY, 0.0, 0.0],
                ..d()
            },
            "clamp_rotation_in_sensor",
        ),
        (
            FtSensorParams {
                clamp_rotation_in_sensor: [0.0, 1e300, 0.0],
                ..d()
            },
            "clamp_rotation_in_sensor",
        ),
        (nan_gain, "gain"),
        (singular, "gain (singular)"),
        (
            FtSensorParams {
                cubic_nonlinearity: [0.0, 0.0, 0.2, 0.0, 0.0, 0.0],
                ..d()
            },
            "cubic_nonlinearity",
        ),
        (
            FtSensorParams {
                full_scale: [500.0, 0.0, 900.0, 20.0, 20.0, 20.0],
                ..d()
            },
            "full_scale",
        ),
        (
            FtSensorParams {
                initial_bias: [0.0, 0.0, 0.0, f64::NAN, 0.0, 0.0],
                ..d()
            },
            "initial_bias",
        ),
        (
            FtSensorParams {
                bias_random_walk: [-1e-3; 6],
                ..d()
            },
            "bias_random_walk",
        ),
        (
            FtSensorParams {
                bias_time_constant: 0.0,
                ..d()
            },
            "bias_time_constant",
        ),
        (
            FtSensorParams {
                noise_std: [0.05, 0.05, -0.05, 0.0, 0.0, 0.0],
                ..d()
            },
            "noise_std",
        ),
        (
            FtSensorParams {
                bias_time_constant: 1e300,
                ..d()
            },
            "bias_time_constant",
        ),
        (
            FtSensorParams {
                rate: f64::INFINITY,
                ..d()
            },
            "rate",
        ),
        (FtSensorParams { rate: 1e300, ..d() }, "rate"),
        (
            FtSensorParams {
                rate: 1e-300,
                ..d()
            },
            "rate",
        ),
        (
            FtSensorParams {
                clock_offset: -1e300,
                ..d()
            },
            "clock_offset",
        ),
        (
            FtSensorParams {
                clock_offset: f64::NAN,
                ..d()
            },
            "clock_offset",
        ),
        (
            FtSensorParams {
                dropout_probability: 1.0,
                ..d()
            },
            "dropout_probability",
        ),
    ];
    for (config, field) in cases {
        assert_eq!(field_of(config), field);
    }
}

#[test]
fn bad_reads_and_inverses_give_errors_not_panics() {
    let mut s = sensor(FtSensorParams::default(), 10);
    let nan = wrench([0.0, f64::NAN, 0.0], [0.0; 3]);
    assert!(matches!(
        s.read(&nan, 0.0),
        Err(SensingError::Core(CoreError::NonFinite {
            field: "wrench",
            index: 1,
            ..
        }))
    ));
    assert!(matches!(
        s.read(&Wrench::default(), f64::INFINITY),
        Err(SensingError::Core(CoreError::NonFinite {
            field: "time",
            ..
        }))
    ));
    let raw_nan = Vector6::new(0.0, 0.0, 0.0, 0.0, 0.0, f64::NAN);
    assert!(s.invert_deterministic(&raw_nan, &Vector6::zeros()).is_err());
    // Times beyond the clock's range are refused rather than mis-stamped.
    assert!(matches!(
        s.read(&Wrench::default(), 1e300),
        Err(SensingError::OutOfRange { field: "time", .. })
    ));
    assert!(matches!(
        s.read(&Wrench::default(), -1e300),
        Err(SensingError::OutOfRange { field: "time", .. })
    ));
    assert_abs_diff_eq!(
        read(&mut s, &Wrench::default(), 1e6).time,
        1e6,
        epsilon = 0.01
    );

    // A softening nonlinearity has no inverse beyond its monotone range.
    let mut config = FtSensorParams::ideal();
    config.cubic_nonlinearity[0] = -0.1;
    config.full_scale[0] = 1.0;
    let soft = sensor(config, 10);
    let beyond = Vector6::new(2.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    assert!(matches!(
        soft.invert_deterministic(&beyond, &Vector6::zeros()),
        Err(SensingError::NotInvertible { channel: 0, .. })
    ));
    let within = Vector6::new(0.9, 0.0, 0.0, 0.0, 0.0, 0.0);
    assert!(
        soft.invert_deterministic(&within, &Vector6::zeros())
            .is_ok()
    );
}

#[test]
fn the_configuration_round_trips_through_toml() {
    for config in [
        FtSensorParams::default(),
        FtSensorParams::ideal(),
        FtSensorParams {
            bias_time_constant: f64::INFINITY,
            ..FtSensorParams::default()
        },
    ] {
        let text = match toml::to_string(&config) {
            Ok(text) => text,
            Err(e) => panic!("serialise: {e}"),
        };
        let back: FtSensorParams = match toml::from_str(&text) {
            Ok(back) => back,
            Err(e) => panic!("deserialise: {e}\n{text}"),
        };
        assert_eq!(back, config);
    }
    assert!(toml::from_str::<FtSensorParams>("noise = 1.0").is_err());
}

#[test]
fn a_deterministic_drift_adds_its_rate_times_time() {
    let mut config = FtSensorParams::ideal();
    config.initial_bias = [1.0, 0.0, 0.0, -0.25, 0.0, 0.0];
    config.bias_drift_rate = [0.0, 2e-3, 0.0, -1e-4, 0.0, 0.0];
    let mut s = sensor(config, 9);
    let zero = wrench([0.0; 3], [0.0; 3]);
    for t in [0.0, 10.0, 1400.0] {
        let reading = read(&mut s, &zero, t);
        let expected = [1.0, 2e-3 * t, 0.0, -0.25 - 1e-4 * t, 0.0, 0.0];
        for (i, e) in expected.iter().enumerate() {
            assert_abs_diff_eq!(reading.raw[i], e, epsilon = 1e-9);
            assert_abs_diff_eq!(s.bias()[i], e, epsilon = 1e-9);
        }
    }
    let bad = FtSensorParams {
        bias_drift_rate: [0.0, f64::NAN, 0.0, 0.0, 0.0, 0.0],
        ..FtSensorParams::default()
    };
    assert!(FtSensor::new(bad, 0).is_err());
}

/// Hysteresis is a play operator on each channel: a load reached from below reads up to `h`
/// low, from above up to `h` high, the same load in between reads where it was left, and
/// the state carries over to another sensor.
#[test]
fn hysteresis_reads_by_the_load_history_and_carries_over() -> Result<(), SensingError> {
    let mut config = FtSensorParams::ideal();
    config.hysteresis = [0.1, 0.0, 0.0, 0.0, 0.0, 0.0];
    let mut sensor = FtSensor::new(config.clone(), 1)?;
    let force = |f: f64| Wrench::new(Vector3::zeros(), Vector3::new(f, 0.0, 0.0));
    // The ideal sensor maps the clamp's x force to raw channel 0.
    let reading = |s: &mut FtSensor, f: f64, t: f64| s.read(&force(f), t).map(|r| r.raw[0]);
    assert_eq!(reading(&mut sensor, 0.0, 0.0)?, 0.0);
    let up = reading(&mut sensor, 1.0, 0.01)?;
    assert!((up - 0.9).abs() < 1e-12, "{up}");
    let held = reading(&mut sensor, 0.95, 0.02)?;
    assert!((held - 0.9).abs() < 1e-12, "{held}");
    let down = reading(&mut sensor, 0.0, 0.03)?;
    assert!((down - 0.1).abs() < 1e-12, "{down}");
    let state = sensor.hysteresis_state();
    let mut next = FtSensor::new(config.clone(), 2)?;
    next.set_hysteresis_state(state)?;
    assert!((reading(&mut next, 0.0, 0.0)? - 0.1).abs() < 1e-12);
    assert!(
        next.set_hysteresis_state(Some(Vector6::repeat(f64::NAN)))
            .is_err()
    );
    // Beyond 1 % of full scale is refused, naming the key.
    config.hysteresis[0] = 0.02 * config.full_scale[0];
    let e = FtSensor::new(config, 1)
        .map(|_| ())
        .expect_err("refused")
        .to_string();
    assert!(e.contains("hysteresis"), "{e}");
    Ok(())
}
