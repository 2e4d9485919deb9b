//! What the command line and the tour report of the rolling sphere, as typed,
//! serializable results: a program gets the numbers of `rollstack sphere ... --json`
//! (docs/cli.md) from these functions, without the command line. The field names of
//! each report are the keys of that JSON.
//!
//! - [`report`]: the holonomy of one rectangle in every form, with the checks of the
//!   closed form (2.4.6) and of the components (B.1.2);
//! - [`plan`]: the rectangles of the inverse planner (App. C) and of the Euler planner
//!   (§2.5), each with the waypoints of the centre's path;
//! - [`roll`]: rolling along a rectangle, circle or polygon by (2.3.4)–(2.3.5) against
//!   the closed-form holonomy, and the speed-vs-error study of the two integrators;
//! - [`level_sets`]: the level sets of ψ(ϑ, φ2) of Figure 2.5, (2.4.11) corrected;
//! - [`examples`]: the worked examples of Ch. 2 with the values the thesis prints:
//!   (2.4.10) and (2.4.12).
//!
//! Lengths are in units of the sphere's radius R throughout. Each report also carries
//! its readable text (`Display`, the lines `rollstack sphere ...` prints without
//! `--json`) and the cells of its CSV rows (`CSV_HEADER` with `csv_cells` or `csv_rows`,
//! numbers in Rust's shortest round-trip form).

pub mod examples;
pub mod level_sets;
pub mod plan;
pub mod report;
pub mod roll;

use crate::rectangle::Direction;

/// The `ccw` cell of the CSV files: `1` for counter-clockwise travel, `0` for clockwise.
pub(crate) fn ccw_cell(direction: Direction) -> String {
    u8::from(direction == Direction::Ccw).to_string()
}
