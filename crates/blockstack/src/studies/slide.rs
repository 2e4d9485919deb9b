//! The column on a pulled base at one speed: the top block's angle at the end and how
//! the column ends (§4.5, Figure 4.7).

use crate::exploration::{leaf_spread, LeafSpread};
use crate::record::{finite_text, optional_text, Frame};
use crate::scenarios::{sliding_column_in, ColumnUnits, Sliding};
use crate::scene::Scene;
use crate::simulation::{simulate, RunOptions};
use crate::studies::convergence::row::RowConvergence;
use crate::studies::convergence::Settings;
use crate::studies::shaking::one_line;

/// How the column on a pulled base ends (§4.5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum SlideRegime {
    /// Small v0: the column rides along, upright, on the base.
    RidesAlong,
    /// Intermediate v0: the blocks rotate about the base's corner and topple.
    Topples,
    /// Large v0: the base is pulled out and the column drops almost straight
    /// (tablecloth trick).
    Drops,
}

impl SlideRegime {
    /// The name written to the CSV.
    #[must_use]
    pub fn name(self) -> &'static str {
        match self {
            Self::RidesAlong => "rides-along",
            Self::Topples => "topples",
            Self::Drops => "drops",
        }
    }
}

/// The tipping angle atan(w/h) of a block standing on a level face: turned further, its
/// centre of mass is beyond the corner it pivots on and gravity turns it further.
#[must_use]
pub fn tipping_angle(width: f64, height: f64) -> f64 {
    width.atan2(height)
}

/// Classifies the end state: any block turned beyond its [`tipping_angle`] → topples;
/// else the lowest block still above the base's top face (its centre higher than the
/// base top) and horizontally over the base → rides along (possibly rocking); else →
/// drops.
#[must_use]
pub fn slide_regime(scene: &Scene, last: &Frame) -> SlideRegime {
    let toppled = last
        .blocks
        .iter()
        .zip(scene.blocks())
        .any(|(p, b)| p.theta.abs() > tipping_angle(b.width(), b.height()));
    if toppled {
        return SlideRegime::Topples;
    }
    let base = scene.base();
    let on_base = last
        .blocks
        .first()
        .is_some_and(|p| p.y > base.top() && (p.x - last.base.x).abs() < 0.5 * base.width());
    if on_base {
        SlideRegime::RidesAlong
    } else {
        SlideRegime::Drops
    }
}

/// One run of the slide sweep (one point of Figure 4.7).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SlideRow {
    /// v0.
    pub v0: f64,
    /// Angle θ of the top block at the last step (rad).
    pub top_angle: Option<f64>,
    /// The regime, or null when the run failed.
    pub regime: Option<SlideRegime>,
    /// Steps taken.
    pub steps: usize,
    /// Why the run stopped early (or could not start), or null.
    pub error: Option<String>,
    /// Time of the last step.
    pub t_final: f64,
    /// Failure time (loss of support), or null.
    pub failure_time: Option<f64>,
    /// Steps whose first Newton attempt failed.
    pub failed_steps: usize,
    /// Solver time (s).
    pub wall_time_s: f64,
    /// Motions explored ([`RunOptions::spread_branches`]; 1: the plain run).
    pub branches: usize,
    /// Smallest top block angle at the end over the explored motions, or null.
    pub top_angle_min: Option<f64>,
    /// Their median top block angle, or null.
    pub top_angle_median: Option<f64>,
    /// Their largest top block angle, or null.
    pub top_angle_max: Option<f64>,
    /// With `--convergence K`: the row's verdicts over Δt/2^k, k = 0…K
    /// ([`crate::studies::convergence::row`]); absent otherwise, so that the row, its
    /// JSON and its line in the row log are those of a sweep without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub convergence: Option<RowConvergence>,
}

impl SlideRow {
    /// The columns of `sweep_slide.csv`, one per field, in order.
    pub const CSV_HEADER: [&'static str; 13] = [
        "v0",
        "top_angle",
        "regime",
        "steps",
        "error",
        "t_final",
        "failure_time",
        "failed_steps",
        "wall_time_s",
        "branches",
        "top_angle_min",
        "top_angle_median",
        "top_angle_max",
    ];

    /// The row's cells under [`Self::CSV_HEADER`]: numbers in shortest round-trip form,
    /// an empty cell for a missing or non-finite value.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        vec![
            finite_text(self.v0),
            optional_text(self.top_angle),
            self.regime.map_or("", SlideRegime::name).to_owned(),
            self.steps.to_string(),
            self.error.clone().unwrap_or_default(),
            finite_text(self.t_final),
            optional_text(self.failure_time),
            self.failed_steps.to_string(),
            finite_text(self.wall_time_s),
            self.branches.to_string(),
            optional_text(self.top_angle_min),
            optional_text(self.top_angle_median),
            optional_text(self.top_angle_max),
        ]
    }
}

/// One line: v0, the top block's angle at the end, and the regime, with the error if any.
impl std::fmt::Display for SlideRow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let angle = self
            .top_angle
            .map_or_else(|| "-".to_owned(), |a| format!("{a:.4} rad"));
        write!(
            f,
            "v0 = {:.4}: top angle {angle} at t = {:.3}, {}",
            self.v0,
            self.t_final,
            self.regime.map_or("-", SlideRegime::name)
        )?;
        // The spread over the explored motions (`--branches`), as the band drawn:
        // whenever it is more than the plain run's angle.
        let plain = [self.top_angle; 2] == [self.top_angle_min, self.top_angle_max];
        if self.branches > 1 || !plain {
            let s = if self.branches == 1 { "" } else { "s" };
            write!(f, "; {} motion{s}", self.branches)?;
            if let (Some(lo), Some(hi)) = (self.top_angle_min, self.top_angle_max) {
                write!(f, ", top angle from {lo:.4} to {hi:.4} rad")?;
            }
        }
        if let Some(c) = &self.convergence {
            f.write_str(&c.line())?;
        }
        if let Some(e) = &self.error {
            write!(f, ", error: {e}")?;
        }
        Ok(())
    }
}

/// Runs the sliding column `p` (its blocks on a base pulled at `p.v0` to `p.t_end`, with
/// friction `p.mu`, [`crate::scenarios::sliding_column`]); every failure goes into the row.
#[must_use]
pub fn slide_row(p: &Sliding, options: &RunOptions) -> SlideRow {
    slide_row_in(p, &ColumnUnits::default(), options)
}

/// [`slide_row`] for free blocks of another size or in another gravity (`units`).
#[must_use]
pub fn slide_row_in(p: &Sliding, units: &ColumnUnits, options: &RunOptions) -> SlideRow {
    let mut row = SlideRow {
        v0: p.v0,
        top_angle: None,
        regime: None,
        steps: 0,
        error: None,
        t_final: 0.0,
        failure_time: None,
        failed_steps: 0,
        wall_time_s: 0.0,
        branches: 0,
        top_angle_min: None,
        top_angle_median: None,
        top_angle_max: None,
        convergence: None,
    };
    let scene = match sliding_column_in(p, units) {
        Ok(s) => s,
        Err(e) => {
            row.error = Some(one_line(&e.to_string()));
            return row;
        }
    };
    let mut last: Option<Frame> = None;
    match simulate(&scene, options, |r| last = Some(Frame::from_record(r))) {
        Ok(s) => {
            row.steps = s.steps;
            row.failure_time = s.failure_time;
            row.failed_steps = s.failed_steps;
            row.wall_time_s = s.wall_time_s;
            row.error = s.error.map(|e| one_line(&e.to_string()));
            if let Some(f) = last.filter(Frame::is_finite) {
                row.t_final = f.t;
                row.top_angle = f.blocks.last().map(|p| p.theta);
                if row.error.is_none() {
                    row.regime = Some(slide_regime(&scene, &f));
                }
            }
            let spread = leaf_spread(&scene, options, false, row.top_angle, |b| {
                b.outcome.final_poses.last().map(|p| p.theta)
            });
            match spread {
                Ok(LeafSpread {
                    branches, spread, ..
                }) => {
                    row.branches = branches;
                    row.top_angle_min = spread.map(|v| v[0]);
                    row.top_angle_median = spread.map(|v| v[1]);
                    row.top_angle_max = spread.map(|v| v[2]);
                }
                Err(e) => row.error = Some(one_line(&e.to_string())),
            }
        }
        Err(e) => row.error = Some(one_line(&e.to_string())),
    }
    row
}

/// [`slide_row_in`] and, with `settings` (`--convergence K`), the row's verdicts over
/// Δt/2^k, its band the top block's angle at the end over the levels and members
/// ([`RowConvergence`]).
#[must_use]
pub fn slide_row_judged(
    p: &Sliding,
    units: &ColumnUnits,
    options: &RunOptions,
    settings: Option<Settings>,
) -> SlideRow {
    let mut row = slide_row_in(p, units, options);
    if let (Some(settings), Ok(scene)) = (settings, sliding_column_in(p, units)) {
        row.convergence = Some(RowConvergence::of(&scene, options, settings, |r| {
            r.observed.final_poses.last().map(|p| p.theta)
        }));
    }
    row
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coordinates::Pose;
    use crate::scenarios::sliding_column;

    #[test]
    fn csv_cells_match_the_header_and_name_the_regime() {
        let row = SlideRow {
            v0: 0.15,
            top_angle: Some(0.25),
            regime: Some(SlideRegime::Topples),
            steps: 300,
            error: None,
            t_final: 3.0,
            failure_time: None,
            failed_steps: 0,
            wall_time_s: f64::NAN,
            branches: 1,
            top_angle_min: Some(0.25),
            top_angle_median: Some(0.25),
            top_angle_max: Some(0.25),
            convergence: None,
        };
        let cells = row.csv_cells();
        assert_eq!(cells.len(), SlideRow::CSV_HEADER.len());
        assert_eq!(cells[..4], ["0.15", "0.25", "topples", "300"]);
        assert_eq!(cells[8], "", "a non-finite number is an empty cell");
    }

    #[test]
    fn slide_regimes_from_the_end_state() {
        let scene = sliding_column(&Sliding {
            blocks: 2,
            ..Sliding::default()
        })
        .unwrap();
        let frame = |base_x: f64, blocks: &[(f64, f64, f64)]| Frame {
            t: 3.0,
            base: Pose::new(base_x, 0.0, 0.0),
            blocks: blocks
                .iter()
                .map(|&(x, y, th)| Pose::new(x, y, th))
                .collect(),
        };
        // Upright on the base, carried along.
        let ride = frame(1.0, &[(1.0, 0.4, 0.0), (1.0, 0.8, 0.01)]);
        assert_eq!(slide_regime(&scene, &ride), SlideRegime::RidesAlong);
        // The base pulled out, the column upright on the floor.
        let drop = frame(3.0, &[(0.1, 0.0, 0.0), (0.1, 0.4, -0.05)]);
        assert_eq!(slide_regime(&scene, &drop), SlideRegime::Drops);
        // A block lying on its side.
        let topple = frame(3.0, &[(0.1, 0.0, 0.0), (0.4, -0.1, 1.5)]);
        assert_eq!(slide_regime(&scene, &topple), SlideRegime::Topples);
        // Rocking on the base within the tipping angle atan(0.2/0.4) = 26.57° rides along;
        // beyond it topples.
        let rock = frame(1.0, &[(1.0, 0.4, 0.0), (1.0, 0.8, 0.46)]);
        assert_eq!(slide_regime(&scene, &rock), SlideRegime::RidesAlong);
        let tip = frame(1.0, &[(1.0, 0.4, 0.0), (1.0, 0.8, -0.47)]);
        assert_eq!(slide_regime(&scene, &tip), SlideRegime::Topples);
    }

    #[test]
    fn a_slow_base_carries_the_column_and_a_bad_count_is_a_row_error() {
        let options = RunOptions {
            t_end: Some(0.5),
            ..RunOptions::default()
        };
        let slow = Sliding {
            blocks: 2,
            v0: 0.05,
            t_end: 0.5,
            ..Sliding::default()
        };
        let row = slide_row(&slow, &options);
        assert_eq!(row.regime, Some(SlideRegime::RidesAlong), "{row:?}");
        assert!((row.t_final - 0.5).abs() < 1e-12);
        assert!(row.top_angle.is_some_and(|a| a.abs() < 1e-3));
        let bad = slide_row(
            &Sliding {
                v0: f64::NAN,
                ..slow
            },
            &options,
        );
        assert!(bad.error.is_some() && bad.regime.is_none());
        let rough = slide_row(&Sliding { mu: -1.0, ..slow }, &options);
        assert!(
            rough.error.as_ref().is_some_and(|e| e.contains("mu")),
            "{rough:?}"
        );
    }
}
