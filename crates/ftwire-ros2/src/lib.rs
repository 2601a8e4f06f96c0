#![doc = include_str!("../README.md")]

pub mod bag;
pub mod cdr;
pub mod import;
pub mod msg;
pub mod node;
