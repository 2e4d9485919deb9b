//! The per-point computations behind the figures, sweeps and tables of Ch. 4 and
//! App. I: what one row of a sweep or one line of a report is, as a typed,
//! serializable result.
//!
//! - [`shaking`]: the shaken column's time to failure at one base frequency (Figure 4.6);
//! - [`slide`]: the column on a pulled base at one speed, its top block's angle and how
//!   it ends (Figure 4.7);
//! - [`scene_sweep`]: any scene with some of its numbers set to other values, one run
//!   per combination (`rollstack blocks sweep scene`);
//! - [`lire`]: the outcome of a Leaning Tower of Lire run (Figure 4.4);
//! - [`painleve`]: Painlevé's paradoxes for one block (App. I, Figure I.2);
//! - [`fragility`]: a scene under every record of a list at every intensity level,
//!   each run's outcome (overturned, failed) and lognormal fragility curves fitted to
//!   them (`rollstack blocks fragility`);
//! - [`convergence`]: a scene at Δt/2^k and under tiny perturbations, with a verdict on
//!   its failure time and its outcome (converged, chaotic, non-unique).

pub mod convergence;
pub mod fragility;
pub mod lire;
pub mod painleve;
pub mod scene_sweep;
pub mod shaking;
pub mod slide;
pub mod work_precision;
