//! How a run's summary is compared with its recording in `tests/golden/`: the same keys,
//! array lengths, strings, booleans, nulls and integers; numbers written with a fraction
//! within the tolerance [`TOLERANCES`] states for their key.
//!
//! Why numbers may differ at all: ftwire-rod fuses multiply–adds on a CPU with AVX2 and FMA and
//! not elsewhere (`FTWIRE_NO_SIMD=1` forces the portable path), and the C library's `sin`,
//! `exp`, … may differ in the last bit from machine to machine. Each such rounding is an ulp;
//! the experiments' fits, inverse shape solves and closed loops carry it into their results.
//! Each tolerance is well below any change a result is read for, and well above what the two
//! paths give (docs/development.md, "Recorded summaries", has the measured differences).
//! Counts, outcomes and flags are not allowed to move: a path that changes a decision is a
//! regression.
//!
//! Shared by `crates/ftwire/tests/cli_support` and ftwire-lab's `tests/tracking.rs`.
#![allow(dead_code)]

use serde_json::Value;

/// How far a number may be from its recording: `|now − recorded| ≤ absolute + relative ·
/// |recorded|`.
#[derive(Debug, Clone, Copy)]
pub struct Tolerance {
    /// In the quantity's own unit.
    pub absolute: f64,
    /// A fraction of the recorded value.
    pub relative: f64,
}

/// One row of [`TOLERANCES`]: the keys it covers, their tolerance and why.
#[derive(Debug)]
pub struct Rule {
    /// Key names; `*` at the start or the end stands for any text (`*_mm*`: every key with
    /// `_mm` in it). The numbers of an array fall under the array's key.
    pub keys: &'static [&'static str],
    /// The tolerance of those keys' numbers.
    pub tolerance: Tolerance,
    /// Why those numbers move by up to that much.
    pub why: &'static str,
}

/// A tolerance in the quantity's unit alone.
const fn absolute(absolute: f64) -> Tolerance {
    Tolerance {
        absolute,
        relative: 0.0,
    }
}

/// A tolerance as a fraction of the recorded value alone.
const fn relative(relative: f64) -> Tolerance {
    Tolerance {
        absolute: 0.0,
        relative,
    }
}

/// Every number's tolerance, by key: the first row that covers a key applies, and a key no row
/// covers has [`DEFAULT`].
pub const TOLERANCES: &[Rule] = &[
    Rule {
        keys: &["evaluations_median"],
        tolerance: absolute(50.0),
        why: "the identification's residual evaluations: Levenberg-Marquardt stops once the cost \
              falls by less than 1e-12, a test met at the rounding level, so a fit may take a few \
              iterations (1 + 2n evaluations each, 9 with four parameters) more or fewer",
    },
    Rule {
        keys: &["*relative_error*"],
        tolerance: absolute(1e-6),
        why: "identified parameters against the truth, differences of nearly equal numbers: \
              bounded by the parameters' own tolerance (1e-6 relative), not relative to \
              themselves",
    },
    Rule {
        keys: &["estimate", "mean", "std", "linear_density", "chi2_per_dof"],
        tolerance: relative(1e-6),
        why: "identified parameters, their spread over trials and the fit's chi-squared: \
              least-squares fits stopped at a tolerance, from samples solved with the model",
    },
    Rule {
        keys: &["*_rel"],
        tolerance: relative(1e-6),
        why: "F/T errors relative to the signal, raw and through the calibration's \
              least-squares fit",
    },
    Rule {
        keys: &["*_mm*"],
        tolerance: absolute(1e-4),
        why: "shape and tracking errors [mm]: shapes solved back from sensed wrenches, along \
              closed loops that feed them back; 0.1 um, against errors read to 0.01 mm",
    },
    Rule {
        keys: &["final_error*"],
        tolerance: absolute(1e-6),
        why: "the last configuration's distance from the goal [normalised; success is 0.1]: the \
              end of a closed loop on sensed wrenches",
    },
    Rule {
        keys: &["detector_threshold"],
        tolerance: relative(1e-6),
        why: "the collision detector's threshold, learnt from the residuals of simulated free \
              motions along a closed loop",
    },
    Rule {
        keys: &["slope", "floor", "detection_force_n", "a_error_mean"],
        tolerance: relative(1e-7),
        why: "the collision detector's fit, the contact force at a detection [N] and the mean \
              configuration error [normalised]: simulated closed loops",
    },
    Rule {
        keys: &["min_clearance*", "cost"],
        tolerance: relative(1e-7),
        why: "the plan's clearance and cost: the same plan, its wire shapes solved with the model",
    },
];

/// The tolerance of a number no row of [`TOLERANCES`] covers: settings echoed back, drawn
/// configurations, path lengths, medians of step counts and fractions of samples. They are
/// computed without the model's fused arithmetic, so only the last digits of the C library's
/// functions may differ.
pub const DEFAULT: Rule = Rule {
    keys: &["*"],
    tolerance: relative(1e-12),
    why: "no model arithmetic: at most the C library's last digits",
};

/// Whether `pattern` (see [`Rule::keys`]) covers `key`.
fn covers(pattern: &str, key: &str) -> bool {
    if pattern == "*" {
        return true;
    }
    match (pattern.strip_prefix('*'), pattern.strip_suffix('*')) {
        (Some(_), Some(_)) => key.contains(&pattern[1..pattern.len() - 1]),
        (Some(suffix), None) => key.ends_with(suffix),
        (None, Some(prefix)) => key.starts_with(prefix),
        (None, None) => key == pattern,
    }
}

/// The rule for the numbers under `key`.
pub fn rule(key: &str) -> &'static Rule {
    TOLERANCES
        .iter()
        .find(|r| r.keys.iter().any(|p| covers(p, key)))
        .unwrap_or(&DEFAULT)
}

/// The first place where `now` differs from `recorded` beyond the tolerances, as a JSON path
/// with both values, or `None` where they agree. `at` is the path of both values, `key` the
/// name whose rule applies to the numbers among them.
pub fn first_difference(now: &Value, recorded: &Value, at: &str, key: &str) -> Option<String> {
    match (now, recorded) {
        (Value::Object(x), Value::Object(y)) => {
            let keys: std::collections::BTreeSet<&String> = x.keys().chain(y.keys()).collect();
            keys.into_iter().find_map(|k| match (x.get(k), y.get(k)) {
                (Some(p), Some(q)) => first_difference(p, q, &format!("{at}.{k}"), k),
                (p, q) => Some(format!("{at}.{k}: {p:?} against {q:?}")),
            })
        }
        (Value::Array(x), Value::Array(y)) if x.len() == y.len() => x
            .iter()
            .zip(y)
            .enumerate()
            .find_map(|(i, (p, q))| first_difference(p, q, &format!("{at}[{i}]"), key)),
        (Value::Number(p), Value::Number(q)) if p.is_f64() && q.is_f64() => {
            let (p, q) = (p.as_f64()?, q.as_f64()?);
            let rule = rule(key);
            let allowed = rule.tolerance.absolute + rule.tolerance.relative * q.abs();
            // Written out, a summary's numbers are finite.
            ((p - q).abs() > allowed).then(|| {
                format!(
                    "{at}: {p} against {q}, {:e} apart, more than the {allowed:e} allowed ({})",
                    (p - q).abs(),
                    rule.why
                )
            })
        }
        _ if now == recorded => None,
        _ => Some(format!("{at}: {now} against {recorded}")),
    }
}
