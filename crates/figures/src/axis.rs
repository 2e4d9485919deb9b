//! Tick marks and their labels, chosen here rather than by plotters so that every axis
//! reads cleanly: linear axes step by 1, 2 or 5 times a power of ten and print exactly
//! the decimals that step needs; logarithmic axes put their labels on decades (`1e-8`,
//! `1e-6`, …) and never print a rounding artefact such as `9999999e-5`.
//!
//! A [`Ticks`] lives in *display* coordinates: the value itself on a linear axis, its
//! base-10 logarithm on a logarithmic one (the plot draws log₁₀ of the data on a linear
//! scale, so the ticks are exactly where they are said to be).
//!
//! ```
//! use figures::axis::{format_decade, Ticks};
//!
//! assert_eq!(format_decade(-6), "1e-6");
//! let t = Ticks::log(-8.3, -3.2);
//! assert_eq!(t.labels, ["1e-8", "1e-7", "1e-6", "1e-5", "1e-4"]);
//! let t = Ticks::linear(0.0, 1.03);
//! assert_eq!(t.labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
//! ```

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};

/// The tick marks of one axis in display coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct Ticks {
    /// Labelled ticks (bold grid lines), in increasing order.
    pub major: Vec<f64>,
    /// Unlabelled ticks between them (light grid lines).
    pub minor: Vec<f64>,
    /// One label per major tick.
    pub labels: Vec<String>,
}

/// About how many labelled ticks an axis gets.
pub(crate) const TARGET_TICKS: f64 = 6.0;

/// At most this many labelled decades on a logarithmic axis.
const MAX_DECADES: i32 = 8;

/// `1e{e}`: the label of the decade 10^e, e.g. `1e-6`.
#[must_use]
pub fn format_decade(e: i32) -> String {
    format!("1e{e}")
}

/// The label of m·10^e on a logarithmic axis: `5e-6`, or in plain decimals (`0.05`,
/// `200`) when `plain`.
fn format_log_value(m: i32, e: i32, plain: bool) -> String {
    if !plain {
        return format!("{m}e{e}");
    }
    let decimals = usize::try_from(-e).unwrap_or(0);
    format!("{:.*}", decimals, f64::from(m) * 10f64.powi(e))
}

impl Ticks {
    /// Ticks of a linear axis over [`lo`, `hi`]: steps of 1, 2 or 5 × 10^k, about six of
    /// them, labelled with the decimals the step needs (scientific notation for very
    /// large or very small values).
    #[must_use]
    pub fn linear(lo: f64, hi: f64) -> Self {
        Self::linear_about(lo, hi, TARGET_TICKS)
    }

    /// [`Self::linear`] with about `target` labelled ticks (at least one): the step is
    /// at least the range over `target`, so an axis of `n` pixels asked for at most
    /// n/d ticks has its labels at least d pixels apart.
    #[must_use]
    pub fn linear_about(lo: f64, hi: f64, target: f64) -> Self {
        // A range too narrow for its step to be a normal number (or empty) gets the
        // unit range about its start: a subnormal step has no power of ten to round to,
        // and its tick count overflows.
        let (lo, hi) = if hi > lo && ((hi - lo) / target.max(1.0)).is_normal() {
            (lo, hi)
        } else {
            (lo - 0.5, lo + 0.5)
        };
        let raw = (hi - lo) / target.max(1.0);
        let exp = raw.log10().floor();
        let mag = 10f64.powf(exp);
        let (mant, minor_parts) = match raw / mag {
            r if r <= 1.0 => (1.0, 5.0),
            r if r <= 2.0 => (2.0, 4.0),
            r if r <= 5.0 => (5.0, 5.0),
            _ => (10.0, 5.0),
        };
        let step = mant * mag;
        let minor_step = step / minor_parts;
        // Ticks are k·step for integers k: no accumulated rounding.
        // (±1e-9: 0.35 / 0.05 comes out a hair below 7.)
        let (k0, k1) = ((lo / step - 1e-9).ceil(), (hi / step + 1e-9).floor());
        #[allow(clippy::cast_possible_truncation)]
        let major: Vec<f64> = (k0 as i64..=k1 as i64)
            .map(|k| snap(k as f64 * step, step))
            .collect();
        let (m0, m1) = (
            (lo / minor_step - 1e-9).ceil(),
            (hi / minor_step + 1e-9).floor(),
        );
        #[allow(clippy::cast_possible_truncation)]
        let minor: Vec<f64> = (m0 as i64..=m1 as i64)
            .map(|k| k as f64 * minor_step)
            .filter(|v| major.iter().all(|m| (m - v).abs() > 0.25 * minor_step))
            .collect();
        let biggest = lo.abs().max(hi.abs());
        // (+1e-9: log10(0.1) may come out a hair below −1.)
        let step_exp = (step.log10() + 1e-9).floor();
        let labels = if biggest >= 1e6 || step < 1e-4 {
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let digits = (biggest.log10().floor() - step_exp).max(0.0) as usize;
            major.iter().map(|v| scientific(*v, digits)).collect()
        } else {
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let decimals = (-step_exp).max(0.0) as usize;
            major
                .iter()
                .map(|v| {
                    let s = format!("{v:.decimals$}");
                    if s.trim_start_matches(['-', '0', '.']).is_empty() {
                        s.trim_start_matches('-').to_owned()
                    } else {
                        s
                    }
                })
                .collect()
        };
        Self {
            major,
            minor,
            labels,
        }
    }

    /// Ticks of a logarithmic axis whose display range is [`lo`, `hi`] (base-10
    /// logarithms of the values). Spanning two decades or more: labels on the decades
    /// (every second or third one on very wide ranges), light lines at 2…9 × 10^k.
    /// Narrower: labels at 1, 2, 5 × 10^k, or at every mantissa 1…9 when that gives too
    /// few, or linear ticks of the values as a last resort. Labels are plain decimals
    /// when every labelled value lies in [0.001, 1000], `1e-6`-style otherwise.
    #[must_use]
    pub fn log(lo: f64, hi: f64) -> Self {
        let (lo, hi) = if hi > lo {
            (lo, hi)
        } else {
            (lo - 0.5, lo + 0.5)
        };
        #[allow(clippy::cast_possible_truncation)]
        let (d0, d1) = (lo.ceil() as i32, hi.floor() as i32);
        let within = |v: f64| v >= lo - 1e-12 && v <= hi + 1e-12;
        let mantissa_points = |ms: &[i32]| -> Vec<(i32, i32)> {
            #[allow(clippy::cast_possible_truncation)]
            let (e0, e1) = (lo.floor() as i32, hi.ceil() as i32);
            (e0..=e1)
                .flat_map(|e| ms.iter().map(move |&m| (m, e)))
                .filter(|&(m, e)| within(f64::from(m).log10() + f64::from(e)))
                .collect()
        };
        let all_minor: Vec<(i32, i32)> = mantissa_points(&[2, 3, 4, 5, 6, 7, 8, 9]);
        // (mantissa, exponent) pairs: the labelled ticks and the light ones.
        type Marks = Vec<(i32, i32)>;
        let (labelled, minor): (Marks, Marks) = if d1 - d0 >= 1 {
            let count = d1 - d0 + 1;
            let every = (count + MAX_DECADES - 1) / MAX_DECADES;
            let decades: Vec<i32> = (d0..=d1).filter(|e| (e - d0) % every == 0).collect();
            let minor = if every == 1 {
                all_minor
            } else {
                (d0..=d1)
                    .filter(|e| !decades.contains(e))
                    .map(|e| (1, e))
                    .collect()
            };
            (decades.into_iter().map(|e| (1, e)).collect(), minor)
        } else {
            let one_two_five = mantissa_points(&[1, 2, 5]);
            if one_two_five.len() >= 3 {
                let minor = all_minor
                    .into_iter()
                    .filter(|p| !one_two_five.contains(p))
                    .collect();
                (one_two_five, minor)
            } else {
                let every = mantissa_points(&[1, 2, 3, 4, 5, 6, 7, 8, 9]);
                if every.len() < 2 {
                    return Self::log_of_linear(lo, hi);
                }
                (every, Vec::new())
            }
        };
        let plain = labelled.iter().all(|&(_, e)| (-3..=3).contains(&e));
        let at = |&(m, e): &(i32, i32)| f64::from(m).log10() + f64::from(e);
        Self {
            major: labelled.iter().map(at).collect(),
            minor: minor.iter().map(at).collect(),
            labels: labelled
                .iter()
                .map(|&(m, e)| format_log_value(m, e, plain))
                .collect(),
        }
    }

    /// Linear ticks of the values 10^lo … 10^hi, placed at their logarithms (a
    /// logarithmic axis narrower than the gap between two mantissas).
    fn log_of_linear(lo: f64, hi: f64) -> Self {
        let t = Self::linear(10f64.powf(lo), 10f64.powf(hi));
        let keep: Vec<usize> = (0..t.major.len()).filter(|&i| t.major[i] > 0.0).collect();
        Self {
            major: keep.iter().map(|&i| t.major[i].log10()).collect(),
            minor: Vec::new(),
            labels: keep.iter().map(|&i| t.labels[i].clone()).collect(),
        }
    }
}

/// `v` rounded to a multiple of `step` within rounding: −0 and 1e-17 become 0.
fn snap(v: f64, step: f64) -> f64 {
    if v.abs() < 1e-9 * step {
        0.0
    } else {
        v
    }
}

/// `v` as `m.mme±k` with `digits` decimals in the mantissa, e.g. `2.5e-5`, `0e0` for 0.
fn scientific(v: f64, digits: usize) -> String {
    if v == 0.0 {
        return "0".to_owned();
    }
    let s = format!("{v:.digits$e}");
    // `2.50e-5` → `2.5e-5`: trailing zeros of the mantissa say nothing.
    match s.split_once('e') {
        Some((m, e)) if m.contains('.') => {
            format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
        }
        _ => s,
    }
}

/// A plotters axis over a display range whose tick marks and labels are a [`Ticks`]:
/// plotters draws exactly these ticks with exactly these labels.
#[derive(Debug, Clone)]
pub(crate) struct TickedRange {
    range: std::ops::Range<f64>,
    ticks: Ticks,
}

impl TickedRange {
    pub(crate) fn new(range: std::ops::Range<f64>, ticks: Ticks) -> Self {
        Self { range, ticks }
    }
}

impl Ranged for TickedRange {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let f = (value - self.range.start) / (self.range.end - self.range.start);
        let pixels = f64::from(limit.1 - limit.0);
        #[allow(clippy::cast_possible_truncation)]
        let offset = (pixels * f + 1e-3).floor().clamp(-1e7, 1e7) as i32;
        limit.0 + offset
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.ticks.minor.clone()
        } else {
            self.ticks.major.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.range.clone()
    }
}

impl ValueFormatter<f64> for TickedRange {
    fn format_ext(&self, value: &f64) -> String {
        self.ticks
            .major
            .iter()
            .position(|m| (m - value).abs() <= 1e-9 * (1.0 + m.abs()))
            .map_or_else(String::new, |i| self.ticks.labels[i].clone())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decades_are_labelled_as_such() {
        assert_eq!(format_decade(-6), "1e-6");
        assert_eq!(format_decade(-8), "1e-8");
        assert_eq!(format_decade(3), "1e3");
        // The error axis of a work-precision diagram: 1e-9 … 1e-2.
        let t = Ticks::log(-9.2, -1.9);
        assert_eq!(
            t.labels,
            ["1e-9", "1e-8", "1e-7", "1e-6", "1e-5", "1e-4", "1e-3", "1e-2"]
        );
        for (m, e) in t.major.iter().zip(-9..) {
            assert!((m - f64::from(e)).abs() < 1e-12);
        }
        // Light lines at 2…9 × 10^k between them, none on a decade.
        assert!(t.minor.iter().all(|v| {
            let f = v - v.floor();
            f > 0.3 && f < 0.96
        }));
        assert!(t.minor.len() >= 7 * 8);
        assert!(t.labels.iter().all(|l| !l.contains("999")));
    }

    #[test]
    fn wide_log_ranges_label_every_few_decades() {
        let t = Ticks::log(-17.0, 1.0);
        assert!(t.labels.len() <= 8, "{:?}", t.labels);
        assert_eq!(t.labels[0], "1e-17");
        assert!(t.labels.iter().all(|l| l.starts_with("1e")));
    }

    #[test]
    fn log_axes_in_ordinary_ranges_print_plain_numbers() {
        let t = Ticks::log(-3.1, 1.2);
        assert_eq!(t.labels, ["0.001", "0.01", "0.1", "1", "10"]);
    }

    #[test]
    fn narrow_log_ranges_use_mantissas() {
        // 3e-5 … 4e-4: 5e-5, 1e-4, 2e-4.
        let t = Ticks::log(3e-5f64.log10(), 4e-4f64.log10());
        assert_eq!(t.labels, ["5e-5", "1e-4", "2e-4"]);
        // Narrower than 2…5: the values' own linear ticks.
        let t = Ticks::log(2.1f64.log10(), 3.9f64.log10());
        assert_eq!(t.labels, ["2.5", "3.0", "3.5"]);
        let t = Ticks::log(1.5f64.log10(), 4.5f64.log10());
        assert_eq!(t.labels, ["2", "3", "4"]);
    }

    #[test]
    fn linear_ticks_are_round_and_carry_the_needed_decimals() {
        assert_eq!(
            Ticks::linear(0.0, 90.0).labels,
            ["0", "20", "40", "60", "80"]
        );
        assert_eq!(
            Ticks::linear(-0.31, 0.29).labels,
            ["-0.3", "-0.2", "-0.1", "0.0", "0.1", "0.2"]
        );
        let t = Ticks::linear(0.1, 0.35);
        assert_eq!(t.labels, ["0.10", "0.15", "0.20", "0.25", "0.30", "0.35"]);
        assert_eq!(Ticks::linear(2e-5, 9e-5).labels[0], "2e-5");
        // No label is -0, no tick is off its multiple by rounding.
        let t = Ticks::linear(-1.0, 1.0);
        assert!(t.labels.contains(&"0.0".to_owned()));
        assert!(t.major.contains(&0.0));
        // Degenerate ranges still get ticks, a few: an empty one, one whose step would
        // be subnormal (`blocks painleve --mu-max 5e-324` overflowed the tick count),
        // an infinite one.
        for (lo, hi) in [(3.0, 3.0), (0.0, 5e-324), (0.0, f64::INFINITY)] {
            let n = Ticks::linear(lo, hi).major.len();
            assert!((1..=12).contains(&n), "{n} ticks over [{lo}, {hi}]");
        }
    }
}
