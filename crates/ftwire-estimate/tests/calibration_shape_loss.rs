//! The map fitted on the shape (`calibration::shape_loss`): from labels that are off in a
//! direction the shape barely shows, the fit on the markers' distance finds a map whose
//! shapes meet the markers, on records it was not fitted on too; a gross outlier does not
//! steer it (Huber's loss); bad settings are refused by name.

use ftwire_core::WireParams;
use ftwire_estimate::calibration::shape_loss::{ShapeLossParams, ShapeSample, fit_on_shape};
use ftwire_estimate::{KirchhoffModel, WireModel};
use nalgebra::{Matrix6, Point3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

fn model() -> KirchhoffModel {
    KirchhoffModel::new(WireParams::new([0.042, 0.055, 0.055], 0.63, 0.001).expect("a wire"))
}

/// A sensor that reads `raw = G a + o` (force first): the map to learn is affine.
fn sensor() -> (Matrix6<f64>, Vector6<f64>) {
    let mut g = Matrix6::zeros();
    for i in 0..3 {
        g[(i, i + 3)] = 1.0 + 0.05 * i as f64; // force channels from a's force part
        g[(i + 3, i)] = 10.0 - i as f64; // torque channels from a's torque part
    }
    g[(0, 4)] = 0.03;
    (g, Vector6::new(1.8, -1.3, 0.5, 0.2, -0.1, 0.05))
}

/// Records at stable configurations near a bent shape, with markers on the model's shape.
fn records(count: usize, seed: u64) -> Vec<(ShapeSample, Vector6<f64>)> {
    let model = model();
    let (g, o) = sensor();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let base = Vector6::new(0.0, 0.08, 0.02, -0.15, 0.05, 0.0);
    let mut out = Vec::new();
    while out.len() < count {
        let a = base
            + Vector6::from_fn(|i, _| {
                rng.random_range(-1.0..1.0) * if i < 3 { 0.02 } else { 0.05 }
            });
        let Ok(shape) = model.shape(&a, 11) else {
            continue;
        };
        let markers: Vec<Point3<f64>> = shape.positions[1..]
            .iter()
            .map(|p| Point3::from(*p))
            .collect();
        out.push((
            ShapeSample {
                raw: g * a + o,
                offset: Vector6::zeros(),
                markers,
                fractions: None,
            },
            a,
        ));
    }
    out
}

#[test]
fn the_shape_fit_meets_the_markers_from_labels_that_miss_them()
-> Result<(), Box<dyn std::error::Error>> {
    let model = model();
    let train = records(40, 1);
    let validation: Vec<ShapeSample> = records(12, 2).into_iter().map(|(s, _)| s).collect();
    // Labels off by a bias in the force along the wire, which the shape barely shows, and
    // by a torque bias, which it does.
    let labels: Vec<Vector6<f64>> = train
        .iter()
        .map(|(_, a)| a + Vector6::new(0.0, 0.004, -0.003, 0.05, 0.0, 0.0))
        .collect();
    let samples: Vec<ShapeSample> = train.iter().map(|(s, _)| s.clone()).collect();
    let params = ShapeLossParams {
        degrees: vec![2],
        ridges: vec![1.0],
        label_weight: 0.0,
        ..ShapeLossParams::default()
    };
    let fitted = fit_on_shape(&model, &samples, &labels, &validation, &params)?;
    let affine = &fitted.candidates[0];
    assert_eq!(fitted.candidates.len(), 2);
    assert!(affine.validation_marker_mean < 2e-4, "{affine:?}");
    assert!(affine.train_marker_mean < 2e-4, "{affine:?}");
    // The labels' own map is millimetres off at the markers.
    let start = {
        let mut p = params.clone();
        p.max_iterations = 1;
        p.degrees.clear();
        fit_on_shape(&model, &samples, &labels, &validation, &p)?
    };
    assert!(start.candidates[0].validation_marker_mean > affine.validation_marker_mean);
    // The chosen map applied as every consumer applies it.
    let back =
        ftwire_estimate::calibration::Calibration::from_json(&fitted.calibration.to_json()?)?;
    for s in &validation {
        assert_eq!(back.apply(&s.raw), fitted.calibration.apply(&s.raw));
    }
    Ok(())
}

#[test]
fn a_gross_outlier_does_not_steer_the_fit() -> Result<(), Box<dyn std::error::Error>> {
    let model = model();
    let train = records(40, 3);
    let validation: Vec<ShapeSample> = records(12, 4).into_iter().map(|(s, _)| s).collect();
    let labels: Vec<Vector6<f64>> = train.iter().map(|(_, a)| *a).collect();
    let mut samples: Vec<ShapeSample> = train.iter().map(|(s, _)| s.clone()).collect();
    // One record's markers 50 mm off (a swapped marker set).
    for m in &mut samples[7].markers {
        m.y += 0.05;
    }
    let params = ShapeLossParams {
        degrees: Vec::new(),
        label_weight: 0.0,
        ..ShapeLossParams::default()
    };
    let fitted = fit_on_shape(&model, &samples, &labels, &validation, &params)?;
    assert!(fitted.huber < 5e-3, "{}", fitted.huber);
    let c = &fitted.candidates[0];
    assert!(c.validation_marker_mean < 1e-3, "{c:?}");
    Ok(())
}

#[test]
fn bad_settings_are_refused_by_name() {
    let model = model();
    let train = records(5, 5);
    let samples: Vec<ShapeSample> = train.iter().map(|(s, _)| s.clone()).collect();
    let labels: Vec<Vector6<f64>> = train.iter().map(|(_, a)| *a).collect();
    for (params, name) in [
        (
            ShapeLossParams {
                degrees: vec![4],
                ..ShapeLossParams::default()
            },
            "degrees",
        ),
        (
            ShapeLossParams {
                ridges: vec![f64::NAN],
                ..ShapeLossParams::default()
            },
            "ridges",
        ),
        (
            ShapeLossParams {
                label_weight: -1.0,
                ..ShapeLossParams::default()
            },
            "label_weight",
        ),
        (
            ShapeLossParams {
                huber: Some(0.0),
                ..ShapeLossParams::default()
            },
            "huber",
        ),
    ] {
        let e = fit_on_shape(&model, &samples, &labels, &samples, &params)
            .map(|_| ())
            .expect_err("refused")
            .to_string();
        assert!(e.contains(name), "{e}");
    }
    let e = fit_on_shape(
        &model,
        &samples,
        &labels[..2],
        &samples,
        &ShapeLossParams::default(),
    )
    .map(|_| ())
    .expect_err("refused")
    .to_string();
    assert!(e.contains("labels"), "{e}");
}

/// With the markers' arc lengths known, the fit takes each marker at its own arc length and
/// meets held-out markers as well.
#[test]
fn the_shape_fit_at_known_arc_lengths_meets_the_markers() -> Result<(), Box<dyn std::error::Error>>
{
    let model = model();
    let with_fractions = |records: Vec<(ShapeSample, Vector6<f64>)>| {
        records
            .into_iter()
            .map(|(mut s, a)| {
                s.fractions = Some((1..=s.markers.len()).map(|k| k as f64 / 10.0).collect());
                (s, a)
            })
            .collect::<Vec<_>>()
    };
    let train = with_fractions(records(30, 6));
    let validation: Vec<ShapeSample> = with_fractions(records(10, 7))
        .into_iter()
        .map(|(s, _)| s)
        .collect();
    let labels: Vec<Vector6<f64>> = train
        .iter()
        .map(|(_, a)| a + Vector6::new(0.0, 0.004, -0.003, 0.05, 0.0, 0.0))
        .collect();
    let samples: Vec<ShapeSample> = train.iter().map(|(s, _)| s.clone()).collect();
    let params = ShapeLossParams {
        degrees: Vec::new(),
        label_weight: 0.0,
        ..ShapeLossParams::default()
    };
    let fitted = fit_on_shape(&model, &samples, &labels, &validation, &params)?;
    let c = &fitted.candidates[0];
    assert!(c.validation_marker_mean < 2e-4, "{c:?}");
    // The shared metric judges the chosen map as the fit judged it.
    let (mean, failures) = ftwire_estimate::calibration::shape_loss::marker_mean(
        &model,
        &fitted.calibration,
        &validation,
        params.nodes,
    )?;
    assert_eq!(failures, 0);
    assert!(
        (mean - c.validation_marker_mean).abs() < 1e-9,
        "{mean} {c:?}"
    );
    Ok(())
}
