//! Shape fitting from markers (paper eq. 15): the marker Jacobian against central differences,
//! and recovery of known configurations from markers on the model's own centreline (gravity
//! off), with and without 0.3 mm noise and dropouts, over several seeds.

use ftwire_core::WireParams;
use ftwire_estimate::shape::{
    Correspondence, FitParams, GlobalSearch, Markers, MultiStart, ShapeFit, ShapeFitter,
    SwarmSearch, centreline_distance, centreline_point, evenly_spaced_fractions,
};
use ftwire_estimate::{EstimateError, KirchhoffModel, WireModel};
use ftwire_rod::sampling::Sampler;
use ftwire_rod::{from_normalised, to_normalised};
use nalgebra::{Point3, Vector3, Vector6};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::StandardNormal;

fn two_mm() -> Result<KirchhoffModel, EstimateError> {
    Ok(KirchhoffModel::new(WireParams::new(
        [0.042, 0.055, 0.055],
        0.63,
        0.001,
    )?))
}

fn three_mm() -> Result<KirchhoffModel, EstimateError> {
    Ok(KirchhoffModel::new(WireParams::new(
        [0.214, 0.278, 0.278],
        0.82,
        0.0015,
    )?))
}

#[test]
fn marker_jacobian_matches_central_differences() -> Result<(), EstimateError> {
    for (model, seed) in [(two_mm()?, 11), (three_mm()?, 12)] {
        let wire = *model.wire();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let sampler = Sampler::new(10.0)?;
        for _ in 0..8 {
            let a = sampler.sample_a(model.rod(), &mut rng);
            let s = rng.random_range(0.05..=1.0) * wire.length();
            let point = centreline_point(&model, &a, s, true)?;
            // Central differences in normalised units (step 1e-6 of c2/L, c2/L²).
            let z = to_normalised(&wire, &a);
            let scales = from_normalised(&wire, &Vector6::repeat(1.0));
            let h = 1e-6;
            for i in 0..6 {
                let mut plus = z;
                let mut minus = z;
                plus[i] += h;
                minus[i] -= h;
                let p = centreline_point(&model, &from_normalised(&wire, &plus), s, false)?;
                let m = centreline_point(&model, &from_normalised(&wire, &minus), s, false)?;
                let fd: Vector3<f64> = (p.position - m.position) / (2.0 * h);
                let analytic: Vector3<f64> = point.jacobian.column(i) * scales[i];
                let scale = point.jacobian.norm() * scales.amax() + 1e-9;
                assert!(
                    (fd - analytic).norm() <= 1e-6 * scale,
                    "column {i} at s = {s}, a = {a:?}: fd {fd:?} vs analytic {analytic:?}"
                );
            }
        }
    }
    Ok(())
}

/// Markers at 0, 0.1 L, …, L on the model's true centreline, with noise σ per axis \[m\] and
/// `dropouts` markers removed at random.
fn markers_of(
    model: &KirchhoffModel,
    truth: &Vector6<f64>,
    sigma: f64,
    dropouts: usize,
    rng: &mut ChaCha8Rng,
) -> Result<Markers, EstimateError> {
    let shape = model.shape(truth, 11)?;
    let mut positions: Vec<Option<Point3<f64>>> = shape
        .positions
        .iter()
        .map(|p| {
            let noise = Vector3::from_fn(|_, _| sigma * rng.sample::<f64, _>(StandardNormal));
            Some(Point3::from(p + noise))
        })
        .collect();
    let mut dropped = 0;
    while dropped < dropouts {
        let k = rng.random_range(0..positions.len());
        if let Some(slot) = positions.get_mut(k).filter(|slot| slot.is_some()) {
            *slot = None;
            dropped += 1;
        }
    }
    Markers::new(&evenly_spaced_fractions(11), &positions)
}

/// Errors of one fit: relative error of `a` in normalised units, mean shape error \[m\].
fn errors(
    model: &KirchhoffModel,
    truth: &Vector6<f64>,
    fit: &ShapeFit,
) -> Result<(f64, f64), EstimateError> {
    let wire = model.wire();
    let z_true = to_normalised(wire, truth);
    let relative = (to_normalised(wire, &fit.a) - z_true).norm() / z_true.norm();
    let fitted = model.shape(&fit.a, 100)?;
    let true_shape = model.shape(truth, 100)?;
    let shape = centreline_distance(&fitted.positions, &true_shape.positions, 100)?;
    Ok((relative, shape))
}

struct Summary {
    relative: Vec<f64>,
    shape: Vec<f64>,
    rms: Vec<f64>,
}

fn run(
    model: &KirchhoffModel,
    config: FitParams,
    seeds: &[u64],
    per_seed: usize,
    sigma: f64,
    max_dropouts: usize,
) -> Result<Summary, EstimateError> {
    run_with(
        model,
        config,
        MultiStart::default(),
        seeds,
        per_seed,
        sigma,
        max_dropouts,
    )
}

fn run_with<G: GlobalSearch>(
    model: &KirchhoffModel,
    config: FitParams,
    global: G,
    seeds: &[u64],
    per_seed: usize,
    sigma: f64,
    max_dropouts: usize,
) -> Result<Summary, EstimateError> {
    let fitter = ShapeFitter::new(*model)
        .with_config(config)?
        .with_global(global);
    let sampler = Sampler::new(10.0)?;
    let mut summary = Summary {
        relative: Vec::new(),
        shape: Vec::new(),
        rms: Vec::new(),
    };
    for &seed in seeds {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        for _ in 0..per_seed {
            let truth = sampler.sample_stable(model.rod(), &mut rng)?;
            let dropouts = rng.random_range(0..=max_dropouts);
            let markers = markers_of(model, &truth, sigma, dropouts, &mut rng)?;
            let fit = fitter.fit(&markers, &mut rng)?;
            let (relative, shape) = errors(model, &truth, &fit)?;
            eprintln!(
                "seed {seed}: rel {relative:.2e} shape {:.3} mm rms {:.3} mm trusted {} starts {} iters {} {:?}",
                shape * 1e3,
                fit.rms * 1e3,
                fit.trusted,
                fit.starts,
                fit.iterations,
                fit.termination
            );
            summary.relative.push(relative);
            summary.shape.push(shape);
            summary.rms.push(fit.rms);
        }
    }
    Ok(summary)
}

fn max(values: &[f64]) -> f64 {
    values.iter().copied().fold(0.0, f64::max)
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len().max(1) as f64
}

#[test]
fn exact_markers_recover_a_and_the_shape() -> Result<(), EstimateError> {
    let summary = run(&two_mm()?, FitParams::default(), &[1, 2, 3], 6, 0.0, 0)?;
    eprintln!(
        "exact: rel max {:.2e} mean {:.2e}; shape max {:.2e} mm",
        max(&summary.relative),
        mean(&summary.relative),
        max(&summary.shape) * 1e3
    );
    assert!(max(&summary.relative) < 1e-4, "{:?}", summary.relative);
    assert!(max(&summary.shape) < 1e-5, "{:?}", summary.shape);
    Ok(())
}

#[test]
fn noisy_markers_with_dropouts_recover_the_shape() -> Result<(), EstimateError> {
    for (model, seeds) in [(two_mm()?, [4, 5, 6]), (three_mm()?, [7, 8, 9])] {
        let summary = run(&model, FitParams::default(), &seeds, 6, 3e-4, 2)?;
        eprintln!(
            "noisy L = {}: rel max {:.2e} mean {:.2e}; shape max {:.3} mm mean {:.3} mm; rms max {:.3} mm",
            model.wire().length(),
            max(&summary.relative),
            mean(&summary.relative),
            max(&summary.shape) * 1e3,
            mean(&summary.shape) * 1e3,
            max(&summary.rms) * 1e3
        );
        assert!(max(&summary.shape) < 0.5e-3, "{:?}", summary.shape);
        // The shape pins a down only up to the noise: a few percent of |a|.
        assert!(max(&summary.relative) < 0.2, "{:?}", summary.relative);
        assert!(mean(&summary.shape) < 0.25e-3, "{:?}", summary.shape);
        assert!(max(&summary.rms) < 1e-3, "{:?}", summary.rms);
    }
    Ok(())
}

#[test]
fn closest_point_correspondence_recovers_the_shape() -> Result<(), EstimateError> {
    let config = FitParams {
        correspondence: Correspondence::ClosestPoint,
        ..FitParams::default()
    };
    let summary = run(&two_mm()?, config, &[10, 11], 4, 3e-4, 1)?;
    eprintln!(
        "closest point: rel max {:.2e}; shape max {:.3} mm mean {:.3} mm",
        max(&summary.relative),
        max(&summary.shape) * 1e3,
        mean(&summary.shape) * 1e3
    );
    assert!(max(&summary.shape) < 1e-3, "{:?}", summary.shape);
    Ok(())
}

#[test]
fn bad_settings_are_named() -> Result<(), EstimateError> {
    let model = two_mm()?;
    let bad_rms = FitParams {
        trusted_rms: -1.0,
        ..FitParams::default()
    };
    assert!(matches!(
        ShapeFitter::new(model).with_config(bad_rms),
        Err(EstimateError::BadShapeSetting {
            name: "trusted_rms",
            value: -1.0,
            ..
        })
    ));
    let mut no_iterations = FitParams::default();
    no_iterations.local.max_iterations = 0;
    assert!(matches!(
        ShapeFitter::new(model).with_config(no_iterations),
        Err(EstimateError::BadShapeSetting {
            name: "local.max_iterations",
            ..
        })
    ));
    // A global stage with no samples is refused when it runs; no continuation either.
    let fitter = ShapeFitter::new(model)
        .with_config(FitParams {
            continuation_steps: 0,
            ..FitParams::default()
        })?
        .with_global(MultiStart {
            samples: 0,
            ..MultiStart::default()
        });
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let truth = Vector6::new(0.0, 0.02, 0.01, -0.05, 0.03, 0.0);
    let markers = markers_of(&model, &truth, 0.0, 0, &mut rng)?;
    assert!(matches!(
        fitter.fit(&markers, &mut rng),
        Err(EstimateError::BadShapeSetting {
            name: "global.samples",
            ..
        })
    ));
    Ok(())
}

/// The paper's route (§IV-A): PSO over normalised A on the marker cost ([`SwarmSearch`]), then
/// the local refinement; the continuation from the straight wire is switched off so that the
/// swarm alone finds the basin. Noisy markers, both wires, several seeds.
#[test]
fn the_particle_swarm_then_refinement_recovers_the_shape() -> Result<(), EstimateError> {
    let config = FitParams {
        continuation_steps: 0,
        ..FitParams::default()
    };
    for (model, seeds) in [(two_mm()?, [21, 22]), (three_mm()?, [23, 24])] {
        let summary = run_with(&model, config, SwarmSearch::default(), &seeds, 3, 3e-4, 1)?;
        eprintln!(
            "swarm L = {}: shape max {:.3} mm",
            model.wire().length(),
            max(&summary.shape) * 1e3
        );
        assert!(max(&summary.shape) < 1e-3, "{:?}", summary.shape);
    }
    Ok(())
}
