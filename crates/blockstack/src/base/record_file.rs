//! Reading recorded accelerations: the PEER NGA `.AT2` text format that strong-motion
//! databases distribute, and CSV. Every error is one line naming the file and the line.
//!
//! - `.AT2` (by its extension, any case): four header lines, the fourth holding the
//!   number of points and the step, as `NPTS=  5590, DT= .0050 SEC` or
//!   `5590    0.0050    NPTS, DT`; then NPTS accelerations in g, several per line, in
//!   Fortran forms (`-.1234E-02`, `1.5D-03`). The samples are at t = 0, DT, 2DT, …
//! - Anything else is CSV: `t,a` rows, or one column `a` with a step `dt` given apart
//!   (samples at 0, dt, 2dt, …); lines starting with `#` and blank lines are skipped, and
//!   so is a first line that is not numbers (a header such as `t,a`).

use super::record::{Accelerogram, Baseline};
use crate::error::BlockError;
use std::io::Read;
use std::path::Path;

/// The largest record file read, bytes (64 MiB: a 30 s record at 200 Hz is 100 kB; a
/// larger file is not a record).
pub const MAX_RECORD_BYTES: u64 = 64 << 20;

/// How a record file becomes a base motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RecordOptions {
    /// The step of a one-column CSV file (time units).
    pub dt: Option<f64>,
    /// The model acceleration of one unit of the file's (the scene's g for a record in g).
    pub unit: f64,
    /// A factor on the accelerations, after `scale_to_pga`.
    pub scale: f64,
    /// The peak |a| the corrected record is scaled to, in the file's units (g for
    /// `.AT2`), before `scale`.
    pub scale_to_pga: Option<f64>,
    /// The baseline correction.
    pub baseline: Baseline,
}

impl Default for RecordOptions {
    /// As read, in model units, with the baseline correction.
    fn default() -> Self {
        Self {
            dt: None,
            unit: 1.0,
            scale: 1.0,
            scale_to_pga: None,
            baseline: Baseline::EndAtRest,
        }
    }
}

/// The record at `path` as a base motion: read, corrected, scaled to `scale_to_pga` then
/// by `scale`, and converted to model units. Scaling after the correction makes the
/// peak exactly `scale_to_pga` (the correction is linear, so the order changes nothing
/// else).
///
/// # Errors
/// As [`read_record`]; bad samples (times not increasing), a factor that is not finite,
/// a `scale_to_pga` not positive or a record with no acceleration to scale, naming the
/// file.
pub fn load_record(path: &Path, options: &RecordOptions) -> Result<Accelerogram, BlockError> {
    let name = path.display();
    let samples = read_record(path, options.dt)?;
    let record = Accelerogram::new(&samples)
        .map_err(|e| BlockError::Record(format!("record {name}: {e}")))?
        .corrected(options.baseline);
    let to_pga = match options.scale_to_pga {
        None => 1.0,
        Some(pga) => {
            input::positive("scale_to_pga", pga)?;
            let peak = record.peak();
            if peak == 0.0 {
                return Err(BlockError::Record(format!(
                    "record {name} has no acceleration to scale to scale_to_pga (its peak is 0)"
                )));
            }
            pga / peak
        }
    };
    let factor = input::finite("scale", options.scale)? * to_pga * options.unit;
    Ok(record.scaled(input::finite("record scale", factor)?))
}

/// The samples (tᵢ, aᵢ) of the record at `path`, accelerations in the file's units
/// (g for `.AT2`). `dt` is the step of a one-column CSV file.
///
/// # Errors
/// An unreadable or too large file, a malformed one (naming its line), a `dt` for a file
/// that gives its own times, or a one-column CSV without `dt`.
pub fn read_record(path: &Path, dt: Option<f64>) -> Result<Vec<(f64, f64)>, BlockError> {
    let name = path.display().to_string();
    let fail = |e: std::io::Error| BlockError::Record(format!("cannot read record {name}: {e}"));
    let mut bytes = Vec::new();
    std::fs::File::open(path)
        .map_err(fail)?
        .take(MAX_RECORD_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(fail)?;
    if bytes.len() as u64 > MAX_RECORD_BYTES {
        return Err(BlockError::Record(format!(
            "record {name} is larger than {} MiB, the most a record may be",
            MAX_RECORD_BYTES >> 20
        )));
    }
    let text = String::from_utf8(bytes)
        .map_err(|_| BlockError::Record(format!("record {name} is not text (UTF-8)")))?;
    let at2 = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("at2"));
    if at2 {
        if dt.is_some() {
            return Err(BlockError::Record(format!(
                "record {name}: an .AT2 file gives its own DT; leave 'dt' out"
            )));
        }
        parse_at2(&text, &name)
    } else {
        parse_csv(&text, &name, dt)
    }
}

/// A number as Fortran writes it: `-.1234E-02`, `1.5D-03`, `.5`.
fn number(token: &str) -> Option<f64> {
    let t = token.trim().replace(['D', 'd'], "E");
    t.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// One line's error: `record NAME line N: WHAT`.
fn at_line(name: &str, line: usize, what: &str) -> BlockError {
    BlockError::Record(format!("record {name} line {line}: {what}"))
}

/// The samples of a PEER NGA `.AT2` text (module docs).
///
/// # Errors
/// Fewer than four header lines, a fourth line without NPTS and DT, a value that is not
/// a number, or a number of values other than NPTS: one line naming `name` and the line.
pub fn parse_at2(text: &str, name: &str) -> Result<Vec<(f64, f64)>, BlockError> {
    let lines: Vec<&str> = text.lines().collect();
    let Some(header) = lines.get(3) else {
        return Err(at_line(
            name,
            lines.len() + 1,
            "an .AT2 file has four header lines, the fourth with NPTS and DT",
        ));
    };
    let (npts, dt) = npts_dt(header).ok_or_else(|| {
        at_line(
            name,
            4,
            &format!("expected NPTS and DT (`NPTS= 5590, DT= .0050 SEC` or `5590 0.0050 NPTS, DT`), got '{}'", header.trim()),
        )
    })?;
    // NPTS as the file states it may be anything: no more room than the text can fill.
    let mut a = Vec::with_capacity(npts.min(text.len() / 2));
    for (k, line) in lines.iter().enumerate().skip(4) {
        for token in line.split([' ', '\t', ',']).filter(|s| !s.is_empty()) {
            let v = number(token)
                .ok_or_else(|| at_line(name, k + 1, &format!("'{token}' is not a number")))?;
            if a.len() == npts {
                return Err(at_line(
                    name,
                    k + 1,
                    &format!("more values than NPTS = {npts}"),
                ));
            }
            a.push(v);
        }
    }
    if a.len() < npts {
        return Err(at_line(
            name,
            lines.len(),
            &format!("the file ends after {} values, NPTS = {npts}", a.len()),
        ));
    }
    Ok(evenly_spaced(&a, dt))
}

/// NPTS and DT of an `.AT2` fourth line, in either form; DT must be positive and NPTS at
/// least 2.
fn npts_dt(line: &str) -> Option<(usize, f64)> {
    let upper = line.to_ascii_uppercase();
    let (npts, dt) = if upper.contains("NPTS=") || upper.contains("NPTS =") {
        (after(&upper, "NPTS")?, after(&upper, "DT")?)
    } else {
        let mut tokens = upper.split([' ', '\t', ',']).filter(|s| !s.is_empty());
        (tokens.next()?.to_owned(), tokens.next()?.to_owned())
    };
    let n = number(&npts).filter(|n| n.fract() == 0.0 && *n >= 2.0 && *n <= 1e9)?;
    let dt = number(&dt).filter(|d| *d > 0.0)?;
    // A whole number in [2, 1e9]: the cast is exact.
    #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
    Some((n as usize, dt))
}

/// The token after `KEY` and its `=` in `line` (`NPTS=  5590,` gives `5590`).
fn after(line: &str, key: &str) -> Option<String> {
    let rest = &line[line.find(key)? + key.len()..];
    let rest = rest.trim_start().strip_prefix('=')?.trim_start();
    let end = rest
        .find(|c: char| c == ',' || c.is_whitespace())
        .unwrap_or(rest.len());
    Some(rest[..end].to_owned())
}

/// The samples (i·dt, aᵢ).
fn evenly_spaced(a: &[f64], dt: f64) -> Vec<(f64, f64)> {
    (0u32..)
        .zip(a)
        .map(|(i, &a)| (dt * f64::from(i), a))
        .collect()
}

/// The samples of a CSV text (module docs).
///
/// # Errors
/// A value that is not a number, a row with another number of columns than the first, a
/// one-column file without `dt` or a two-column file with it, or no rows.
pub fn parse_csv(text: &str, name: &str, dt: Option<f64>) -> Result<Vec<(f64, f64)>, BlockError> {
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut columns = None;
    for (k, line) in text.lines().enumerate() {
        let line = line.trim();
        if line.is_empty() || line.starts_with('#') {
            continue;
        }
        let cells: Vec<&str> = line.split(',').map(str::trim).collect();
        let values: Option<Vec<f64>> = cells.iter().map(|c| number(c)).collect();
        let Some(values) = values else {
            if columns.is_none() && rows.is_empty() {
                continue; // the header
            }
            let bad = cells.iter().find(|c| number(c).is_none()).unwrap_or(&"");
            return Err(at_line(name, k + 1, &format!("'{bad}' is not a number")));
        };
        let n = *columns.get_or_insert(values.len());
        if values.len() != n || n > 2 {
            return Err(at_line(
                name,
                k + 1,
                &format!(
                    "{} columns; a record has `t,a` or one column `a`",
                    values.len()
                ),
            ));
        }
        rows.push(values);
    }
    match (columns, dt) {
        (None, _) => Err(BlockError::Record(format!(
            "record {name} has no rows of numbers"
        ))),
        (Some(1), Some(dt)) => {
            let dt = input::positive("record dt", dt)?;
            let a: Vec<f64> = rows.iter().map(|r| r[0]).collect();
            Ok(evenly_spaced(&a, dt))
        }
        (Some(1), None) => Err(BlockError::Record(format!(
            "record {name} has one column: give its time step 'dt'"
        ))),
        (Some(_), Some(_)) => Err(BlockError::Record(format!(
            "record {name} gives its times (t,a): leave 'dt' out"
        ))),
        (Some(_), None) => Ok(rows.iter().map(|r| (r[0], r[1])).collect()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const HEAD: &str = "PEER NGA STRONG MOTION DATABASE RECORD\nSYNTHETIC, 1/1/2000, TEST\nACCELERATION TIME SERIES IN UNITS OF G\n";

    #[test]
    fn both_forms_of_the_fourth_line_are_read() {
        let body = "  .1000E-01 -.2000E-02  3.0D-03\n  .4\n";
        for line4 in [
            "NPTS=     4, DT=   .0050 SEC\n",
            "4    0.0050    NPTS, DT\n",
            "npts = 4, dt = 5.0E-03 sec\n",
        ] {
            let s = parse_at2(&format!("{HEAD}{line4}{body}"), "x.AT2").unwrap();
            assert_eq!(s.len(), 4, "{line4}");
            assert_eq!(s[1], (0.005, -0.002));
            assert_eq!(s[2].1, 0.003);
            assert_eq!(s[3], (0.015, 0.4));
        }
    }

    fn at2_error(text: &str) -> String {
        let e = parse_at2(text, "quake.AT2").unwrap_err().to_string();
        assert!(!e.contains('\n'), "one line: {e}");
        assert!(e.starts_with("record quake.AT2 line "), "{e}");
        e
    }

    #[test]
    fn a_malformed_at2_names_the_file_and_line() {
        let e = at2_error(&format!("{HEAD}NPTS= 3, DT= .01\n.1 .2\n.3x\n"));
        assert!(e.contains("line 6: '.3x' is not a number"), "{e}");
        let e = at2_error(&format!("{HEAD}DT= .01\n.1 .2\n"));
        assert!(e.contains("line 4: expected NPTS and DT"), "{e}");
        let e = at2_error(&format!("{HEAD}NPTS= 3, DT= .01\n.1 .2\n"));
        assert!(e.contains("ends after 2 values, NPTS = 3"), "{e}");
        let e = at2_error(&format!("{HEAD}NPTS= 2, DT= .01\n.1 .2 .3\n"));
        assert!(e.contains("line 5: more values than NPTS = 2"), "{e}");
        let e = at2_error(&format!("{HEAD}NPTS= 2, DT= -.01\n.1 .2\n"));
        assert!(e.contains("line 4"), "{e}");
        assert!(at2_error("one\ntwo\n").contains("line 3: an .AT2 file has four header lines"));
    }

    /// The synthetic record of the repository (scripts/synthetic_record.py).
    fn synthetic() -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/data/synthetic.AT2")
    }

    #[test]
    fn the_synthetic_record_loads_scaled_to_its_peak() {
        let raw = read_record(&synthetic(), None).unwrap();
        assert_eq!(raw.len(), 1000);
        assert_eq!(raw[999].0, 9.99);
        let peak = raw.iter().fold(0.0f64, |m, s| m.max(s.1.abs()));
        assert!((peak - 0.25).abs() < 1e-7, "{peak}");
        let options = RecordOptions {
            unit: 9.81,
            scale_to_pga: Some(0.4),
            scale: 0.5,
            ..RecordOptions::default()
        };
        let r = load_record(&synthetic(), &options).unwrap();
        // scale_to_pga, then scale, in g; times g: the peak is exactly 0.2 g.
        assert!((r.peak() - 0.2 * 9.81).abs() < 1e-12, "{}", r.peak());
        let end = r.at(r.end());
        assert!(end.velocity.abs() < 1e-12 && end.displacement.abs() < 1e-12);
        let zero = std::env::temp_dir().join(format!("rollstack-zero-{}.csv", std::process::id()));
        std::fs::write(&zero, "t,a\n0,0\n1,0\n").unwrap();
        let to_pga = RecordOptions {
            scale_to_pga: Some(1.0),
            ..RecordOptions::default()
        };
        let e = load_record(&zero, &to_pga).unwrap_err().to_string();
        std::fs::remove_file(&zero).unwrap();
        assert!(e.contains("no acceleration to scale"), "{e}");
        let e = load_record(Path::new("/no/such.AT2"), &RecordOptions::default()).unwrap_err();
        assert!(
            e.to_string()
                .starts_with("cannot read record /no/such.AT2: "),
            "{e}"
        );
    }

    #[test]
    fn csv_has_times_or_a_step() {
        let s = parse_csv("t,a\n0,0.1\n0.5,0.2\n# end\n", "r.csv", None).unwrap();
        assert_eq!(s, vec![(0.0, 0.1), (0.5, 0.2)]);
        let s = parse_csv("0.1\n0.2\n0.3\n", "r.csv", Some(0.5)).unwrap();
        assert_eq!(s[2], (1.0, 0.3));
        let e = parse_csv("0.1\n0.2\n", "r.csv", None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("give its time step 'dt'"), "{e}");
        let e = parse_csv("0,0.1\n1,x\n", "r.csv", None)
            .unwrap_err()
            .to_string();
        assert_eq!(e, "record r.csv line 2: 'x' is not a number");
        let e = parse_csv("0,0.1\n1\n", "r.csv", None)
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2: 1 columns"), "{e}");
        assert!(parse_csv("0,0.1\n1,0\n", "r.csv", Some(0.1)).is_err());
        assert!(parse_csv("# nothing\n", "r.csv", None).is_err());
    }
}
