//! The experiments' rig support: the wire placed at `a0` reads back as `a0` through the F/T
//! pipeline once the sensor is tared, and not before.

use ftwire::experiment::Gravity;
use ftwire::experiment::rig::{measure, mounting, pipeline, place_wire, tare};
use ftwire::wire::WireSpec;
use ftwire_estimate::ft::Tare;
use ftwire_rod::from_normalised;
use ftwire_sim::RigConfig;
use nalgebra::Vector6;

#[test]
fn a_tared_sensor_reads_the_placed_configuration_back() -> Result<(), Box<dyn std::error::Error>> {
    let wire = WireSpec::preset("nitinol-3mm-820").ok_or("preset")?;
    let params = wire.wire_params()?;
    let configurations = [
        Vector6::new(0.5, 2.0, -3.0, -2.0, 1.5, 1.0),
        Vector6::new(-1.0, -1.0, 2.5, 1.0, 3.0, -2.0),
        Vector6::new(0.2, 3.0, 1.0, -4.0, -1.0, 2.0),
    ];
    for (seed, z) in configurations.iter().enumerate() {
        check(&wire, &params, &from_normalised(&params, z), seed as u64)?;
    }
    Ok(())
}

fn check(
    wire: &WireSpec,
    params: &ftwire_core::WireParams,
    a0: &Vector6<f64>,
    seed: u64,
) -> Result<(), Box<dyn std::error::Error>> {
    let config = RigConfig {
        seed,
        ..RigConfig::default()
    };
    let mut rig = place_wire(wire, Gravity::Off, a0, config.clone())?;
    let tared = pipeline(tare(&mut rig)?, mounting(&config)?)?;
    let untared = pipeline(Tare::none(), mounting(&config)?)?;
    let with_tare = measure(&mut rig, &tared)?;
    let without = measure(&mut rig, &untared)?;
    let scale = |a: &Vector6<f64>| ftwire_rod::to_normalised(params, a);
    let error_tared = (scale(&with_tare.a) - scale(a0)).norm() / scale(a0).norm();
    let error_untared = (scale(&without.a) - scale(a0)).norm() / scale(a0).norm();
    // What is left after taring is the sensor's gain, cross-talk and nonlinearity (about 1 %)
    // and the simulator's discretisation (0.2 %): the learnt calibration's job.
    eprintln!("relative error: tared {error_tared:.4}, untared {error_untared:.4}");
    assert!(error_tared < 0.04, "tared: {error_tared}");
    // The untared offset is as large as the wire's force scale (DESIGN.md).
    assert!(
        error_untared > 3.0 * error_tared,
        "untared {error_untared} vs tared {error_tared}"
    );
    assert!(with_tare.raw.screen.accepted >= 50);
    Ok(())
}
