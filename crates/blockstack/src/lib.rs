//! A 2D stack of rigid blocks on a driven base (Honein 2024, Ch. 4, App. G, H, I): the
//! model and the contact geometry, ready for a nonsmooth time stepper.
//!
//! - [`Block`], [`Base`] with its prescribed [`BaseMotion`] in x, y and rotation
//!   (harmonic, pulses, recorded accelerations: [`base`]), coordinates [`Pose`] /
//!   [`Twist`] (4.2.1)–(4.2.2);
//! - the contact geometry of App. G: corners ([`Corner`], (G.1.1)), the two gaps and one
//!   slip speed of each interface ([`Interface`], (G.2.2)–(G.3.2)), loss of support
//!   ((G.2.4) corrected, ERRATA 23), an optional [`Floor`]; every quantity comes with its
//!   exact force direction W and the velocity-product term ζ of its time derivative;
//! - [`Scene`]s (validated, from TOML via [`SceneFile`]; keys in docs/scenes.md; the
//!   built-in scenes of [`scenes`]; defaults taken, warnings and the resolved solver
//!   parameters in [`scene_info`]) and the thesis's scenarios
//!   ([`scenarios`]: Leaning Tower of Lire with the harmonic overhangs of ERRATA 16, the
//!   shaken column, the sliding column);
//! - [`Scene::contacts`]: all gaps and slips in the block coordinates, what a stepper
//!   evaluates per iterate;
//! - [`painleve`]: Painlevé's paradoxes for one block (App. I, ERRATA 18);
//! - [`system`]: the scene as an nsga `System` ([`StackSystem`]: q = (x, y, θ) per block,
//!   q̇ = u, diagonal mass, gravity, the gaps and slips of App. G with the base motion in
//!   χ and ζ, one friction law per interface bounded by μ(λ_N1 + λ_N2), App. H), with
//!   exact sparse derivatives whose cost is linear in the number of blocks;
//! - [`simulation`]: [`simulate`] runs a scene with the nonsmooth generalized-α stepper
//!   (consistent start of §4.3, failure and opening times of §4.4, energy, branch points
//!   of docs/method.md §8, ERRATA 22) and returns a [`RunSummary`].
//!
//! ```
//! use blockstack::scenarios::{lire, Perturbation};
//!
//! // The four-block Leaning Tower of Lire at rest in its maximum-overhang configuration.
//! let scene = lire(4, Perturbation::None)?;
//! let q = scene.initial_coordinates();
//! let u = vec![0.0; q.len()];
//! let contacts = scene.contacts(0.0, &q, &u);
//! // Every interface is closed along its whole edge: both gaps vanish.
//! for gap in &contacts.normals[..8] {
//!     assert!(gap.expect("supported").value.abs() < 1e-14);
//! }
//! // The top block's centre of mass sits at the right edge of the block below it.
//! assert!((q[9] - (q[6] + 0.5)).abs() < 1e-15);
//!
//! // Unperturbed, it is an equilibrium: one second of simulation leaves it in place.
//! let options = blockstack::RunOptions { t_end: Some(1.0), ..Default::default() };
//! let summary = blockstack::simulate(&scene, &options, |_record| {})?;
//! assert_eq!(summary.steps, 100);
//! assert!((summary.final_poses[3].x - q[9]).abs() < 1e-9);
//! assert!(summary.failure_time.is_none() && summary.error.is_none());
//! # Ok::<(), blockstack::BlockError>(())
//! ```
#![warn(missing_docs)]

pub mod arrangement;
pub mod base;
pub mod block;
pub mod broad_phase;
pub mod contact_laws;
pub mod contact_states;
pub mod coordinates;
pub mod corners;
mod error;
pub mod events;
pub mod exploration;
pub mod floor;
pub mod fork_check;
pub mod gaps;
pub mod interface;
pub mod materials;
pub mod overlap;
pub mod painleve;
pub mod pairs;
pub mod record;
pub mod scenarios;
pub mod scene;
pub mod scene_base;
pub mod scene_file;
pub mod scene_info;
pub mod scenes;
pub mod simulation;
pub mod slip;
pub mod stack;
pub mod stepping;
pub mod studies;
pub mod system;
pub mod time_guard;
pub mod turned;

pub use arrangement::{Arrangement, Seat};
pub use base::{
    Accelerogram, Base, BaseKinematics, BaseMotion, Baseline, CubicSpline, Pulse, PulseShape,
};
pub use block::Block;
pub use coordinates::{BodyState, Pose, Twist, Vec2};
pub use corners::Corner;
pub use error::BlockError;
pub use events::{EventKind, FailureEvent};
pub use floor::{Floor, FloorContacts};
pub use gaps::{CornerOnFace, Face, PairRow};
pub use interface::{GapCase, Interface, InterfaceContacts, InterfaceGap, Size, Support};
pub use pairs::CornerContact;
pub use scene::{ContactParams, Prox, Scene, SolverParams};
pub use scene_file::{LoadedScene, SceneFile};
pub use scene_info::{Defaults, SceneReport, SceneWarning};
pub use scenes::BuiltinScene;
pub use simulation::{
    simulate, BlockPose, BlockstackError, BranchRecord, InterfaceForce, RunError, RunOptions,
    RunReport, RunSummary, StepRecord,
};
pub use slip::{slip_direction, LowerBody};
pub use stack::{ContactRow, FrictionLaw, SparseColumn, StackContacts};
pub use system::{SlotChange, StackSystem};
