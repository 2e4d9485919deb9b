//! The caption line of a block-stack figure: the numerical choices its curves depend on
//! beyond the physics, so that a picture read on its own says how it was computed. A
//! run's motion depends on Δt and on the prox parameter; an exploration's tree (and the
//! bands of a sweep over explored motions) also on the branch rule, which decides what
//! a fork records. The caption goes on its own line under the title ([`Numerics::under`]),
//! which [`fit_title`](crate::plot::fit_title) keeps as a line of its own.

use nsga::{BranchRule, Prox};

/// How the runs of a figure chose their step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Step {
    /// One Δt for every run.
    Fixed(f64),
    /// N steps per base period: Δt = 2π/(Nω), ω the swept frequency.
    PerPeriod(f64),
    /// Each run its own Δt, from the first to the last: a study over Δt.
    Range(f64, f64),
}

/// The numerical choices one figure shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Numerics {
    /// The branch rule, where it decides what the figure shows (an exploration, a sweep
    /// over explored motions); `None` for plain runs, whose motion it does not change.
    pub rule: Option<BranchRule>,
    /// The step.
    pub step: Step,
    /// The prox parameter.
    pub prox: Prox,
}

impl Numerics {
    /// Plain runs with step `dt` and prox parameter `prox` (no branch rule).
    #[must_use]
    pub fn run(dt: f64, prox: Prox) -> Self {
        Self {
            rule: None,
            step: Step::Fixed(dt),
            prox,
        }
    }

    /// Runs with the steps `dts`: one Δt when they share it, else the range from the
    /// largest to the smallest (a scene sweep over ω at fixed steps per period).
    #[must_use]
    pub fn of_steps(dts: &[f64], prox: Prox) -> Self {
        let largest = dts.iter().copied().fold(f64::NAN, f64::max);
        let smallest = dts.iter().copied().fold(f64::NAN, f64::min);
        let step = if largest == smallest {
            Step::Fixed(largest)
        } else {
            Step::Range(largest, smallest)
        };
        Self {
            rule: None,
            step,
            prox,
        }
    }

    /// The same with the branch rule, which applies to what it shows.
    #[must_use]
    pub fn with_rule(self, rule: BranchRule) -> Self {
        Self {
            rule: Some(rule),
            ..self
        }
    }

    /// The caption, e.g. "self-consistent rule, Δt = 0.01, prox scaled (α = 1)" or
    /// "Δt = 2π/(100ω), prox r = 0.3": the rule as the command line spells it, Δt to four
    /// significant digits, the prox as scaled (α) or constant (r).
    #[must_use]
    pub fn caption(&self) -> String {
        let rule = self.rule.map(|r| match r {
            BranchRule::SelfConsistent => "self-consistent rule".to_owned(),
            BranchRule::Converged => "converged rule (the thesis's count)".to_owned(),
        });
        let step = match self.step {
            Step::Fixed(dt) => format!("Δt = {}", significant(dt)),
            Step::PerPeriod(n) => format!("Δt = 2π/({}ω)", significant(n)),
            Step::Range(first, last) => {
                format!("Δt = {} … {}", significant(first), significant(last))
            }
        };
        let prox = match self.prox {
            Prox::Scaled(alpha) => format!("prox scaled (α = {})", significant(alpha)),
            Prox::Constant(r) => format!("prox r = {}", significant(r)),
        };
        rule.into_iter()
            .chain([step, prox])
            .collect::<Vec<_>>()
            .join(", ")
    }

    /// `title` with the caption on a line of its own under it.
    #[must_use]
    pub fn under(&self, title: &str) -> String {
        format!("{title}\n{}", self.caption())
    }
}

/// `title` with `more` appended to its first line, before the caption if it has one: a
/// frame's time or a panel's name goes with the headline, the caption stays under it.
#[must_use]
pub fn extend_headline(title: &str, more: &str) -> String {
    match title.split_once('\n') {
        Some((headline, caption)) => format!("{headline}{more}\n{caption}"),
        None => format!("{title}{more}"),
    }
}

/// `x` to four significant digits without trailing zeros (0.02222, 0.01, 100), in
/// exponent form outside 10⁻³ ≤ |x| < 10⁵ (6.25e-5).
fn significant(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor();
    if !(-3.0..5.0).contains(&magnitude) {
        let s = format!("{x:.3e}");
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{}e{exponent}", trim_zeros(mantissa));
    }
    // Four significant digits: 3 − ⌊log₁₀|x|⌋ decimals, none for |x| ≥ 1000.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let decimals = (3.0 - magnitude).max(0.0) as usize;
    trim_zeros(&format!("{x:.decimals$}")).to_owned()
}

/// "0.0100" → "0.01", "2.500" → "2.5", "100" → "100".
fn trim_zeros(s: &str) -> &str {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.')
    } else {
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn captions_name_the_rule_the_step_and_the_prox() {
        let run = Numerics::run(0.01, Prox::Scaled(1.0));
        assert_eq!(run.caption(), "Δt = 0.01, prox scaled (α = 1)");
        let explored =
            Numerics::run(2.0 / 90.0, Prox::Constant(0.3)).with_rule(BranchRule::Converged);
        assert_eq!(
            explored.caption(),
            "converged rule (the thesis's count), Δt = 0.02222, prox r = 0.3"
        );
        let swept = Numerics {
            rule: Some(BranchRule::SelfConsistent),
            step: Step::PerPeriod(100.0),
            prox: Prox::Scaled(0.5),
        };
        assert_eq!(
            swept.caption(),
            "self-consistent rule, Δt = 2π/(100ω), prox scaled (α = 0.5)"
        );
        let study = Numerics {
            step: Step::Range(0.01, 6.25e-4),
            ..run
        };
        assert_eq!(study.caption(), "Δt = 0.01 … 6.25e-4, prox scaled (α = 1)");
        assert_eq!(Numerics::of_steps(&[0.01, 0.01], Prox::Scaled(1.0)), run);
        let swept = Numerics::of_steps(&[0.005, 0.02, 0.01], Prox::Scaled(1.0));
        assert_eq!(swept.step, Step::Range(0.02, 0.005));
        assert_eq!(run.under("Lire"), "Lire\nΔt = 0.01, prox scaled (α = 1)");
        let frame = extend_headline(&run.under("Lire"), ", t = 6.40");
        assert_eq!(frame, "Lire, t = 6.40\nΔt = 0.01, prox scaled (α = 1)");
        assert_eq!(
            extend_headline("Lire", ": top block angle"),
            "Lire: top block angle"
        );
    }

    #[test]
    fn numbers_keep_four_significant_digits() {
        assert_eq!(significant(0.01), "0.01");
        assert_eq!(significant(2.0 * std::f64::consts::PI / 400.0), "0.01571");
        assert_eq!(significant(100.0), "100");
        assert_eq!(significant(12_345.6), "12346");
        assert_eq!(significant(1e-5), "1e-5");
        assert_eq!(significant(0.3), "0.3");
    }
}
