//! Values written as text, as a user types them: angles in radians by default, `90deg`,
//! and multiples of π such as `3pi/2`; finite numbers; comma-separated lists; and
//! decimal-exact `A:B:STEP` ranges and lists of them for sweeps.
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
    let s = text
        .trim()
        .to_ascii_lowercase()
        .replace('π', "pi")
        .replace(' ', "");
    if s.is_empty() {
        return Err("empty angle".into());
    }
    let value = if let Some(deg) = s.strip_suffix("deg") {
        parse_number(deg, text)?.to_radians()
    } else if let Some(pos) = s.find("pi") {
        parse_pi_fraction(&s, pos, text)?
    } else {
        parse_number(&s, text)?
    };
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("angle '{text}' is not finite"))
    }
}

/// `[k][*]pi[/d]`, with k and d plain numbers.
fn parse_pi_fraction(s: &str, pos: usize, original: &str) -> Result<f64, String> {
    let head = s[..pos].trim_end_matches('*');
    let tail = &s[pos + 2..];
    let factor = match head {
        "" | "+" => 1.0,
        "-" => -1.0,
        h => parse_number(h, original)?,
    };
    let divisor = match tail {
        "" => 1.0,
        t => {
            let d = t
                .strip_prefix('/')
                .ok_or_else(|| format!("cannot read angle '{original}'"))?;
            parse_number(d, original)?
        }
    };
    if divisor == 0.0 {
        return Err(format!("angle '{original}' divides by zero"));
    }
    Ok(factor * PI / divisor)
}

fn parse_number(s: &str, original: &str) -> Result<f64, String> {
    let v: f64 = s
        .parse()
        .map_err(|_| format!("cannot read angle '{original}' (use radians, 90deg or 3pi/2)"))?;
    if v.is_finite() {
        Ok(v)
    } else {
        Err(format!("angle '{original}' is not finite"))
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

/// Parses `A:B:STEP` into the values A, A+STEP, … up to B inclusive, or a single number
/// into one value.
///
/// The values are decimal-exact: when A, B and STEP are decimals (at most 15 significant
/// digits and 22 decimals, the usual case), each value is computed in integers scaled by
/// a power of ten and divided once at the end, so it is the number its decimal text reads
/// as: `0:1:0.05` contains `0.15` itself, not `0.15000000000000002`, and B is reached
/// exactly when it lies on the grid. Other numbers (`1e-30:1e-29:1e-31`) are stepped in
/// floating point and B is reached within 1e-9 of a step.
///
/// # Errors
/// Non-finite values, a step of the wrong sign or zero, or more than ten million points.
pub fn parse_range(text: &str) -> Result<Vec<f64>, String> {
    let parts: Vec<&str> = text.split(':').collect();
    let num = |s: &str| -> Result<f64, String> {
        let v: f64 = s
            .trim()
            .parse()
            .map_err(|_| format!("cannot read '{s}' in range '{text}' (expected A:B:STEP)"))?;
        if !v.is_finite() {
            return Err(format!("range '{text}' has a non-finite value"));
        }
        Ok(v)
    };
    match parts.as_slice() {
        [a] => Ok(vec![num(a)?]),
        [a_text, b_text, step_text] => {
            let (a, b, step) = (num(a_text)?, num(b_text)?, num(step_text)?);
            if step == 0.0 || (b - a) * step < 0.0 {
                return Err(format!(
                    "range '{text}': STEP must be non-zero and point from A to B"
                ));
            }
            let too_many = || format!("range '{text}' has more than ten million points");
            if let Some(grid) = DecimalGrid::new(a_text, b_text, step_text) {
                let n = grid.count();
                if n > MAX_RANGE_POINTS {
                    return Err(too_many());
                }
                return Ok((0..=n).map(|k| grid.value(k)).collect());
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
        _ => Err(format!("cannot read range '{text}' (expected A:B:STEP)")),
    }
}

/// Largest number of steps a range may take (ten million).
const MAX_RANGE_POINTS: usize = 10_000_000;

/// Parses the values of a sweep: comma-separated items, each an `A:B:STEP` range or one
/// number ([`parse_range`]), in the order given: `0.1,0.2,0.5`, `0:1:0.25`,
/// `0.1:0.3:0.1,0.5`.
///
/// # Errors
/// The first item that is not a range or a number, or an empty item.
pub fn parse_values(text: &str) -> Result<Vec<f64>, String> {
    let mut out = Vec::new();
    for item in text.split(',') {
        if item.trim().is_empty() {
            return Err(format!(
                "empty value in '{text}' (expected A:B:STEP, a number or a comma list of them)"
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
        for bad in ["1:2:0", "1:2:-1", "a:b:c", "1:2", "1:nan:1"] {
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
