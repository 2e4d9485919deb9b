//! The state the stepper carries from step to step (docs/method.md §3, "carried over").

use crate::linalg::norm;

/// Two states closer than this ([`State::relative_distance`]) are the same continuation
/// (how branch candidates are deduplicated, docs/method.md §8.4).
pub const SAME_MOTION: f64 = 1e-8;

/// The state carried from step to step (docs/method.md §3 "Carried over").
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct State {
    /// Step counter k (t = t0 + k Δt, ERRATA 20).
    pub k: u64,
    /// Time t_k.
    pub t: f64,
    /// Coordinates q.
    pub q: Vec<f64>,
    /// Velocities u.
    pub u: Vec<f64>,
    /// Smooth acceleration a.
    pub a: Vec<f64>,
    /// Auxiliary acceleration ā.
    pub a_bar: Vec<f64>,
    /// Normal contact forces λ_N.
    pub lambda_n: Vec<f64>,
    /// Auxiliary λ̄_N.
    pub lambda_n_bar: Vec<f64>,
    /// Friction forces λ_F.
    pub lambda_f: Vec<f64>,
    /// Auxiliary λ̄_F.
    pub lambda_f_bar: Vec<f64>,
    /// Normal percussions P_N of the last step (eq. 95).
    pub p_n: Vec<f64>,
    /// Friction percussions P_F of the last step.
    pub p_f: Vec<f64>,
    /// The last step's unknowns x (eq. 126), the next Newton start.
    pub x: Vec<f64>,
}

impl State {
    /// Whether two states are the same continuation: q and u agree to 1e-8 relative to
    /// 1 + ‖q‖ + ‖u‖ (how branch candidates are deduplicated, docs/method.md §4).
    #[must_use]
    pub fn same_motion(&self, other: &State) -> bool {
        self.relative_distance(other) <= SAME_MOTION
    }

    /// ‖(q, u) − (q, u)_other‖ / (1 + ‖q_other‖ + ‖u_other‖): the distance between two
    /// continuations, relative to the motion's size.
    #[must_use]
    pub fn relative_distance(&self, other: &State) -> f64 {
        let squared =
            |a: &[f64], b: &[f64]| -> f64 { a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum() };
        let distance = (squared(&self.q, &other.q) + squared(&self.u, &other.u)).sqrt();
        distance / (1.0 + norm(&other.q) + norm(&other.u))
    }
}
