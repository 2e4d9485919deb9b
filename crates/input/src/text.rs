//! Values written as text, as a user types them: angles in radians by default, `90deg`,
//! and multiples of π such as `3pi/2`; finite numbers; comma-separated lists; and
//! `A:B:STEP` ranges for sweeps.
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

/// Parses `A:B:STEP` into the values A, A+STEP, … up to B inclusive (within 1e-9 of a
/// step), or a single number into one value.
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
        [a, b, step] => {
            let (a, b, step) = (num(a)?, num(b)?, num(step)?);
            if step == 0.0 || (b - a) * step < 0.0 {
                return Err(format!(
                    "range '{text}': STEP must be non-zero and point from A to B"
                ));
            }
            let n = ((b - a) / step + 1e-9).floor();
            if n > 1e7 {
                return Err(format!("range '{text}' has more than ten million points"));
            }
            // n is a checked non-negative count below 1e7, so the cast is exact.
            #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
            let n = n as usize;
            Ok((0..=n).map(|i| a + step * i as f64).collect())
        }
        _ => Err(format!("cannot read range '{text}' (expected A:B:STEP)")),
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
}
