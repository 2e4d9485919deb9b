//! Benchmark systems with known answers (issue: "benchmark systems"), shipped for tests,
//! benches and the CLI.

pub mod ball;
pub mod chain;
pub mod free_fall;
pub mod incline;
pub mod oscillator;
pub mod rocking;
