//! What the command line and the tour report of the inclined rolling cylinder, as typed,
//! serializable results: a program gets the numbers of `rollstack cylinder ... --json`
//! and the rows of its CSV files (docs/cli.md) from these functions, without the command
//! line. The field names of each report are the keys of that JSON.
//!
//! - [`support`]: the steady support at one inclination, (3.3.8)–(3.3.19), corrected per
//!   ERRATA 9–11, checked against the balance laws (3.3.3);
//! - [`statics`]: the support-force curves of Figures 3.3, 3.4, 3.5, 3.7 and 3.8;
//! - [`holonomy`]: Δφ of a rectangle (3.4.3)–(3.4.9) and of a circle (3.4.10)–(3.4.16)
//!   traced by P (radians, ERRATA 8), each checked by rolling along the path, and the
//!   traces of Figures 3.10 and 3.12;
//! - [`frobenius`]: the Frobenius test of the single cylinder (App. D) and of the pair
//!   (§3.5, App. F; rank 9, ERRATA 13);
//! - [`pair`]: the transport of two touching cylinders (§3.6) and its sweeps, with
//!   [`pair_cost`], what their runs will cost before they start;
//! - [`work_precision`]: speed against error for the pair spun up, NSGA beside
//!   Moreau–Jean, with honest observed orders.
//!
//! Forces are divided by mg, angles are in radians, lengths in any one unit. Each report
//! also carries its readable text (`Display`, the lines `rollstack cylinder ...` prints
//! without `--json`) and each row type the cells of its CSV rows (`CSV_HEADER` with
//! `csv_cells` or `csv_rows`, numbers in Rust's shortest round-trip form).

pub mod frobenius;
pub mod holonomy;
pub mod pair;
pub mod pair_cost;
pub mod statics;
pub mod support;
pub mod work_precision;
