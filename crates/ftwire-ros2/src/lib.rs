#![doc = include_str!("../README.md")]

pub mod msg;
pub mod node;
