//! Unit tests of the parent module.

use super::*;
use ftwire_core::WireParams;
use ftwire_rod::from_normalised;

fn pose(x: f64, angle: f64) -> Pose {
    Pose::from_parts(
        Translation3::new(x, 0.2, 0.0),
        UnitQuaternion::from_scaled_axis(Vector3::new(0.0, 0.0, angle)),
    )
}

fn sample(time: f64, value: f64) -> FtSample {
    FtSample {
        time,
        raw: Vector6::repeat(value),
        saturated: [false; 6],
    }
}

/// Poses at 100 Hz and samples at 1 kHz from `t0` for `seconds`, the samples worth `value`.
fn feed(rests: &mut RestDetector, t0: f64, seconds: f64, at: &Pose, value: f64) -> Vec<RestWindow> {
    let mut found = Vec::new();
    for k in 0..(seconds * 1000.0).round() as usize {
        let t = t0 + k as f64 * 1e-3;
        found.extend(rests.sample(sample(t, value)));
        if k % 10 == 0 {
            found.extend(rests.pose(t, at));
        }
    }
    found
}

#[test]
fn a_still_period_gives_one_rest_after_its_dwell_without_its_settle() {
    let params = RestParams::default();
    let mut rests = RestDetector::new(params);
    let found = feed(&mut rests, 0.0, 2.0, &pose(0.5, 0.0), 1.0);
    assert_eq!(found.len(), 1, "one rest per still period");
    let rest = &found[0];
    assert!((rest.end - params.dwell).abs() < 1e-9, "{}", rest.end);
    let first = rest.samples.first().map_or(f64::NAN, |s| s.time);
    assert!((first - params.settle).abs() < 1e-9, "{first}");
    // Samples from the settle to the dwell, both included, at 1 kHz.
    assert_eq!(rest.samples.len(), 401);
    assert!((rest.tip.translation.vector.x - 0.5).abs() < 1e-12);
}

#[test]
fn a_move_starts_a_new_rest_and_jitter_within_the_tolerance_does_not() {
    let params = RestParams::default();
    let mut rests = RestDetector::new(params);
    assert_eq!(feed(&mut rests, 0.0, 0.3, &pose(0.5, 0.0), 1.0).len(), 0);
    // 0.5 mm and 0.5° of jitter: still.
    let mut found = Vec::new();
    for (i, k) in (300..1000).step_by(10).enumerate() {
        let t = k as f64 * 1e-3;
        let sign = if i % 2 == 0 { 1.0 } else { -1.0 };
        for j in 0..10 {
            found.extend(rests.sample(sample(t + j as f64 * 1e-3, 1.0)));
        }
        found.extend(rests.pose(t, &pose(0.5 + sign * 5e-4, sign * 0.5f64.to_radians())));
    }
    assert_eq!(found.len(), 1);
    // The mean pose of the jitter is the pose it jitters about.
    assert!((found[0].tip.translation.vector.x - 0.5).abs() < 1e-4);
    assert!(found[0].tip.rotation.angle() < 1e-2);
    // A move of 2 mm: a new still period, whose rest averages only its own samples.
    let moved = feed(&mut rests, 1.0, 1.0, &pose(0.502, 0.0), 3.0);
    assert_eq!(moved.len(), 1);
    assert!((moved[0].start - 1.0).abs() < 1e-9);
    assert!(moved[0].samples.iter().all(|s| s.raw[0] == 3.0));
    // A turn of 2° is a move too.
    let turned = feed(&mut rests, 2.0, 0.6, &pose(0.502, 2f64.to_radians()), 5.0);
    assert_eq!(turned.len(), 1);
    assert!((turned[0].start - 2.0).abs() < 1e-9);
}

#[test]
fn a_still_period_from_before_the_tare_rests_once_its_samples_span_the_dwell() {
    let params = RestParams::default();
    let mut rests = RestDetector::new(params);
    // Poses from 0 s, samples (after the tare) from 0.5 s.
    let mut found = Vec::new();
    for k in 0..2000 {
        let t = k as f64 * 1e-3;
        if t >= 0.5 {
            found.extend(rests.sample(sample(t, 1.0)));
        }
        if k % 10 == 0 {
            found.extend(rests.pose(t, &pose(0.5, 0.0)));
        }
    }
    assert_eq!(found.len(), 1);
    assert!((found[0].end - 0.9).abs() < 1e-9, "{}", found[0].end);
    assert_eq!(found[0].samples.len(), 401);
}

#[test]
fn a_still_period_shorter_than_the_dwell_or_without_samples_is_no_rest() {
    let mut rests = RestDetector::new(RestParams::default());
    let mut found = Vec::new();
    for i in 0..10 {
        // Moves every 0.4 s: never a dwell of 0.5 s.
        found.extend(feed(
            &mut rests,
            0.4 * i as f64,
            0.4,
            &pose(0.5 + 0.01 * i as f64, 0.0),
            1.0,
        ));
    }
    assert!(found.is_empty());
    // Poses alone, no F/T samples.
    let mut quiet = RestDetector::new(RestParams::default());
    let none: Vec<RestWindow> = (0..200)
        .flat_map(|k| quiet.pose(k as f64 * 0.01, &pose(0.5, 0.0)))
        .collect();
    assert!(none.is_empty());
}

/// A rest is defined by the stamps: the same stamped poses and samples give the same rests,
/// with the same samples, whether the samples arrive before their poses, after them, or
/// interleaved (each stream in its own order).
#[test]
fn rests_do_not_depend_on_the_order_the_streams_arrive_in() {
    // Two still periods, 1.2 s each, samples at 1 kHz worth their time, poses at 100 Hz.
    let samples: Vec<FtSample> = (0..2400)
        .map(|k| sample(k as f64 * 1e-3, k as f64))
        .collect();
    let poses: Vec<(f64, Pose)> = (0..240)
        .map(|k| {
            let t = k as f64 * 1e-2;
            (t, pose(if t < 1.2 { 0.5 } else { 0.51 }, 0.0))
        })
        .collect();
    enum Event<'a> {
        Sample(&'a FtSample),
        Pose(&'a (f64, Pose)),
    }
    let run = |events: Vec<Event<'_>>| -> Vec<(f64, f64, usize, f64)> {
        let mut rests = RestDetector::new(RestParams::default());
        let mut found = Vec::new();
        for event in events {
            found.extend(match event {
                Event::Sample(s) => rests.sample(*s),
                Event::Pose((t, p)) => rests.pose(*t, p),
            });
        }
        found
            .iter()
            .map(|w| {
                let sum: f64 = w.samples.iter().map(|s| s.raw[0]).sum();
                (w.start, w.end, w.samples.len(), sum)
            })
            .collect()
    };
    // Interleaved by stamp; poses late by 40 ms (samples first); samples late by 40 ms.
    let by_stamp = |pose_lag: f64, sample_lag: f64| {
        let mut events: Vec<(f64, Event<'_>)> = samples
            .iter()
            .map(|s| (s.time + sample_lag, Event::Sample(s)))
            .chain(poses.iter().map(|p| (p.0 + pose_lag, Event::Pose(p))))
            .collect();
        events.sort_by(|a, b| a.0.total_cmp(&b.0));
        events.into_iter().map(|(_, e)| e).collect::<Vec<_>>()
    };
    let reference = run(by_stamp(0.0, 0.0));
    assert_eq!(reference.len(), 2, "{reference:?}");
    assert_eq!(reference[0].2, 401, "{reference:?}");
    for (pose_lag, sample_lag) in [(0.04, 0.0), (0.0, 0.04), (0.0005, 0.0)] {
        assert_eq!(
            run(by_stamp(pose_lag, sample_lag)),
            reference,
            "poses late by {pose_lag} s, samples by {sample_lag} s"
        );
    }
}

#[test]
fn rest_settings_are_checked() {
    assert!(RestParams::default().validate().is_ok());
    for bad in [
        RestParams {
            position_tolerance: 0.0,
            ..RestParams::default()
        },
        RestParams {
            angle_tolerance: f64::NAN,
            ..RestParams::default()
        },
        RestParams {
            dwell: 0.0,
            ..RestParams::default()
        },
        RestParams {
            settle: 0.5,
            ..RestParams::default()
        },
    ] {
        assert!(bad.validate().is_err(), "{bad:?}");
    }
    let few = ObserveParams {
        calibration_moves: 3,
        ..ObserveParams::default()
    };
    assert!(few.validate().is_err());
}

fn wire() -> WireParams {
    WireParams::new([0.214, 0.278, 0.278], 0.82, 0.0015).expect("valid wire")
}

/// Rests of the model's wire at configurations along a motion, read with `bias` added.
fn rests_along(bias: &Vector6<f64>, n: usize) -> Vec<RestSample> {
    let model = KirchhoffModel::new(wire());
    (0..n)
        .map(|i| {
            let s = i as f64 / n as f64;
            let a = from_normalised(
                &wire(),
                &Vector6::new(0.3 * s, 1.0 - s, 0.5, -1.0 + 0.8 * s, 0.5 - s, 0.2 * s),
            );
            RestSample {
                time: i as f64,
                a: a + bias,
                a_std: Vector6::new(1e-5, 1e-5, 1e-5, 1e-3, 1e-3, 1e-3),
                tip: model.tip(&a).expect("solves"),
                samples: 400,
            }
        })
        .collect()
}

#[test]
fn the_bias_estimate_moves_to_a_constant_bias_and_free_moves_arm_the_detector() {
    let model = KirchhoffModel::new(wire());
    // A bias of a few of the observer's prior σ, for a robot that reports where its
    // gripper is: the node's settings for the default sensor.
    let bias = Vector6::new(1e-4, 0.0, -1e-4, 0.01, -0.008, 0.006);
    let params = ObserveParams {
        bias_observer: BiasObserverParams::for_sensor(
            &ftwire_app::config::sensor::DEFAULT,
            500,
            ftwire_control::NoiseModel::None,
            &ftwire_control::NoiseParams::default(),
        ),
        ..ObserveParams::default()
    };
    let mut observer = Observer::new(model, &params).expect("valid");
    let mut calibrated = false;
    for rest in rests_along(&bias, 14) {
        for event in observer.rest(rest) {
            calibrated |= matches!(event, RestEvent::Calibrated(_));
            if let RestEvent::Rest { contact, .. } = event {
                assert!(!contact, "free moves");
            }
        }
    }
    assert!(calibrated);
    assert_eq!(observer.count, 14);
    let estimate = Vector6::from(observer.bias().expect("an observer"));
    assert!(
        (estimate - bias).norm() < 0.5 * bias.norm(),
        "{estimate} vs {bias}"
    );
    let a = Vector6::new(0.0, 0.1, 0.0, -0.2, 0.1, 0.0);
    assert!((observer.correct(&a) - (a - estimate)).norm() < 1e-15);
    // A force the model does not have, growing over the next moves: a contact.
    let mut contact = false;
    let more = rests_along(&Vector6::zeros(), 20);
    for (i, mut rest) in more.into_iter().skip(14).enumerate() {
        rest.a += bias + Vector6::new(0.0, 0.0, 0.0, 0.0, 0.05 * (i + 1) as f64, 0.0);
        rest.time += 14.0;
        for event in observer.rest(rest) {
            if let RestEvent::Rest { contact: c, .. } = event {
                contact |= c;
            }
        }
    }
    assert!(contact);
    assert!(observer.contact_moves > 0);
    assert!(observer.residual().is_some_and(|(_, c)| c));
}
