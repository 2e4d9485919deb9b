//! Values written as text, as a user types them: angles in radians by default, `90deg`,
//! and multiples of π such as `3pi/2`; values of any kind in the same forms (a rate
//! `-6pi`, [`parse_value`]); plain finite numbers; comma-separated lists; and
//! decimal-exact `A:B:STEP` ranges and lists of them for sweeps, whose A, B and STEP take
//! the forms of a single value (`10deg:40deg:10deg`).
//!
//! docs/architecture.md (Conventions): every API takes radians; the command line also accepts
//! degrees and π-fractions because that is how the thesis states its examples.
//!
//! Two kinds of angle: an [`Angle`] may have any size (a side of a rolled path given as
//! the angle it turns the body, `3pi`), while a [`RotationAngle`] (the angle of a
//! rotation, an inclination, a heading) refuses a bare number beyond ±2π, which is
//! almost always degrees written without `deg`:
//!
//! ```
//! use input::text::{parse_angle, parse_rotation_angle};
//!
//! assert_eq!(parse_angle("90")?, 90.0);
//! assert_eq!(
//!     parse_rotation_angle("90").unwrap_err(),
//!     "90 rad is more than 2π: write 90deg for degrees, or give radians"
//! );
//! assert!((parse_rotation_angle("90deg")? - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
//! assert!((parse_rotation_angle("3pi")? - 3.0 * std::f64::consts::PI).abs() < 1e-15);
//! # Ok::<(), String>(())
//! ```

use std::f64::consts::{PI, TAU};
use std::str::FromStr;

/// An angle in radians parsed from text.
///
/// Accepted forms: `1.25` (radians), `90deg`, `-45deg`, `pi`, `-pi/4`, `3pi/2`,
/// `0.5pi`, `2*pi/3`, `π/2`. Non-finite values are rejected; any size is accepted (for
/// a rotation angle that refuses bare degrees, see [`RotationAngle`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Angle(pub f64);

impl FromStr for Angle {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_angle(s).map(Angle)
    }
}

/// An angle of a rotation, an inclination or a heading, in radians, parsed from text
/// ([`parse_rotation_angle`]): the forms of [`Angle`], but a bare number (no `deg`, no
/// `pi`) larger than 2π in size is refused as degrees written without `deg`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RotationAngle(pub f64);

impl FromStr for RotationAngle {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_rotation_angle(s).map(RotationAngle)
    }
}

/// Parses one rotation angle (see [`RotationAngle`]) to radians: [`parse_angle`], then a
/// bare number beyond ±2π is refused with the explanation every angle flag of the
/// command line gives ("90 rad is more than 2π: write 90deg for degrees, or give
/// radians"). Degrees (`720deg`) and multiples of π (`3pi`) may be of any size.
///
/// # Errors
/// As [`parse_angle`], and a bare number larger than 2π in size.
pub fn parse_rotation_angle(text: &str) -> Result<f64, String> {
    let value = parse_angle(text)?;
    let s = text.trim().to_ascii_lowercase();
    let bare = !(s.ends_with("deg") || s.contains("pi") || s.contains('π'));
    if bare && value.abs() > TAU {
        let t = text.trim();
        let size = if value < 0.0 { " in size" } else { "" };
        return Err(format!(
            "{t} rad is more than 2π{size}: write {t}deg for degrees, or give radians"
        ));
    }
    Ok(value)
}

/// Parses a comma-separated list of rotation angles ([`parse_rotation_angle`]).
///
/// # Errors
/// The first entry that is not a rotation angle.
pub fn parse_rotation_angle_list(text: &str) -> Result<Vec<f64>, String> {
    text.split(',').map(parse_rotation_angle).collect()
}

/// Parses one angle (see [`Angle`]) to radians.
///
/// # Errors
/// A message naming the offending text when it is not an angle or not finite.
pub fn parse_angle(text: &str) -> Result<f64, String> {
    Term::read(text)
        .and_then(|t| t.value())
        .map_err(|p| p.message(text, "angle", "use radians, 90deg or 3pi/2"))
}

/// Parses one value as a user types it: a plain number (`1.5`, `-2e-3`), a multiple of π
/// (`2pi`, `-6π`, `pi/6`, `3*pi/2`), or degrees, converted to radians (`30deg`). The
/// forms are those of [`parse_angle`], so that a rate may be written as `2pi` and every
/// sweep value as the single values of the same flag.
///
/// # Errors
/// A message naming the offending text when it is none of these or not finite.
pub fn parse_value(text: &str) -> Result<f64, String> {
    Term::read(text)
        .and_then(|t| t.value())
        .map_err(|p| p.message(text, "value", VALUE_FORMS))
}

/// The forms [`parse_value`] reads, for its error messages.
const VALUE_FORMS: &str =
    "use a number, a multiple of π such as 2pi or pi/6, or degrees such as 30deg";

/// What is wrong with a typed value; worded by the parser that read it ([`Problem::message`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Problem {
    Empty,
    Unreadable,
    DividesByZero,
    NotFinite,
}

impl Problem {
    /// The message for `text`, a `what` (`angle`), with `hint` on the forms accepted.
    fn message(self, text: &str, what: &str, hint: &str) -> String {
        match self {
            Self::Empty => format!("empty {what}"),
            Self::Unreadable => format!("cannot read {what} '{text}' ({hint})"),
            Self::DividesByZero => format!("{what} '{text}' divides by zero"),
            Self::NotFinite => format!("{what} '{text}' is not finite"),
        }
    }
}

/// The unit a typed value's coefficient is in: none, π/d, or degrees (to radians).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Unit {
    Plain,
    Pi { divisor: f64 },
    Degrees,
}

impl Unit {
    /// The value of `coefficient` of this unit, in radians for angles.
    fn apply(self, coefficient: f64) -> f64 {
        match self {
            Self::Plain => coefficient,
            Self::Pi { divisor } => coefficient * PI / divisor,
            Self::Degrees => coefficient.to_radians(),
        }
    }
}

/// A typed value split into its decimal coefficient (as text) and its unit: `3pi/2` is
/// 3 of π/2, `30deg` is 30 of degrees. A range steps in coefficients when its three
/// values share a unit, so that `10deg:40deg:10deg` holds exactly what `20deg` reads as.
#[derive(Debug, Clone, PartialEq)]
struct Term {
    coefficient: String,
    unit: Unit,
}

impl Term {
    /// `[k]deg`, `[k][*]pi[/d]` (k, d plain numbers) or a plain number.
    fn read(text: &str) -> Result<Self, Problem> {
        let s = text
            .trim()
            .to_ascii_lowercase()
            .replace('π', "pi")
            .replace(' ', "");
        if s.is_empty() {
            return Err(Problem::Empty);
        }
        if let Some(deg) = s.strip_suffix("deg") {
            return Ok(Self::of(deg, Unit::Degrees));
        }
        let Some(pos) = s.find("pi") else {
            return Ok(Self::of(&s, Unit::Plain));
        };
        let coefficient = match s[..pos].trim_end_matches('*') {
            "" | "+" => "1",
            "-" => "-1",
            head => head,
        };
        let divisor = match &s[pos + 2..] {
            "" => 1.0,
            tail => number(tail.strip_prefix('/').ok_or(Problem::Unreadable)?)?,
        };
        if divisor == 0.0 {
            return Err(Problem::DividesByZero);
        }
        Ok(Self::of(coefficient, Unit::Pi { divisor }))
    }

    fn of(coefficient: &str, unit: Unit) -> Self {
        Self {
            coefficient: coefficient.to_owned(),
            unit,
        }
    }

    /// The value it stands for, finite.
    fn value(&self) -> Result<f64, Problem> {
        let value = self.unit.apply(number(&self.coefficient)?);
        if value.is_finite() {
            Ok(value)
        } else {
            Err(Problem::NotFinite)
        }
    }
}

/// A plain finite number.
fn number(s: &str) -> Result<f64, Problem> {
    let v: f64 = s.parse().map_err(|_| Problem::Unreadable)?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(Problem::NotFinite)
    }
}

/// Parses a comma-separated list of angles.
///
/// # Errors
/// The first entry that is not an angle.
pub fn parse_angle_list(text: &str) -> Result<Vec<f64>, String> {
    text.split(',').map(parse_angle).collect()
}

/// Parses one plain finite number (no units).
///
/// # Errors
/// When `text` is not a finite number.
pub fn parse_finite(text: &str) -> Result<f64, String> {
    let v: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("cannot read number '{text}'"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("'{text}' is not a finite number"))
    }
}

/// Parses a comma-separated list of plain finite numbers.
///
/// # Errors
/// The first entry that is not a finite number.
pub fn parse_number_list(text: &str) -> Result<Vec<f64>, String> {
    text.split(',').map(parse_finite).collect()
}

/// Parses `A:B:STEP` into the values A, A+STEP, … up to B inclusive, or a single value
/// into one value. A, B, STEP and the single value take every form of [`parse_value`]:
/// `0.5`, `2pi`, `pi/6`, `30deg` (`10deg:40deg:10deg`, `0:2pi:pi/4`).
///
/// The values are decimal-exact: when A, B and STEP are decimals of one unit (at most 15
/// significant digits and 22 decimals, the usual case), each value is computed in integers
/// scaled by a power of ten and divided once at the end, so it is the number its decimal
/// text reads as: `0:1:0.05` contains `0.15` itself, not `0.15000000000000002`,
/// `10deg:40deg:10deg` contains what `20deg` reads as, and B is reached exactly when it
/// lies on the grid. Other values (`1e-30:1e-29:1e-31`, `pi/6:pi/2:pi/6`) are stepped in
/// floating point and B is reached within 1e-9 of a step.
///
/// # Errors
/// Unreadable or non-finite values (a single value is refused as [`parse_value`] refuses
/// it), a step of the wrong sign or zero, or more than ten million points.
pub fn parse_range(text: &str) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = text.split(':').collect();
    match parts.as_slice() {
        [single] => Ok(vec![parse_value(single)?]),
        [a, b, step] => {
            let term = |part: &str| {
                let t = Term::read(part)?;
                t.value().map(|v| (t, v))
            };
            let bad = |part: &str, p: Problem| {
                let what = format!("'{}' in range '{text}'", part.trim());
                match p {
                    Problem::Unreadable | Problem::Empty => {
                        format!("cannot read {what} (A, B and STEP: {VALUE_FORMS})")
                    }
                    Problem::DividesByZero => format!("{what} divides by zero"),
                    Problem::NotFinite => format!("range '{text}' has a non-finite value"),
                }
            };
            let read = |part: &str| term(part).map_err(|p| bad(part, p));
            range_values(text, read(a)?, read(b)?, read(step)?)
        }
        _ => Err(format!("cannot read range '{text}' (expected A:B:STEP)")),
    }
}

/// The values of the range `text` from its read A, B and STEP.
fn range_values(
    text: &str,
    (a_term, a): (Term, f64),
    (b_term, b): (Term, f64),
    (step_term, step): (Term, f64),
) -> Result<Vec<f64>, String> {
    if step == 0.0 || (b - a) * step < 0.0 {
        return Err(format!(
            "range '{text}': STEP must be non-zero and point from A to B"
        ));
    }
    let too_many = || format!("range '{text}' has more than ten million points");
    let one_unit = a_term.unit == b_term.unit && b_term.unit == step_term.unit;
    let grid = one_unit
        .then(|| {
            DecimalGrid::new(
                &a_term.coefficient,
                &b_term.coefficient,
                &step_term.coefficient,
            )
        })
        .flatten();
    if let Some(grid) = grid {
        let n = grid.count();
        if n > MAX_RANGE_POINTS {
            return Err(too_many());
        }
        let unit = a_term.unit;
        return Ok((0..=n).map(|k| unit.apply(grid.value(k))).collect());
    }
    let n = ((b - a) / step + 1e-9).floor();
    if n > MAX_RANGE_POINTS as f64 {
        return Err(too_many());
    }
    // n is a checked non-negative count below 1e7, so the cast is exact.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    let n = n as usize;
    Ok((0..=n).map(|i| a + step * i as f64).collect())
}

/// Largest number of steps a range may take (ten million).
const MAX_RANGE_POINTS: usize = 10_000_000;

/// Whether any value of `text` (values as [`parse_values`] reads them) is written in
/// degrees (`30deg`): an angle unit, which a quantity that is not an angle refuses.
#[must_use]
pub fn in_degrees(text: &str) -> bool {
    text.split([',', ':'])
        .any(|t| Term::read(t).is_ok_and(|t| t.unit == Unit::Degrees && t.value().is_ok()))
}

/// Parses the values of a sweep: comma-separated items, each an `A:B:STEP` range or one
/// value ([`parse_range`]), in the order given: `0.1,0.2,0.5`, `0:1:0.25`,
/// `0.1:0.3:0.1,0.5`, `pi/6,30deg:60deg:15deg`.
///
/// # Errors
/// The first item that is not a range or a value, or an empty item.
pub fn parse_values(text: &str) -> Result<Vec<f64>, String> {
    let mut out = Vec::new();
    for item in text.split(',') {
        if item.trim().is_empty() {
            return Err(format!(
                "empty value in '{text}' (expected A:B:STEP, one value or a comma list of them)"
            ));
        }
        out.extend(parse_range(item)?);
    }
    Ok(out)
}

/// A range's A, B and STEP as integers over one power of ten: A = a/10^d, STEP = s/10^d.
struct DecimalGrid {
    a: i64,
    b: i64,
    step: i64,
    scale: f64,
}

impl DecimalGrid {
    /// The grid of three decimals, or `None` when one is not a plain decimal that fits
    /// (more than 15 significant digits, or more than 22 decimals).
    fn new(a: &str, b: &str, step: &str) -> Option<Self> {
        let (a, b, step) = (decimal(a)?, decimal(b)?, decimal(step)?);
        let d = a.1.max(b.1).max(step.1);
        if d > 22 {
            return None;
        }
        // Every integer below 2^53 is a double, so the products and the final division
        // (one correctly rounded operation) are exact up to that division.
        let limit = 1i128 << 53;
        let scaled = |(m, e): (i128, u32)| -> Option<i64> {
            let v = m.checked_mul(10i128.checked_pow(d - e)?)?;
            (v.abs() < limit).then(|| i64::try_from(v).ok()).flatten()
        };
        Some(Self {
            a: scaled(a)?,
            b: scaled(b)?,
            step: scaled(step)?,
            // d ≤ 22: 10^d is a double exactly.
            scale: 10f64.powi(i32::try_from(d).ok()?),
        })
    }

    /// The number of steps from A to B (B included when it lies on the grid).
    fn count(&self) -> usize {
        // Same signs checked by the caller: the quotient is non-negative.
        usize::try_from((self.b - self.a) / self.step).unwrap_or(usize::MAX)
    }

    /// A + k·STEP, rounded once.
    fn value(&self, k: usize) -> f64 {
        // k ≤ ten million and |STEP|, |B − A| < 2^53: the integer stays below 2^77 in
        // i128 and, being between A and B, below 2^53 in magnitude.
        let n = i128::from(self.a) + i128::from(self.step) * k as i128;
        n as f64 / self.scale
    }
}

/// A plain decimal `[-+]digits[.digits][e[-+]digits]` as (m, d) with value m/10^d and
/// d ≥ 0; `None` for anything else or more than 15 significant digits.
fn decimal(text: &str) -> Option<(i128, u32)> {
    let t = text.trim();
    let (mantissa, exponent) = match t.find(['e', 'E']) {
        Some(i) => (&t[..i], t[i + 1..].parse::<i32>().ok()?),
        None => (t, 0),
    };
    let (negative, digits) = match mantissa.as_bytes().first()? {
        b'-' => (true, &mantissa[1..]),
        b'+' => (false, &mantissa[1..]),
        _ => (false, mantissa),
    };
    let (whole, frac) = digits.split_once('.').unwrap_or((digits, ""));
    if whole.is_empty() && frac.is_empty() {
        return None;
    }
    if !whole
        .bytes()
        .chain(frac.bytes())
        .all(|c| c.is_ascii_digit())
    {
        return None;
    }
    let all = format!("{whole}{frac}");
    let significant = all.trim_start_matches('0');
    if significant.len() > 15 {
        return None;
    }
    let m: i128 = if significant.is_empty() {
        0
    } else {
        significant.parse().ok()?
    };
    let m = if negative { -m } else { m };
    // value = m · 10^(exponent − frac digits)
    let e = exponent.checked_sub(i32::try_from(frac.len()).ok()?)?;
    if e >= 0 {
        let m = m.checked_mul(10i128.checked_pow(u32::try_from(e).ok()?)?)?;
        Some((m, 0))
    } else {
        Some((m, e.unsigned_abs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn degrees_are_seen_in_any_value_of_a_list_or_range() {
        for text in ["30deg", "0.1,30deg", "0:90deg:10deg", " 5 DEG "] {
            assert!(in_degrees(text), "{text}");
        }
        for text in ["0.5", "pi/6", "0:2pi:pi/4", "1e-3,2", "deg"] {
            assert!(!in_degrees(text), "{text}");
        }
    }

    #[test]
    fn forms() {
        assert_relative_eq!(parse_angle("1.5").unwrap(), 1.5);
        assert_relative_eq!(parse_angle("90deg").unwrap(), PI / 2.0);
        assert_relative_eq!(parse_angle("-45deg").unwrap(), -PI / 4.0);
        assert_relative_eq!(parse_angle("3pi/2").unwrap(), 1.5 * PI);
        assert_relative_eq!(parse_angle("pi").unwrap(), PI);
        assert_relative_eq!(parse_angle("-pi/4").unwrap(), -PI / 4.0);
        assert_relative_eq!(parse_angle("2*pi/3").unwrap(), 2.0 * PI / 3.0);
        assert_relative_eq!(parse_angle("0.5pi").unwrap(), PI / 2.0);
        assert_relative_eq!(parse_angle("π/2").unwrap(), PI / 2.0);
    }

    #[test]
    fn rejects() {
        for bad in ["", "nan", "inf", "pi/0", "abc", "3pi2", "1e999", "NaNdeg"] {
            assert!(parse_angle(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn rotation_angles_refuse_bare_degrees() {
        for ok in [
            "6.28", "-6.28", "90deg", "-720deg", "3pi", "-4pi/3", "7π/2", "0",
        ] {
            assert!(parse_rotation_angle(ok).is_ok(), "{ok}");
        }
        assert_eq!(
            parse_rotation_angle(" 45 ").unwrap_err(),
            "45 rad is more than 2π: write 45deg for degrees, or give radians"
        );
        assert_eq!(
            parse_rotation_angle("-90").unwrap_err(),
            "-90 rad is more than 2π in size: write -90deg for degrees, or give radians"
        );
        assert!(parse_rotation_angle("abc").is_err());
        assert_eq!(
            "7".parse::<RotationAngle>(),
            Err(parse_rotation_angle("7").unwrap_err())
        );
        assert_eq!("7".parse::<Angle>(), Ok(Angle(7.0)));
        assert_eq!(parse_rotation_angle_list("0,90deg,pi").unwrap().len(), 3);
        assert!(parse_rotation_angle_list("0,90,pi").is_err());
    }

    #[test]
    fn lists() {
        assert_eq!(parse_angle_list("0,pi/2,90deg").unwrap().len(), 3);
        assert!(parse_number_list("1,NaN").is_err());
    }

    #[test]
    fn ranges() {
        assert_eq!(parse_range("1:2:0.5").unwrap(), vec![1.0, 1.5, 2.0]);
        assert_eq!(parse_range("3").unwrap(), vec![3.0]);
        assert_eq!(parse_range("0:1:0.1").unwrap().len(), 11);
        assert_eq!(parse_range("2:1:-0.5").unwrap(), vec![2.0, 1.5, 1.0]);
        for bad in [
            "1:2:0",
            "1:2:-1",
            "a:b:c",
            "1:2",
            "1:nan:1",
            "1:2:3:4",
            "30deg:10deg:10deg",
        ] {
            assert!(parse_range(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn ranges_are_decimal_exact() {
        let twentieths = parse_range("0:1:0.05").unwrap();
        assert_eq!(twentieths.len(), 21);
        assert!(twentieths.contains(&0.15) && twentieths.contains(&0.35));
        assert_eq!(twentieths[20], 1.0);
        // Every value is the double its decimal text reads as.
        for (k, v) in twentieths.iter().enumerate() {
            let text = format!("{}.{:02}", k * 5 / 100, k * 5 % 100);
            assert_eq!(*v, text.parse::<f64>().unwrap(), "{text}");
        }
        assert_eq!(parse_range("0.1:0.3:0.1").unwrap(), vec![0.1, 0.2, 0.3]);
        assert_eq!(parse_range("0.3:0.1:-0.1").unwrap(), vec![0.3, 0.2, 0.1]);
        assert_eq!(
            parse_range("-0.2:0.2:0.1").unwrap(),
            vec![-0.2, -0.1, 0.0, 0.1, 0.2]
        );
        assert_eq!(
            parse_range("1e-3:3e-3:1e-3").unwrap(),
            vec![0.001, 0.002, 0.003]
        );
        assert_eq!(parse_range("1:10:4").unwrap(), vec![1.0, 5.0, 9.0]);
        assert_eq!(
            parse_range("1.5e2:2e2:25").unwrap(),
            vec![150.0, 175.0, 200.0]
        );
        assert_eq!(parse_range(".5:1.:.25").unwrap(), vec![0.5, 0.75, 1.0]);
        // Beyond plain decimals: floating-point steps, B within 1e-9 of a step.
        assert_eq!(parse_range("1e-30:3e-30:1e-30").unwrap().len(), 3);
        assert_eq!(
            parse_range("0:0.3333333333333333333:0.1111111111111111111")
                .unwrap()
                .len(),
            4
        );
        assert!(parse_range("0:1e8:1e-3").is_err(), "more than ten million");
    }

    #[test]
    fn ranges_take_the_forms_of_a_single_value() {
        // Each value of a range is the number its single value reads as.
        let degrees = parse_range("10deg:40deg:10deg").unwrap();
        let singles: Vec<f64> = ["10deg", "20deg", "30deg", "40deg"]
            .iter()
            .map(|t| parse_value(t).unwrap())
            .collect();
        assert_eq!(degrees, singles);
        assert_eq!(parse_range("30deg").unwrap(), vec![PI / 6.0]);
        assert_eq!(parse_range("pi/6").unwrap(), vec![PI / 6.0]);
        assert_eq!(parse_range("2pi").unwrap(), vec![2.0 * PI]);
        assert_eq!(parse_range("-6pi").unwrap(), vec![-6.0 * PI]);
        assert_eq!(
            parse_range("2pi:6pi:2pi").unwrap(),
            vec![2.0 * PI, 4.0 * PI, 6.0 * PI]
        );
        let sixths = parse_range("pi/6:pi/2:pi/6").unwrap();
        assert_eq!(sixths.len(), 3);
        assert_relative_eq!(sixths[2], PI / 2.0, max_relative = 1e-15);
        assert_eq!(parse_range("0:pi:pi/4").unwrap().len(), 5);
        assert_eq!(
            parse_values("pi/6,30deg:60deg:15deg").unwrap().len(),
            4,
            "a list mixes single values and ranges of any form"
        );
    }

    #[test]
    fn a_bad_single_value_is_not_called_a_range() {
        let single = parse_range("abc").unwrap_err();
        assert!(!single.contains("A:B:STEP"), "{single}");
        assert!(
            single.contains("'abc'") && single.contains("30deg"),
            "{single}"
        );
        assert!(!parse_values("1,x").unwrap_err().contains("A:B:STEP"));
        let part = parse_range("1:x:1").unwrap_err();
        assert!(part.contains("'x' in range '1:x:1'"), "{part}");
        assert_eq!(
            parse_range("1:2").unwrap_err(),
            "cannot read range '1:2' (expected A:B:STEP)"
        );
        assert!(parse_range("0:1:pi/0")
            .unwrap_err()
            .contains("divides by zero"));
    }

    #[test]
    fn values_read_rates_as_multiples_of_pi() {
        assert_eq!(parse_value("-6pi").unwrap(), -6.0 * PI);
        assert_eq!(parse_value("-6π").unwrap(), parse_angle("-6pi").unwrap());
        assert_eq!(parse_value(" 1.5 ").unwrap(), 1.5);
        assert_eq!(parse_value("30deg").unwrap(), 30f64.to_radians());
        assert_eq!(parse_value("").unwrap_err(), "empty value");
        assert_eq!(parse_value("inf").unwrap_err(), "value 'inf' is not finite");
        assert!(parse_value("abc")
            .unwrap_err()
            .starts_with("cannot read value 'abc'"));
    }

    #[test]
    fn value_lists_mix_numbers_and_ranges() {
        assert_eq!(parse_values("0.1,0.2,0.5").unwrap(), vec![0.1, 0.2, 0.5]);
        assert_eq!(
            parse_values("0.1:0.3:0.1, 1").unwrap(),
            vec![0.1, 0.2, 0.3, 1.0]
        );
        assert_eq!(parse_values("-1").unwrap(), vec![-1.0]);
        for bad in ["", "1,", ",1", "1,,2", "1,a", "1:2:0,3", "nan"] {
            assert!(parse_values(bad).is_err(), "{bad}");
        }
    }
}
