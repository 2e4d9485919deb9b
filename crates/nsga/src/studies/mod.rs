//! Whole runs of the benchmark systems with answers known in closed form, and what the
//! command line and the tour report of them.
//!
//! - [`asymptotic`]: observed orders fitted only where the runs follow the reference's
//!   sequence of contact events;
//! - [`ball`]: the paper's rotating bouncing ball, both schemes, and its report;
//! - [`work_precision`]: error against solver time for NSGA at several ρ∞ and
//!   Moreau–Jean.

pub mod asymptotic;
pub mod ball;
pub mod work_precision;
