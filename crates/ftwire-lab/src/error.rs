//! The commands' error ([`ftwire_app::error`], re-exported here whole) and the sorting of the
//! simulator's errors into it, which only the lab, the one crate that sees the simulator, can
//! do.

pub use ftwire_app::error::*;

/// Sorts a simulator error: Newton's failure is "no answer"; invalid parameters, poses and
/// guesses are bad input. `context` names what the user asked for.
pub fn from_sim(error: ftwire_sim::SimError, context: &str) -> LabError {
    use ftwire_sim::SimError;
    match error {
        SimError::NewtonFailed { .. } | SimError::WorkExhausted { .. } | SimError::NotSolved => {
            LabError::no_answer(format!("{context}: {error}"))
        }
        _ => LabError::bad_input(format!("{context}: {error}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failed_solve_is_no_answer_and_a_bad_rod_is_bad_input() {
        let sim = from_sim(
            ftwire_sim::SimError::NewtonFailed {
                iterations: 3,
                residual: 1.0,
                subdivisions: 2,
            },
            "solving",
        );
        assert_eq!(sim.exit_code(), 1);
        let sim = from_sim(
            ftwire_sim::SimError::TooFewEdges { edges: 2, min: 3 },
            "building",
        );
        assert_eq!(sim.exit_code(), 2);
        assert!(sim.to_string().starts_with("building: "));
    }
}
