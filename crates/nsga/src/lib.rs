//! Nonsmooth generalized-α time stepping with frictional contact.
//!
//! Implements the scheme of G. Capobianco, J. Harsch, S. R. Eugster, R. I. Leine, *A
//! nonsmooth generalized-alpha method for mechanical systems with frictional contact*,
//! Int. J. Numer. Methods Eng. 122 (2021) 6497–6526, as specified in `docs/method.md`
//! (equation numbers in the docs are the paper's), used by the thesis in §4.2 and App. H.
//!
//! * [`system`]: the [`System`] trait a user implements (coordinates, mass, forces,
//!   bilateral constraints, normal contacts with e_N, friction laws with 1 or 2
//!   components bounded by μ times the *sum* of one or more normal forces);
//! * [`stepper`]: the [`Stepper`] (unknowns of eq. 126, parameters of eq. 72,
//!   second-order position update eq. 125, prox/index-set contact laws eqs. 128–142,
//!   semismooth Newton eq. 143), with a consistent start ([`start`]), retries with
//!   other ρ∞, typed errors ([`StepError`]), statistics, readable and fixable index
//!   sets ([`IndexSets`]) and branch-point reports ([`BranchPoint`]); optionally
//!   simplified Newton updates from kept factors ([`LinearOptions::reuse_factorization`](crate::LinearOptions::reuse_factorization))
//!   and a line search ([`NewtonOptions::line_search`](crate::NewtonOptions::line_search));
//! * [`moreau`]: the Moreau–Jean midpoint baseline on the same trait;
//! * [`linalg`]: dense LU, Markowitz LU and sparse LU behind [`LinearSolver`];
//! * [`systems`]: benchmark systems with known answers (free fall, oscillator,
//!   bouncing ball, incline, rocking block, chain), and [`studies`] with whole runs of them
//!   (the ball cases, work-precision diagrams).
//!
//! # Adding a system (design note)
//!
//! A system is one `evaluate` function written generically over a [`Scalar`] (so
//! that exact Jacobians come from forward-mode automatic differentiation), plus a
//! [`Layout`]. Constraints come in two families, each described by its values, its
//! force directions W (nu × n, as triplets) and the terms χ, ζ that complete its time
//! derivatives: the position family p = (g, g_N) with ṗ = W_pᵀu + χ_p,
//! p̈ = W_pᵀa + ζ_p, and the velocity family v = (γ, γ_F) with v = W_vᵀu + χ_v,
//! v̇ = W_vᵀa + ζ_v. For a gap g_N(q) with q̇ = u, W_p is its gradient, χ_p = 0
//! (no prescribed motion) and ζ_p = uᵀ(∂²g_N/∂q²)u. Large systems override
//! [`System::derivatives`] with their sparse structure ([`systems::chain`] shows how).
//!
//! A point mass on the ground (one gap, one friction law):
//!
//! ```
//! use nsga::{Evaluation, FrictionLaw, Layout, Options, Scalar, Stepper, System};
//!
//! /// A puck sliding on the floor y = 0: q = (x, y).
//! struct Puck { mass: f64, mu: f64 }
//!
//! impl System for Puck {
//!     fn layout(&self) -> Layout {
//!         Layout {
//!             nq: 2,
//!             nu: 2,
//!             e_n: vec![0.0],
//!             friction: vec![FrictionLaw { components: 1, mu: self.mu, e_f: 0.0, normals: vec![0] }],
//!             ..Layout::default()
//!         }
//!     }
//!     fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
//!         out.mass.push(0, 0, T::from(self.mass));
//!         out.mass.push(1, 1, T::from(self.mass));
//!         out.forces[1] = T::from(-9.81 * self.mass);
//!         out.position[0] = q[1]; // gap g_N = y
//!         out.position_w.push(1, 0, T::from(1.0)); // ġ_N = ẏ
//!         out.velocity_w.push(0, 0, T::from(1.0)); // slip γ_F = ẋ
//!     }
//! }
//!
//! let mut s = Stepper::new(Puck { mass: 2.0, mu: 0.5 }, 0.0, &[0.0, 0.0], &[1.0, 0.0], Options::default())?;
//! for _ in 0..150 {
//!     s.step()?;
//! }
//! // Sliding decelerates at μg = 4.905 m/s² and stops at t = 1/4.905 = 0.204 s.
//! let st = s.state();
//! assert!(st.u[0].abs() < 1e-9);
//! assert!((st.q[0] - 1.0 / (2.0 * 0.5 * 9.81)).abs() < 2e-3);
//! assert!(st.q[1].abs() < 1e-9);
//! # Ok::<(), nsga::StepError>(())
//! ```
//!
//! # Prox parameter and units
//!
//! The prox parameter is scaled per constraint, r_k = α/(w_kᵀM⁻¹w_k) (docs/method.md §4),
//! with [`Prox::Constant`] kept to reproduce the thesis's r = 0.3. Residual rows are
//! scaled to impulse units (acceleration-level rows × Δt, position-level rows ÷ Δt) so
//! that one tolerance fits all rows.
//!
//! # Linear algebra
//!
//! The default, [`SolverChoice::Markowitz`], factorizes Newton matrices of up to
//! [`linalg::MARKOWITZ_SPARSE_THRESHOLD`] unknowns by [`MarkowitzLu`]: a sparse
//! elimination on dense storage, with pivots chosen per matrix, since the pattern changes
//! with the index sets from one iteration to the next; larger ones by [`BandLu`] (banded
//! LU after a reverse Cuthill–McKee ordering; faer's sparse LU where the band is wide).
//! [`SolverChoice::Auto`] uses dense LU up to [`linalg::DEFAULT_SPARSE_THRESHOLD`]
//! unknowns instead. Both crossovers are measured by `cargo bench -p nsga --bench nsga --
//! linear_solve`.
//! Every solver keeps the factors of its last matrix ([`LinearSolver::solve_again`]),
//! which simplified Newton updates reuse.

#![warn(missing_docs)]

mod assign;
pub mod attempt;
mod constrained_mass;
mod coulomb_lcp;
pub mod error;
pub mod explore;
mod fallback;
pub mod friction_polygon;
pub mod interrupt;
pub mod lcp;
mod lcp_step;
mod level;
pub mod linalg;
mod mass_inverse;
pub mod moreau;
pub mod newton;
pub mod options;
pub mod params;
mod prox;
pub mod report;
pub mod sets;
pub mod start;
pub mod state;
pub mod stepper;
pub mod studies;
pub mod system;
pub mod systems;
pub mod tuning;

pub use attempt::{AttemptFailure, AttemptOutcome, RefusedBecause, Trial};
pub use error::StepError;
pub use explore::{
    explore, Branch, BranchEnd, Exploration, ExploreOptions, Fork, Strategy, Walker,
};
pub use interrupt::Interrupt;
pub use linalg::{AutoSolver, BandLu, DenseLu, LinalgError, LinearSolver, MarkowitzLu, SparseLu};
pub use moreau::{MoreauOptions, MoreauState, MoreauStepper};
pub use options::{
    BranchRule, FailurePolicy, JacobianChoice, LinearOptions, NewtonOptions, Options,
    PolicyOptions, Prox, RhoInfRetry, SolverChoice, DEFAULT_REGULARIZATION, DEFAULT_RETRY_MAX_ITER,
    THESIS_FD_EPSILON,
};
pub use params::GenAlpha;
pub use report::{
    BranchPoint, ExactBecause, LastResort, NewtonWork, RunStats, SolvesByStage, StepStats,
    WorkSeconds,
};
pub use sets::IndexSets;
pub use state::{State, SAME_MOTION};
pub use stepper::{Stepper, GAP_ROUND_OFF, NEGLIGIBLE_SLIP, SET_TIE, WILD_UPDATE};
pub use system::{Derivatives, Evaluation, FrictionLaw, Layout, Probes, Scalar, System, Triplets};
pub use tuning::Tuning;
