//! The one error type of ftwire's commands, and the exit-code rule.
//!
//! Every command returns [`LabError`]; `main` maps it to the process exit code in one place,
//! [`LabError::exit_code`]:
//! - **0**: success;
//! - **1**: the input is valid but no answer was found (no IK solution, Newton did not converge,
//!   later: no path), or the answer could not be written out;
//! - **2**: bad input (clap's own usage errors exit 2 as well).

use std::io;

use thiserror::Error;

/// Exit code of a valid input without an answer.
pub const EXIT_NO_ANSWER: u8 = 1;
/// Exit code of a bad input (as clap's own usage errors).
pub const EXIT_BAD_INPUT: u8 = 2;

/// What went wrong in a command, sorted by who must act: the user (bad input) or nobody (no
/// answer exists for this input, or the output could not be written).
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum LabError {
    /// The input is invalid: a value out of range, an unreadable file, an inconsistent
    /// combination. Exit code 2.
    #[error("{message}")]
    BadInput {
        /// What was wrong and what is allowed.
        message: String,
    },
    /// The input is valid but the solver found no answer. Exit code 1.
    #[error("{message}")]
    NoAnswer {
        /// What was asked and why there is no answer.
        message: String,
    },
    /// Writing the answer failed (a closed pipe, a full disk). Exit code 1.
    #[error("{context}: {source}")]
    Io {
        /// What was being written or read.
        context: String,
        /// The underlying error.
        #[source]
        source: io::Error,
    },
}

impl LabError {
    /// A bad input, with a message saying what was wrong and what is allowed.
    pub fn bad_input(message: impl Into<String>) -> Self {
        Self::BadInput {
            message: message.into(),
        }
    }

    /// A valid input without an answer.
    pub fn no_answer(message: impl Into<String>) -> Self {
        Self::NoAnswer {
            message: message.into(),
        }
    }

    /// An I/O failure while doing `context`.
    pub fn io(context: impl Into<String>, source: io::Error) -> Self {
        Self::Io {
            context: context.into(),
            source,
        }
    }

    /// The process exit code of this error (the rule in the module docs).
    pub fn exit_code(&self) -> u8 {
        match self {
            Self::BadInput { .. } => EXIT_BAD_INPUT,
            Self::NoAnswer { .. } | Self::Io { .. } => EXIT_NO_ANSWER,
        }
    }

    /// A short machine-readable name of the kind: `"bad_input"`, `"no_answer"` or `"io"`.
    pub fn kind(&self) -> &'static str {
        match self {
            Self::BadInput { .. } => "bad_input",
            Self::NoAnswer { .. } => "no_answer",
            Self::Io { .. } => "io",
        }
    }

    /// The same error with `context` in front of its message (`"context: message"`).
    #[must_use]
    pub fn context(self, context: impl std::fmt::Display) -> Self {
        match self {
            Self::BadInput { message } => Self::BadInput {
                message: format!("{context}: {message}"),
            },
            Self::NoAnswer { message } => Self::NoAnswer {
                message: format!("{context}: {message}"),
            },
            Self::Io { context: c, source } => Self::Io {
                context: format!("{context}: {c}"),
                source,
            },
        }
    }
}

/// The front end a library call came from, so that its errors name an input as that front end
/// spells it: a command-line flag (`--tare-time`), a Python keyword (`tare_time`) or a ROS 2
/// parameter (`tare_time`), and the data as its user gave it (a log file, or arrays).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum FrontEnd {
    /// The `ftwire` command.
    #[default]
    Cli,
    /// The Python module.
    Python,
    /// A ROS 2 node.
    Ros,
}

impl FrontEnd {
    /// The input named by its command-line `flag` (`"--tare-time"`), as this front end
    /// spells it.
    ///
    /// ```
    /// use ftwire_app::error::FrontEnd;
    /// assert_eq!(FrontEnd::Cli.spell("--tare-time"), "--tare-time");
    /// assert_eq!(FrontEnd::Python.spell("--tare-time"), "tare_time");
    /// assert_eq!(FrontEnd::Ros.spell("--gravity-in-clamp"), "gravity_in_clamp");
    /// ```
    pub fn spell(self, flag: &str) -> String {
        match self {
            Self::Cli => flag.to_owned(),
            Self::Python | Self::Ros => flag.trim_start_matches('-').replace('-', "_"),
        }
    }

    /// The recorded data, a log at `path`, as its user gave it: `the log PATH`, or for Python
    /// `the arrays` (a call that reads no file).
    pub fn source(self, path: &std::path::Path) -> String {
        match self {
            Self::Python => "the arrays".to_owned(),
            Self::Cli | Self::Ros => format!("the log {}", path.display()),
        }
    }
}

/// Sorts a Kirchhoff-model error: an integration that overflowed is "no answer"; everything
/// else (parameters, a configuration outside `A`, node counts) is bad input.
pub fn from_rod(error: ftwire_rod::RodError, context: &str) -> LabError {
    use ftwire_rod::RodError;
    match error {
        RodError::Diverged { .. } | RodError::SamplingExhausted { .. } => {
            LabError::no_answer(format!("{context}: {error}"))
        }
        _ => LabError::bad_input(format!("{context}: {error}")),
    }
}

/// Sorts an estimator error: a model that cannot be solved is sorted as [`from_rod`] does;
/// data that do not identify the wire, too few good sensor samples, no start for a shape fit
/// and unreadable files are "no answer"; bad settings, logs and samples are bad input.
pub fn from_estimate(error: ftwire_estimate::EstimateError, context: &str) -> LabError {
    use ftwire_estimate::EstimateError;
    match error {
        EstimateError::Model(error) => from_rod(error, context),
        EstimateError::Io { .. }
        | EstimateError::NotIdentified { .. }
        | EstimateError::NoFitStart { .. }
        | EstimateError::TooFewGoodSamples { .. } => {
            LabError::no_answer(format!("{context}: {error}"))
        }
        _ => LabError::bad_input(format!("{context}: {error}")),
    }
}

/// Sorts a robot error: an unreachable target is "no answer"; limits, joint counts, parameters
/// and unreadable models are bad input.
pub fn from_robot(error: ftwire_robot::RobotError, context: &str) -> LabError {
    use ftwire_robot::RobotError;
    match error {
        RobotError::Unreachable { .. }
        | RobotError::OutOfReach { .. }
        | RobotError::DualArmUnreachable { .. } => {
            LabError::no_answer(format!("{context}: {error}"))
        }
        _ => LabError::bad_input(format!("{context}: {error}")),
    }
}

/// Sorts a planning error: no path within the budget is "no answer"; a bad scene, a start or
/// goal outside `Z_free` (or a tip pose no configuration reaches), bad settings and unreadable
/// files are bad input. `context` names what the user asked for.
pub fn from_plan(error: ftwire_plan::PlanError, context: &str) -> LabError {
    use ftwire_plan::PlanError;
    match error {
        PlanError::NoPath { .. } => LabError::no_answer(format!("{context}: {error}")),
        PlanError::Rod(error) => from_rod(error, context),
        _ => LabError::bad_input(format!("{context}: {error}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_kind_has_its_exit_code() {
        assert_eq!(LabError::bad_input("x").exit_code(), 2);
        assert_eq!(LabError::no_answer("x").exit_code(), 1);
        let io = LabError::io("writing", io::Error::other("closed"));
        assert_eq!(io.exit_code(), 1);
        assert_eq!(io.to_string(), "writing: closed");
        assert_eq!(LabError::bad_input("b").context("a").to_string(), "a: b");
    }
}
