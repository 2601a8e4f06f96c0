//! `ftwire shape --log`: the wire's shape for every record of a rig log (paper §IV-C), as a
//! real rig would run the estimator offline. The work is [`ftwire_lab::log::shape`]'s; this
//! command prints each record's answer as soon as it has it.
//!
//! Output per record: with `--json`, one JSON object per line: `record` (from 0), `time`,
//! `a_tilde`, `confidence`, `points` (\[m\]), and `marker_mean_mm` when the record has
//! markers; without, one line of text. A record the model cannot solve gets an `error`
//! instead, and the command then exits 1 after the last record. A bad or empty log, or a
//! `raw` record without `--calibration`, is bad input (exit 2) naming the line or record.

use std::io::{self, Write};

use ftwire::output::JsonLines;
use ftwire_lab::error::LabError;
use ftwire_lab::log::shape::{LogShapes, ShapeLogParams};

use crate::cli::shape::ShapeArgs;

/// Runs the command.
pub fn run(args: ShapeArgs) -> Result<(), LabError> {
    let params = ShapeLogParams {
        log: args.log.clone(),
        wire: args.wire.clone(),
        calibration: args.calibration.file.clone(),
    };
    let shapes = LogShapes::new(&params)?;
    let records = shapes.records().len();
    let stdout = io::stdout();
    let mut out = stdout.lock();
    let mut failed = 0_usize;
    for shape in shapes {
        let shape = shape?;
        if shape.error.is_some() {
            failed += 1;
        }
        if args.output.json {
            JsonLines::new(&mut out).write(&shape)?;
        } else {
            write!(out, "{shape}")
                .and_then(|()| out.flush())
                .map_err(|e| LabError::io("writing the result", e))?;
        }
    }
    if failed > 0 {
        return Err(LabError::no_answer(format!(
            "no shape for {failed} of {records} records (see their `error`)"
        )));
    }
    Ok(())
}
