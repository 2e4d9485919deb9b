//! One module per command family.

pub mod blocks;
pub mod cluster;
pub mod cylinder;
pub mod nsga;
pub mod rotation;
pub mod sphere;
pub mod tuning;
