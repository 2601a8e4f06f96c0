//! Summary statistics the experiments share: the lab's
//! ([`ftwire_lab::experiment::stats`]).

pub use ftwire_lab::experiment::stats::{mean_std, median};
