//! Why a node could not start or run.

use thiserror::Error;

/// Errors of the ROS 2 nodes.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum NodeError {
    /// A setting is out of its allowed range.
    #[error("{setting} = {value}: {allowed}")]
    BadSetting {
        /// The option, as the command line names it.
        setting: &'static str,
        /// What was given.
        value: String,
        /// What is allowed.
        allowed: &'static str,
    },
    /// ROS 2 (DDS) could not create the context, node, topic, publisher or subscription.
    #[error("ROS 2: cannot create {what}: {message}")]
    Ros {
        /// What was being created.
        what: String,
        /// The middleware's message.
        message: String,
    },
    /// The wire, the rig or the estimator could not be set up.
    #[error(transparent)]
    Lab(#[from] ftwire_app::LabError),
    /// The node ran but could not finish its task (too few samples, no estimate, the goal
    /// refused).
    #[error("{0}")]
    Incomplete(String),
}
