//! The convergence of one sweep row (`--convergence K` on `blocks sweep frequency`,
//! `slide` and `scene`): the row's scene run as [`super::converge`] runs it, reduced to
//! the columns a row adds and the band its figure draws.

use super::verdict::{Rule, VerdictKind};
use super::{converge, ConvergenceReport, ConvergenceRun, Settings};
use crate::record::optional_text;
use crate::scene::Scene;
use crate::simulation::RunOptions;
use crate::studies::shaking::one_line;
use std::fmt::Write;

/// Members per perturbation magnitude in a sweep row's study unless `--ensemble` says
/// otherwise: none. A member runs at the finest Δt, as costly as the finest level, so
/// one member per magnitude would more than double a row's study at K = 2 (levels cost
/// 1 + 2 + 4 runs at Δt, three members 12); without members a row can be `converged`,
/// `non-unique` or `not converged`, never `chaotic`.
pub const SWEEP_ENSEMBLE: usize = 0;

/// What a sweep row gains with `--convergence K`.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RowConvergence {
    /// K and members per magnitude.
    pub levels: usize,
    /// Members per magnitude.
    pub ensemble: usize,
    /// The failure time's verdict, or null when the study could not run (`error`).
    pub failure_verdict: Option<VerdictKind>,
    /// The rule that gave it.
    pub failure_rule: Option<Rule>,
    /// For a converged failure time: how far the finest level's value may lie from the
    /// limit Δt → 0.
    pub failure_tolerance: Option<f64>,
    /// For a failure time converged by Richardson's rule: the extrapolated limit.
    pub failure_extrapolated: Option<f64>,
    /// Each level's failure time, coarsest first (null: it stood, or stopped).
    pub failure_times: Vec<Option<f64>>,
    /// The outcome's verdict, or null when the study could not run.
    pub outcome_verdict: Option<VerdictKind>,
    /// The row's value (its failure time, or the top block's angle at the end) at the
    /// finest level.
    pub finest: Option<f64>,
    /// The smallest and largest of that value over the levels and the members (the
    /// band of the sweep's figure), or null when no run has it.
    pub spread: Option<[f64; 2]>,
    /// Why the study could not run, or null.
    pub error: Option<String>,
    /// The study's solver time, s: its runs' together.
    pub wall_time_s: f64,
}

impl RowConvergence {
    /// The columns a row gains (after its own).
    pub const CSV_HEADER: [&'static str; 9] = [
        "levels",
        "failure_verdict",
        "failure_tolerance",
        "failure_extrapolated",
        "level_failure_times",
        "outcome_verdict",
        "spread_min",
        "spread_max",
        "convergence_error",
    ];

    /// `header` with the columns a row gains when `asked` (`--convergence`).
    pub fn extend_header(header: &mut Vec<String>, asked: bool) {
        if asked {
            header.extend(Self::CSV_HEADER.iter().map(|c| (*c).to_owned()));
        }
    }

    /// `cells` with the cells of `c` when `asked` (empty cells for a row without: its
    /// scene was refused).
    pub fn extend_cells(cells: &mut Vec<String>, c: Option<&Self>, asked: bool) {
        if asked {
            cells.extend(c.map_or_else(
                || vec![String::new(); Self::CSV_HEADER.len()],
                Self::csv_cells,
            ));
        }
    }

    /// The study of `scene` with the sweep's `options` (one motion per run: no branches
    /// explored) and `settings`; `value`: the row's quantity in a run.
    #[must_use]
    pub fn of(
        scene: &Scene,
        options: &RunOptions,
        settings: Settings,
        value: impl Fn(&ConvergenceRun) -> Option<f64>,
    ) -> Self {
        let options = RunOptions {
            spread_branches: 1,
            ..options.clone()
        };
        match converge(scene, &options, settings) {
            Ok(report) => Self::from_report(&report, value),
            Err(e) => Self {
                levels: settings.levels,
                ensemble: settings.ensemble,
                failure_verdict: None,
                failure_rule: None,
                failure_tolerance: None,
                failure_extrapolated: None,
                failure_times: Vec::new(),
                outcome_verdict: None,
                finest: None,
                spread: None,
                error: Some(one_line(&e.to_string())),
                wall_time_s: 0.0,
            },
        }
    }

    /// The row's columns of a study's `report`.
    #[must_use]
    pub fn from_report(
        report: &ConvergenceReport,
        value: impl Fn(&ConvergenceRun) -> Option<f64>,
    ) -> Self {
        let levels = &report.runs[..report.dts.len()];
        let values: Vec<f64> = report.runs.iter().filter_map(&value).collect();
        let spread = (!values.is_empty()).then(|| {
            let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            [lo, hi]
        });
        Self {
            levels: report.settings.levels,
            ensemble: report.settings.ensemble,
            failure_verdict: Some(report.failure.verdict),
            failure_rule: Some(report.failure.rule),
            failure_tolerance: report.failure.tolerance,
            failure_extrapolated: report.failure.extrapolated,
            failure_times: levels.iter().map(|r| r.observed.failure_time).collect(),
            outcome_verdict: Some(report.outcome.verdict),
            finest: levels.last().and_then(&value),
            spread,
            error: report.runs.iter().find_map(|r| {
                r.error
                    .as_ref()
                    .map(|e| format!("{}: {}", r.label, one_line(e)))
            }),
            wall_time_s: report.runs.iter().map(|r| r.wall_time_s).sum(),
        }
    }

    /// The solver time of a row's study, s (0 without one): what a sweep adds to its
    /// rows' own.
    #[must_use]
    pub fn seconds(c: Option<&Self>) -> f64 {
        c.map_or(0.0, |c| c.wall_time_s)
    }

    /// The cells under [`Self::CSV_HEADER`]: the level failure times space-separated
    /// (an empty entry `-` for a level that did not fail), verdicts as in the JSON.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let name = |v: Option<VerdictKind>| v.map_or_else(String::new, |v| v.name().to_owned());
        let times: Vec<String> = self
            .failure_times
            .iter()
            .map(|t| t.map_or_else(|| "-".to_owned(), |t| optional_text(Some(t))))
            .collect();
        vec![
            self.levels.to_string(),
            name(self.failure_verdict),
            optional_text(self.failure_tolerance),
            optional_text(self.failure_extrapolated),
            times.join(" "),
            name(self.outcome_verdict),
            optional_text(self.spread.map(|s| s[0])),
            optional_text(self.spread.map(|s| s[1])),
            self.error.clone().unwrap_or_default(),
        ]
    }

    /// `; failure converged to 2.5e-3 (levels 3.4000 3.2000 3.1000), outcome not
    /// converged`: what a row's line of text adds.
    #[must_use]
    pub fn line(&self) -> String {
        let Some(failure) = self.failure_verdict else {
            return format!(
                "; convergence not judged: {}",
                self.error.as_deref().unwrap_or_default()
            );
        };
        let mut s = format!("; failure time {failure}");
        if let Some(t) = self.failure_tolerance {
            let _ = write!(s, " to {t:.2e}");
        }
        if let Some(t) = self.failure_extrapolated {
            let _ = write!(s, ", extrapolated {t:.4}");
        }
        let times: Vec<String> = self
            .failure_times
            .iter()
            .map(|t| t.map_or_else(|| "-".to_owned(), |t| format!("{t:.4}")))
            .collect();
        let _ = write!(s, " (levels {})", times.join(" "));
        if let Some(o) = self.outcome_verdict {
            let _ = write!(s, ", outcome {o}");
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenarios::{shaking_column, Shaking};

    #[test]
    fn a_row_s_study_gives_its_levels_its_band_and_cells_under_the_header() {
        // Figure 4.6's column at ω = 4 to t = 4, at Δt and Δt/2: both fail, within two
        // steps of Δt of each other.
        let scene = shaking_column(&Shaking::default()).unwrap();
        let options = RunOptions {
            t_end: Some(4.0),
            stop_at_failure: true,
            ..RunOptions::default()
        };
        let settings = Settings {
            levels: 1,
            ensemble: 0,
        };
        let c = RowConvergence::of(&scene, &options, settings, |r| r.observed.failure_time);
        assert_eq!(c.failure_times.len(), 2, "{c:?}");
        let [t0, t1] = [c.failure_times[0].unwrap(), c.failure_times[1].unwrap()];
        assert!((t0 - t1).abs() <= 2.0 * scene.solver.dt, "{c:?}");
        assert_eq!(
            (c.finest, c.spread),
            (Some(t1), Some([t0.min(t1), t0.max(t1)]))
        );
        assert_eq!(c.failure_verdict, Some(VerdictKind::Converged));
        assert_eq!(c.failure_rule, Some(Rule::Agreement));
        assert_eq!(c.csv_cells().len(), RowConvergence::CSV_HEADER.len());
        // Not asked: header and cells unchanged; asked for a row without: empty cells.
        let mut cells = vec!["1".to_owned()];
        RowConvergence::extend_cells(&mut cells, Some(&c), false);
        assert_eq!(cells, ["1"]);
        RowConvergence::extend_cells(&mut cells, None, true);
        assert_eq!(cells.len(), 1 + RowConvergence::CSV_HEADER.len());
        assert!(cells[1..].iter().all(String::is_empty));
        // Out-of-range settings: no verdict, the error named.
        let c = RowConvergence::of(
            &scene,
            &options,
            Settings {
                levels: 9,
                ensemble: 0,
            },
            |r| r.observed.failure_time,
        );
        assert_eq!(c.failure_verdict, None);
        assert!(
            c.error.as_deref().is_some_and(|e| e.contains("levels")),
            "{c:?}"
        );
    }
}
