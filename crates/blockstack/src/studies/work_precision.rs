//! Speed against error for block stacks: the error at the final time against a reference
//! run with a much smaller step, and the largest penetration, against solver time, for
//! the nonsmooth generalized-α scheme beside Moreau–Jean, on scenes without forks (no
//! step where several motions solve the contact problem, so that one reference answer
//! exists): one block sliding and tipping on a shaken base, a three-block column whose
//! bottom block slides and then sticks, and the Lire collapse before its first fork.
//!
//! ```no_run
//! use blockstack::studies::work_precision::{stack_work_precision, StackBenchmark};
//!
//! let study = stack_work_precision(StackBenchmark::Block, &[1e-2, 5e-3, 2e-3], 16.0, 1)?;
//! for row in &study.rows {
//!     println!("{row}");
//! }
//! println!("observed order, NSGA: {:?}", study.orders.nsga);
//! # Ok::<(), blockstack::BlockError>(())
//! ```

use crate::record::{finite_text, optional_text};
use crate::scenarios::{lire, shaking_column, Perturbation, Shaking};
use crate::simulation::{stepper_options, RunOptions};
use crate::system::StackSystem;
use crate::{BlockError, Scene};
use nsga::studies::asymptotic::{
    fit_rows, ContactHistory, ContactReader, ContactTolerances, ConvergencePoint, ConvergenceRow,
    ObservedOrder,
};
use nsga::studies::ball::Scheme;
use nsga::studies::work_precision::run_scheme;
use nsga::system::{Evaluation, System};
use std::fmt;
use std::sync::atomic::AtomicBool;

/// The Newton tolerance of every run of the diagram (the scenes' own is 10⁻¹⁰, the
/// thesis's). The Lire tower tilts away from an unstable equilibrium and amplifies every
/// difference between two runs, the residuals that Newton leaves in each step included:
/// with 10⁻¹⁰ its generalized-α errors stayed at 7–10·10⁻⁵ for every Δt from 10⁻² to
/// 5·10⁻⁴ (observed order 0.09), with 10⁻¹² they fall from 2.5·10⁻⁵ to 6.6·10⁻⁸
/// (order 1.98, the scheme's second order) at 20 % more solver time
/// (`rollstack blocks work-precision --system lire --json`). The block and the column
/// give the same errors and orders with either.
pub const WORK_PRECISION_TOL: f64 = 1e-12;

/// The scenes of the block-stack work-precision diagram: none has a fork before its end.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StackBenchmark {
    /// One block w = 0.2, h = 0.4, μ = 0.2 on a base shaken as x = 0.2 sin 4t: it slides
    /// and rocks on its corners; to t = 2.
    Block,
    /// Three such blocks, μ = 0.3, on a base shaken as x = 0.2 sin 2t: the bottom block
    /// slides on the base until t ≈ 0.37, then sticks while a corner of the middle
    /// interface lifts; to t = 0.8. At t ≈ 0.89 the column rocks over onto its other
    /// corners, landing at several interfaces at once, and the outcome of that landing
    /// depends on Δt (the base's corner force after it: 1.22 at Δt = 10⁻³, 1.07 at
    /// 2.5·10⁻⁴): run to t = 2, the errors jumped between 4·10⁻⁴ and 4·10⁻³ from one Δt
    /// to the next and with the reference.
    Column,
    /// The Lire tower of four blocks with its lowest block pushed out by 1 % of w
    /// (Figure 4.4), to t = 5: it tilts as one body, before any interface opens.
    Lire,
}

impl StackBenchmark {
    /// Every benchmark.
    pub const ALL: [Self; 3] = [Self::Block, Self::Column, Self::Lire];

    /// The benchmark's name in files and JSON: `block`, `column` or `lire`.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::Block => "block",
            Self::Column => "column",
            Self::Lire => "lire",
        }
    }

    /// The end time of its runs.
    #[must_use]
    pub fn t_end(self) -> f64 {
        match self {
            Self::Block => 2.0,
            Self::Column => 0.8,
            Self::Lire => 5.0,
        }
    }

    /// Its scene, with the step `dt`.
    ///
    /// # Errors
    /// A `dt` that is not positive and finite.
    pub fn scene(self, dt: f64) -> Result<Scene, BlockError> {
        input::positive("dt", dt)?;
        let shaken = |blocks, omega, mu| Shaking {
            blocks,
            omega,
            mu,
            ..Shaking::default()
        };
        let mut scene = match self {
            Self::Block => shaking_column(&shaken(1, 4.0, 0.2))?,
            Self::Column => shaking_column(&shaken(3, 2.0, 0.3))?,
            Self::Lire => lire(4, Perturbation::Bottom)?,
        };
        scene.solver.dt = dt;
        scene.solver.t_end = self.t_end();
        scene.solver.tol = WORK_PRECISION_TOL;
        Ok(scene)
    }
}

/// One run of the diagram.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StackWorkPrecisionRow {
    /// The scheme: `nsga` or `moreau`.
    pub scheme: Scheme,
    /// Δt.
    pub dt: f64,
    /// Largest difference of any coordinate (block centres in length units, angles in
    /// rad) from the reference at the end time, or null when the run failed.
    pub error: Option<f64>,
    /// Largest penetration over the run, max(0, −g_N), length units.
    pub penetration: Option<f64>,
    /// Solver time, s.
    pub wall_time_s: f64,
    /// The run's contact events: a corner's contact closing or opening, an interface
    /// starting or ending to slip, each lasting longer than a few steps
    /// ([`ContactHistory::events`]; 0 when the run failed).
    pub contact_events: usize,
    /// Whether the run follows the reference's sequence of contact events
    /// ([`ContactHistory::follows`]).
    pub follows_reference: bool,
    /// Whether the order of its scheme was fitted through this run.
    pub fitted: bool,
    /// Why the run stopped, or null.
    pub error_message: Option<String>,
}

impl StackWorkPrecisionRow {
    /// The columns of `work_precision.csv`.
    pub const CSV_HEADER: [&'static str; 9] = [
        "scheme",
        "dt",
        "error",
        "penetration",
        "wall_time_s",
        "contact_events",
        "follows_reference",
        "fitted",
        "error_message",
    ];

    /// The row's cells under [`Self::CSV_HEADER`].
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        vec![
            self.scheme.name().to_owned(),
            finite_text(self.dt),
            optional_text(self.error),
            optional_text(self.penetration),
            finite_text(self.wall_time_s),
            self.contact_events.to_string(),
            u8::from(self.follows_reference).to_string(),
            u8::from(self.fitted).to_string(),
            self.error_message.clone().unwrap_or_default(),
        ]
    }
}

impl fmt::Display for StackWorkPrecisionRow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let e = |v: Option<f64>| v.map_or_else(|| "-".to_owned(), |v| format!("{v:.2e}"));
        write!(
            f,
            "{:<6} dt = {:.1e}: error {}, penetration {}, {:.2e} s, {} contact events",
            self.scheme.name(),
            self.dt,
            e(self.error),
            e(self.penetration),
            self.wall_time_s,
            self.contact_events
        )?;
        if self.error_message.is_none() && !self.follows_reference {
            f.write_str(" (other events than the reference)")?;
        }
        if let Some(m) = &self.error_message {
            write!(f, ", stopped: {m}")?;
        }
        Ok(())
    }
}

/// Observed orders of convergence of each scheme ([`ObservedOrder::fit`]): fitted over
/// the smallest Δt whose runs follow the reference's contact events, or "not in the
/// asymptotic range".
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ObservedOrders {
    /// Nonsmooth generalized-α.
    pub nsga: ObservedOrder,
    /// Moreau–Jean.
    pub moreau: ObservedOrder,
}

/// The whole diagram of one benchmark.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StackWorkPrecision {
    /// The benchmark.
    pub system: StackBenchmark,
    /// The reference step: the smallest Δt over the reference factor.
    pub reference_dt: f64,
    /// Solver time of the reference run, s.
    pub reference_wall_time_s: f64,
    /// The reference run's contact events.
    pub reference_events: usize,
    /// One row per scheme and Δt, NSGA first, Δt in the order given.
    pub rows: Vec<StackWorkPrecisionRow>,
    /// The observed orders.
    pub orders: ObservedOrders,
}

/// The end state and largest penetration of one run, and its solver time.
struct RunEnd {
    q: Vec<f64>,
    penetration: f64,
    wall_time_s: f64,
    history: ContactHistory,
}

/// Runs `bench` with each Δt of `dts` by both schemes and measures each against a
/// generalized-α run with Δt = min(dts)/`reference_factor`. Each point is run `repeat`
/// times (at least once) and keeps the fastest solver time: the runs are deterministic,
/// so they give the same answer, and a single run of a few milliseconds reads whatever
/// else the machine was doing.
///
/// # Errors
/// An empty `dts`, a Δt or factor that is not positive, or a reference run that fails
/// (the rows' own failures are in their `error_message`).
pub fn stack_work_precision(
    bench: StackBenchmark,
    dts: &[f64],
    reference_factor: f64,
    repeat: usize,
) -> Result<StackWorkPrecision, BlockError> {
    stack_work_precision_until(
        bench,
        dts,
        reference_factor,
        repeat,
        &AtomicBool::new(false),
    )
}

/// [`stack_work_precision`] whose runs stop before their next step once `cancel` is set
/// (the Python module sets it on Ctrl-C): the reference run then fails, or the rows
/// left carry [`CANCELLED`] as their error.
///
/// # Errors
/// As [`stack_work_precision`].
pub fn stack_work_precision_until(
    bench: StackBenchmark,
    dts: &[f64],
    reference_factor: f64,
    repeat: usize,
    cancel: &AtomicBool,
) -> Result<StackWorkPrecision, BlockError> {
    input::positive("reference factor", reference_factor)?;
    let smallest = dts.iter().copied().fold(f64::INFINITY, f64::min);
    if dts.is_empty() || !dts.iter().all(|&d| d > 0.0 && d.is_finite()) {
        return Err(BlockError::Scene(
            "every Δt must be positive and finite".into(),
        ));
    }
    let reference_dt = smallest / reference_factor;
    let reference = run(bench, Scheme::Nsga, reference_dt, cancel)
        .map_err(|e| BlockError::Scene(format!("the reference run failed: {e}")))?;
    let mut rows = Vec::new();
    for scheme in [Scheme::Nsga, Scheme::Moreau] {
        for &dt in dts {
            rows.push(match fastest_run(bench, scheme, dt, repeat, cancel) {
                Ok(end) => StackWorkPrecisionRow {
                    scheme,
                    dt,
                    error: Some(max_difference(&end.q, &reference.q)),
                    penetration: Some(end.penetration),
                    wall_time_s: end.wall_time_s,
                    contact_events: end.history.events(dt),
                    follows_reference: end.history.follows(&reference.history, dt),
                    fitted: false,
                    error_message: None,
                },
                Err(e) => StackWorkPrecisionRow {
                    scheme,
                    dt,
                    error: None,
                    penetration: None,
                    wall_time_s: 0.0,
                    contact_events: 0,
                    follows_reference: false,
                    fitted: false,
                    error_message: Some(e),
                },
            });
        }
    }
    // NSGA's rows first, then Moreau–Jean's, one per Δt each.
    let (nsga, moreau) = rows.split_at_mut(dts.len());
    let orders = ObservedOrders {
        nsga: fit_rows(nsga),
        moreau: fit_rows(moreau),
    };
    Ok(StackWorkPrecision {
        system: bench,
        reference_dt,
        reference_wall_time_s: reference.wall_time_s,
        reference_events: reference.history.events(reference_dt),
        rows,
        orders,
    })
}

/// [`run`] `repeat` times (at least once), with the fastest solver time.
fn fastest_run(
    bench: StackBenchmark,
    scheme: Scheme,
    dt: f64,
    repeat: usize,
    cancel: &AtomicBool,
) -> Result<RunEnd, String> {
    let mut end = run(bench, scheme, dt, cancel)?;
    for _ in 1..repeat {
        let again = run(bench, scheme, dt, cancel)?;
        end.wall_time_s = end.wall_time_s.min(again.wall_time_s);
    }
    Ok(end)
}

pub use nsga::studies::work_precision::CANCELLED;

/// One run to the benchmark's end time by `scheme` with step `dt`.
fn run(
    bench: StackBenchmark,
    scheme: Scheme,
    dt: f64,
    cancel: &AtomicBool,
) -> Result<RunEnd, String> {
    let scene = bench.scene(dt).map_err(|e| e.to_string())?;
    let steps = (bench.t_end() / dt).round() as usize;
    let system = StackSystem::new(scene.clone());
    let q0 = scene.initial_coordinates();
    let u0 = vec![0.0; q0.len()];
    let mut penetration = 0.0_f64;
    let mut eval = Evaluation::new(&system.layout());
    let mut contacts = ContactReader::new(system.layout(), tolerances(&scene));
    let options = stepper_options(&scene, &RunOptions::default()).map_err(|e| e.to_string())?;
    let observe = |t: f64, q: &[f64], u: &[f64], p_n: &[f64]| {
        eval.reset();
        system.evaluate(t, q, u, &mut eval);
        let lowest = eval.position.iter().copied().fold(0.0, f64::min);
        penetration = penetration.max(-lowest);
        contacts.record(&system, dt, (t, q, u), p_n);
    };
    let stepped = StackSystem::new(scene.clone());
    let end = run_scheme(stepped, scheme, options, (&q0, &u0), steps, cancel, observe)
        .map_err(|e| e.to_string())?;
    Ok(RunEnd {
        q: end.q,
        penetration,
        wall_time_s: end.wall_time_s,
        history: contacts.into_history(),
    })
}

/// What counts as a closed corner and a slipping interface in `scene`: 10⁻⁸ of the
/// stack's weight and of the speed √(g h) of its smallest block height.
fn tolerances(scene: &Scene) -> ContactTolerances {
    let g = scene.solver.gravity;
    let weight: f64 = scene.blocks().iter().map(|b| b.mass() * g).sum();
    ContactTolerances::relative(weight, (g * scene.smallest_block_height()).sqrt())
}

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

impl ConvergenceRow for StackWorkPrecisionRow {
    fn point(&self) -> ConvergencePoint {
        ConvergencePoint {
            dt: self.dt,
            error: self.error,
            follows: self.follows_reference,
        }
    }

    fn mark_fitted(&mut self, fitted: bool) {
        self.fitted = fitted;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_cancelled_study_stops_before_its_first_step() {
        let cancel = AtomicBool::new(true);
        let err = stack_work_precision_until(StackBenchmark::Block, &[1e-2], 4.0, 1, &cancel)
            .unwrap_err();
        assert!(err.to_string().contains(CANCELLED), "{err}");
    }

    #[test]
    fn repeated_points_give_the_same_answer() {
        let once = stack_work_precision(StackBenchmark::Block, &[1e-2], 4.0, 1).unwrap();
        let thrice = stack_work_precision(StackBenchmark::Block, &[1e-2], 4.0, 3).unwrap();
        assert_eq!(once.rows.len(), thrice.rows.len());
        for (a, b) in once.rows.iter().zip(&thrice.rows) {
            assert_eq!((a.error, a.penetration), (b.error, b.penetration), "{b}");
            assert!(b.wall_time_s > 0.0, "{b}");
        }
    }

    #[test]
    fn a_block_on_a_shaken_base_converges_under_both_schemes() {
        let study =
            stack_work_precision(StackBenchmark::Block, &[1e-2, 5e-3, 2.5e-3], 8.0, 1).unwrap();
        assert_eq!(study.rows.len(), 6);
        for r in &study.rows {
            assert!(r.error_message.is_none(), "{r}");
            assert!(
                r.penetration.unwrap() <= 1e-8 || r.scheme == Scheme::Moreau,
                "{r}"
            );
        }
        // Both converge: the error shrinks with Δt.
        for scheme in [Scheme::Nsga, Scheme::Moreau] {
            let e: Vec<f64> = study
                .rows
                .iter()
                .filter(|r| r.scheme == scheme)
                .map(|r| r.error.unwrap())
                .collect();
            assert!(e[2] < e[0], "{scheme:?}: {e:?}");
        }
        assert!(
            study.orders.nsga.order().unwrap() > 0.5,
            "{:?}",
            study.orders
        );
    }

    /// The column ends before its landing on several corners at once, whose outcome
    /// depends on Δt: its errors are errors of the scheme, the same to 0.3 % against a
    /// reference with Δt/8 as with Δt/16. Run to t = 2 they differed by 3.6 %, and with
    /// the default `--dts` the error at Δt = 5·10⁻³ was 4.5·10⁻³ against the reference
    /// of factor 8 and 1.7·10⁻³ against that of factor 4.
    /// The issue's column: Moreau–Jean's errors 0.33, 0.33, 0.33, 0.33, 1.2·10⁻⁴ once gave
    /// "order 1.99". Its runs follow other contact events than the reference (at
    /// Δt ≥ 10⁻³ the column rocks onto other corners; at 5·10⁻⁴ the bottom interface
    /// keeps slipping where the reference's sticks at t ≈ 0.37), so it has no order;
    /// NSGA's runs all follow the reference, and its order is the slope of their errors.
    #[test]
    fn the_column_has_no_moreau_order_where_its_stick_slip_sequence_differs() {
        let dts = [1e-2, 5e-3, 2e-3, 1e-3, 5e-4];
        let study = stack_work_precision(StackBenchmark::Column, &dts, 16.0, 1).unwrap();
        let (nsga, moreau) = study.rows.split_at(dts.len());
        assert!(
            moreau.iter().all(|r| !r.follows_reference && !r.fitted),
            "{moreau:?}"
        );
        assert_eq!(
            study.orders.moreau,
            ObservedOrder::NotInAsymptoticRange { dts: vec![] }
        );
        assert!(
            nsga.iter().all(|r| r.follows_reference && r.fitted),
            "{nsga:?}"
        );
        let points: Vec<(f64, f64)> = nsga.iter().map(|r| (r.dt, r.error.unwrap())).collect();
        let slope = nsga::studies::asymptotic::least_squares_slope(&points).unwrap();
        let order = study.orders.nsga.order().unwrap();
        assert!((order - slope).abs() < 1e-12, "{order} against {slope}");
        assert_eq!(study.reference_events, 2, "{study:?}");
    }

    #[test]
    fn the_column_errors_do_not_depend_on_the_reference() {
        let errors = |factor: f64| -> Vec<f64> {
            stack_work_precision(StackBenchmark::Column, &[1e-2, 5e-3], factor, 1)
                .unwrap()
                .rows
                .iter()
                .map(|r| r.error.unwrap())
                .collect()
        };
        let (eight, sixteen) = (errors(8.0), errors(16.0));
        for (a, b) in eight.iter().zip(&sixteen) {
            assert!((a - b).abs() <= 0.01 * b, "{eight:?} against {sixteen:?}");
        }
        assert!(sixteen[1] < sixteen[0], "{sixteen:?}");
    }

    /// With the study's tolerance the Lire collapse shows generalized-α's second order
    /// (2.0 here); with the scenes' 10⁻¹⁰ the residuals left in the 32 000 steps of the
    /// reference run made it 1.1 (see [`WORK_PRECISION_TOL`]).
    #[test]
    fn the_lire_collapse_converges_at_second_order() {
        let study =
            stack_work_precision(StackBenchmark::Lire, &[1e-2, 5e-3, 2.5e-3], 16.0, 1).unwrap();
        let order = study.orders.nsga.order().unwrap();
        assert!(order > 1.7, "{:?}", study.orders);
    }
}
