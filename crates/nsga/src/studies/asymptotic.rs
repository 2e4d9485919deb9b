//! Honest observed orders of convergence for nonsmooth motions.
//!
//! A least-squares slope of log(error) against log(Δt) measures a scheme's order only
//! where every run follows the same motion as the reference: the same contacts close and
//! open, stick and slip, in the same order, at nearly the same times. A coarse run that
//! takes another stick–slip sequence ends somewhere else, and its error is the distance
//! between two motions, not a truncation error; a slope through such errors is a number
//! without meaning (errors 0.33, 0.33, 0.33, 0.33, 1.3·10⁻⁴ gave "order 1.99").
//!
//! So each run records its contact events ([`ContactHistory`]): for every normal contact
//! whether it carries a percussion in the step (closed) or not (open), and for every
//! friction law whether its contact sticks or slips at the end of the step, read the same
//! way for both schemes from the step's percussions and velocities. A run
//! [`follows`](ContactHistory::follows) the reference when each constraint changes state
//! the same number of times, to the same states, each change within a few of the run's
//! steps of the reference's. [`ObservedOrder::fit`] fits the slope over the smallest Δt
//! whose runs all follow the reference, and reports
//! [`ObservedOrder::NotInAsymptoticRange`] when fewer than two do.

use crate::system::{Evaluation, Layout, System};
use std::fmt;

/// A run's contact event counts as the reference's when their times differ by at most
/// this many of the run's steps: time stepping places an event only to within a step,
/// and the motion's own error shifts it by a little more.
pub const EVENT_WINDOW_STEPS: f64 = 3.0;

/// The state of one constraint over one step.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContactMode {
    /// A normal contact without percussion, or a friction law whose normal contacts
    /// are all open.
    Open,
    /// A normal contact that carries a percussion.
    Closed,
    /// A friction law of a closed contact whose slip speed is below the tolerance.
    Stick,
    /// A friction law of a closed contact that slips.
    Slip,
}

/// What counts as a percussion and as a slip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactTolerances {
    /// A normal contact is closed when its percussion over the step exceeds this force
    /// times Δt (force units): a small fraction of the system's weight.
    pub force: f64,
    /// A friction law slips when the norm of its slip velocity exceeds this speed.
    pub slip_speed: f64,
}

impl ContactTolerances {
    /// Tolerances for a system of weight `weight` (force units) and typical speed
    /// `speed`: 10⁻⁸ of the weight and 10⁻⁴ of the speed. A contact that takes part
    /// carries a sizeable share of the weight. A sticking interface of a block column
    /// (√(gh) = 2) slipped for single steps at up to 9·10⁻⁶ with Δt = 3·10⁻⁵ (moving
    /// 3·10⁻¹⁰), while the slip it ends falls by 4·10⁻⁵ a step: at 2·10⁻⁴ it is seen to
    /// stop a few of those steps early, well within a run's window.
    #[must_use]
    pub fn relative(weight: f64, speed: f64) -> Self {
        Self {
            force: 1e-8 * weight,
            slip_speed: 1e-4 * speed,
        }
    }
}

/// The contact states of a run as they change: for every normal contact, then every
/// friction law, its first state and each later change with the time it was first seen.
#[derive(Debug, Clone, PartialEq, Default, serde::Serialize)]
pub struct ContactHistory {
    changes: Vec<Vec<(f64, ContactMode)>>,
}

impl ContactHistory {
    /// Appends the states seen at time `t`; a constraint's entry grows only when its
    /// state differs from its last.
    pub fn record(&mut self, t: f64, modes: &[ContactMode]) {
        if self.changes.is_empty() {
            self.changes = modes.iter().map(|&m| vec![(t, m)]).collect();
            return;
        }
        for (seen, &m) in self.changes.iter_mut().zip(modes) {
            if seen.last().is_some_and(|&(_, last)| last != m) {
                seen.push((t, m));
            }
        }
    }

    /// The number of changes after the first states, seen at the resolution of
    /// [`EVENT_WINDOW_STEPS`] steps of `dt` ([`Self::follows`]).
    #[must_use]
    pub fn events(&self, dt: f64) -> usize {
        let window = EVENT_WINDOW_STEPS * dt;
        self.changes
            .iter()
            .map(|c| settled(c, window).len().saturating_sub(1))
            .sum()
    }

    /// Whether this run, taken with step `dt`, follows `reference`: seen at the
    /// resolution of w = [`EVENT_WINDOW_STEPS`] × `dt`, every constraint starts in the
    /// same state, changes the same number of times to the same states, and each change
    /// is within w of the reference's. At that resolution a change undone within w is
    /// no change (a contact of Moreau–Jean that opens for one step while resting, as its
    /// velocity-level impact law lets it), and a change within w of the start sets the
    /// first state.
    #[must_use]
    pub fn follows(&self, reference: &Self, dt: f64) -> bool {
        let window = EVENT_WINDOW_STEPS * dt;
        self.changes.len() == reference.changes.len()
            && self.changes.iter().zip(&reference.changes).all(|(a, b)| {
                let (a, b) = (settled(a, window), settled(b, window));
                a.len() == b.len()
                    && a.first().map(|x| x.1) == b.first().map(|x| x.1)
                    && a.iter()
                        .zip(&b)
                        .skip(1)
                        .all(|(x, y)| x.1 == y.1 && (x.0 - y.0).abs() <= window)
            })
    }
}

/// One constraint's `changes` seen at the resolution `window`: a change back to the
/// state before within `window` cancels the change it undoes, and a change within
/// `window` of the first record replaces the first state.
fn settled(changes: &[(f64, ContactMode)], window: f64) -> Vec<(f64, ContactMode)> {
    let mut out: Vec<(f64, ContactMode)> = Vec::with_capacity(changes.len());
    for &(t, mode) in changes {
        match out.as_mut_slice() {
            [first] if t - first.0 <= window => first.1 = mode,
            [.., before, last] if t - last.0 <= window && before.1 == mode => {
                out.pop();
            }
            _ => out.push((t, mode)),
        }
    }
    out
}

/// Reads the [`ContactMode`] of every constraint of a system from a step's end state
/// and percussions, the same way for every scheme.
#[derive(Debug)]
pub struct ContactReader {
    layout: Layout,
    tolerances: ContactTolerances,
    eval: Evaluation<f64>,
    velocity: Vec<f64>,
    history: ContactHistory,
}

impl ContactReader {
    /// A reader for systems of `layout`.
    #[must_use]
    pub fn new(layout: Layout, tolerances: ContactTolerances) -> Self {
        let eval = Evaluation::new(&layout);
        Self {
            layout,
            tolerances,
            eval,
            velocity: Vec::new(),
            history: ContactHistory::default(),
        }
    }

    /// Records the states after a step of length `dt` ending at (t, q, u) with normal
    /// percussions `p_n`.
    pub fn record<S: System>(
        &mut self,
        system: &S,
        dt: f64,
        (t, q, u): (f64, &[f64], &[f64]),
        p_n: &[f64],
    ) {
        let closed: Vec<bool> = p_n
            .iter()
            .map(|&p| p > self.tolerances.force * dt)
            .collect();
        let mut modes: Vec<ContactMode> = closed
            .iter()
            .map(|&c| {
                if c {
                    ContactMode::Closed
                } else {
                    ContactMode::Open
                }
            })
            .collect();
        if !self.layout.friction.is_empty() {
            self.slip_velocities(system, t, q, u);
            let first = self.layout.n_bilateral_velocity;
            for (law, offset) in self
                .layout
                .friction
                .iter()
                .zip(self.layout.friction_offsets())
            {
                let slip = &self.velocity[first + offset..first + offset + law.components];
                let speed = slip.iter().map(|v| v * v).sum::<f64>().sqrt();
                modes.push(if !law.normals.iter().any(|&k| closed[k]) {
                    ContactMode::Open
                } else if speed > self.tolerances.slip_speed {
                    ContactMode::Slip
                } else {
                    ContactMode::Stick
                });
            }
        }
        self.history.record(t, &modes);
    }

    /// The velocity family v = W_vᵀu + χ_v at (t, q, u), into `self.velocity`.
    fn slip_velocities<S: System>(&mut self, system: &S, t: f64, q: &[f64], u: &[f64]) {
        self.eval.reset();
        system.evaluate(t, q, u, &mut self.eval);
        self.velocity.clone_from(&self.eval.velocity_chi);
        for &(r, c, w) in &self.eval.velocity_w.entries {
            self.velocity[c] += w * u[r];
        }
    }

    /// The history recorded so far.
    #[must_use]
    pub fn into_history(self) -> ContactHistory {
        self.history
    }
}

/// An observed order of convergence, fitted only where it means something. In JSON
/// always the same three keys: `status` (`"fitted"` or `"not_in_asymptotic_range"`),
/// `order` (null when not fitted) and `dts`.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
#[serde(into = "OrderJson")]
pub enum ObservedOrder {
    /// The least-squares slope of log(error) over log(Δt) through the runs of `dts`: the
    /// smallest Δt given, up to the first whose run leaves the reference's sequence of
    /// contact events.
    Fitted {
        /// The slope.
        order: f64,
        /// The Δt fitted over, smallest first.
        dts: Vec<f64>,
    },
    /// Fewer than two of the smallest Δt follow the reference's contact events (or have
    /// a positive error): the errors compare different motions, and no order is given.
    NotInAsymptoticRange {
        /// The smallest Δt whose runs follow the reference (none or one).
        dts: Vec<f64>,
    },
}

/// The JSON form of [`ObservedOrder`].
#[derive(serde::Serialize)]
struct OrderJson {
    status: &'static str,
    order: Option<f64>,
    dts: Vec<f64>,
}

impl From<ObservedOrder> for OrderJson {
    fn from(o: ObservedOrder) -> Self {
        match o {
            ObservedOrder::Fitted { order, dts } => Self {
                status: "fitted",
                order: Some(order),
                dts,
            },
            ObservedOrder::NotInAsymptoticRange { dts } => Self {
                status: "not_in_asymptotic_range",
                order: None,
                dts,
            },
        }
    }
}

/// One run of a convergence study, as [`ObservedOrder::fit`] needs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConvergencePoint {
    /// Δt.
    pub dt: f64,
    /// The error, or `None` when the run failed.
    pub error: Option<f64>,
    /// Whether the run follows the reference's contact events.
    pub follows: bool,
}

impl ObservedOrder {
    /// The order of `points` (any order of Δt): the runs are taken from the smallest Δt
    /// up while they follow the reference and have a positive error; the slope is fitted
    /// through them when there are at least two.
    #[must_use]
    pub fn fit(points: &[ConvergencePoint]) -> Self {
        let mut sorted = points.to_vec();
        sorted.sort_by(|a, b| a.dt.total_cmp(&b.dt));
        let usable: Vec<(f64, f64)> = sorted
            .iter()
            .map_while(|p| p.error.filter(|e| *e > 0.0 && p.follows).map(|e| (p.dt, e)))
            .collect();
        match least_squares_slope(&usable) {
            Some(order) if usable.len() >= 2 => Self::Fitted {
                order,
                dts: usable.iter().map(|p| p.0).collect(),
            },
            _ => Self::NotInAsymptoticRange {
                dts: usable.iter().map(|p| p.0).collect(),
            },
        }
    }

    /// The fitted order, if any.
    #[must_use]
    pub fn order(&self) -> Option<f64> {
        match self {
            Self::Fitted { order, .. } => Some(*order),
            Self::NotInAsymptoticRange { .. } => None,
        }
    }

    /// Whether the run at `dt` is one the order was fitted through.
    #[must_use]
    pub fn fitted_at(&self, dt: f64) -> bool {
        matches!(self, Self::Fitted { dts, .. } if dts.contains(&dt))
    }
}

impl fmt::Display for ObservedOrder {
    /// `1.98 (Δt 5.0e-4 to 2.0e-3)` or `not in the asymptotic range`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Fitted { order, dts } => write!(
                f,
                "{order:.2} (Δt {:.1e} to {:.1e})",
                dts[0],
                dts[dts.len() - 1]
            ),
            Self::NotInAsymptoticRange { .. } => f.write_str("not in the asymptotic range"),
        }
    }
}

/// A row of a convergence study: one run of one scheme at one Δt.
pub trait ConvergenceRow {
    /// What [`ObservedOrder::fit`] needs of the run.
    fn point(&self) -> ConvergencePoint;
    /// Marks whether the order was fitted through the run.
    fn mark_fitted(&mut self, fitted: bool);
}

/// The observed order of `rows`, the runs of one scheme, marking each row the order was
/// fitted through.
pub fn fit_rows<R: ConvergenceRow>(rows: &mut [R]) -> ObservedOrder {
    let points: Vec<ConvergencePoint> = rows.iter().map(ConvergenceRow::point).collect();
    let order = ObservedOrder::fit(&points);
    for r in rows.iter_mut() {
        let dt = r.point().dt;
        r.mark_fitted(order.fitted_at(dt));
    }
    order
}

/// The least-squares slope of ln(e) over ln(Δt) through `(Δt, e)` points; `None` with
/// fewer than two distinct Δt.
#[must_use]
pub fn least_squares_slope(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points.iter().map(|p| (p.0.ln(), p.1.ln())).collect();
    #[allow(clippy::cast_precision_loss)]
    let n = logs.len() as f64;
    let mx = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let my = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let sxx: f64 = logs.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = logs.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

#[cfg(test)]
mod tests {
    use super::*;
    use ContactMode::{Closed, Open, Slip, Stick};

    fn point(dt: f64, error: f64, follows: bool) -> ConvergencePoint {
        ConvergencePoint {
            dt,
            error: Some(error),
            follows,
        }
    }

    #[test]
    fn the_order_is_fitted_over_the_runs_that_follow_the_reference() {
        let points = [
            point(1e-2, 0.33, false),
            point(1e-3, 3e-6, true),
            point(1e-4, 3e-8, true),
            point(1e-5, 3e-10, true),
        ];
        let order = ObservedOrder::fit(&points);
        let expected = least_squares_slope(&[(1e-5, 3e-10), (1e-4, 3e-8), (1e-3, 3e-6)]);
        assert_eq!(order.order(), expected);
        assert!(order.fitted_at(1e-3) && !order.fitted_at(1e-2), "{order:?}");
        assert!(
            order.to_string().contains("(Δt 1.0e-5 to 1.0e-3)"),
            "{order}"
        );
    }

    #[test]
    fn a_step_function_of_errors_has_no_order() {
        // The column: only the smallest Δt follows the reference.
        let dts = [1e-2, 5e-3, 2e-3, 1e-3, 5e-4];
        let errors = [0.3275, 0.3275, 0.3293, 0.3301, 1.3e-4];
        let points: Vec<_> = dts
            .iter()
            .zip(errors)
            .map(|(&dt, e)| point(dt, e, dt < 1e-3))
            .collect();
        let order = ObservedOrder::fit(&points);
        assert_eq!(
            order,
            ObservedOrder::NotInAsymptoticRange { dts: vec![5e-4] }
        );
        assert_eq!(order.to_string(), "not in the asymptotic range");
        let json = serde_json::to_value(&order).unwrap();
        assert_eq!(json["status"], "not_in_asymptotic_range");
        assert!(json["order"].is_null() && json["dts"][0] == 5e-4, "{json}");
        // A run between two followers that leaves the reference ends the range.
        let gap = [
            point(1e-3, 1e-6, true),
            point(2e-3, 1e-2, false),
            point(4e-3, 1.6e-5, true),
        ];
        assert_eq!(ObservedOrder::fit(&gap).order(), None);
    }

    #[test]
    fn histories_follow_within_a_few_steps() {
        let history = |times: &[(f64, [ContactMode; 2])]| {
            let mut h = ContactHistory::default();
            for (t, m) in times {
                h.record(*t, m);
            }
            h
        };
        let reference = history(&[
            (0.001, [Open, Open]),
            (0.100, [Closed, Slip]),
            (0.300, [Closed, Stick]),
            (0.900, [Closed, Stick]),
        ]);
        assert_eq!(reference.events(0.001), 3);
        let near = history(&[
            (0.01, [Open, Open]),
            (0.11, [Closed, Slip]),
            (0.32, [Closed, Stick]),
        ]);
        assert!(near.follows(&reference, 0.01));
        assert!(!near.follows(&reference, 0.001), "three steps of 1 ms");
        // A contact that opens for one step and closes again has not changed.
        let flicker = history(&[
            (0.01, [Open, Open]),
            (0.09, [Closed, Slip]),
            (0.10, [Open, Open]),
            (0.11, [Closed, Slip]),
            (0.20, [Open, Open]),
            (0.21, [Closed, Slip]),
            (0.32, [Closed, Stick]),
        ]);
        assert_eq!(flicker.events(0.001), 11);
        assert_eq!(flicker.events(0.01), 3);
        assert!(flicker.follows(&reference, 0.01));
        assert!(!flicker.follows(&reference, 0.002), "resolved at 6 ms");
        let other = history(&[
            (0.01, [Open, Open]),
            (0.11, [Closed, Slip]),
            (0.32, [Closed, Stick]),
            (0.50, [Closed, Slip]),
        ]);
        assert!(!other.follows(&reference, 0.01), "one more slip");
    }
}
