//! The library side of the `ftwire` binary: what joins the Kirchhoff model (`ftwire-rod`) and
//! the ground-truth simulator (`ftwire-sim`). This crate is the only one allowed to see both
//! sides of the wall (`ARCHITECTURE.md`); the subcommands and the integration tests share these
//! pieces through it.

pub mod bridge;
