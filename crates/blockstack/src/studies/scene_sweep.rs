//! Any scene swept over any of its numbers: the scene file with some keys set to other
//! values (`contact.mu = 0.3`, `blocks.0.width = 0.25`), run once per combination, one
//! typed row per run.
//!
//! - A key is a dotted path into the scene file (docs/scenes.md): `base.omega`,
//!   `contact.mu`, `contact.e_n`, `solver.steps_per_period`, `floor.y`, …; for the
//!   `[[blocks]]` entries, `blocks.K.width` sets entry K (counting from 0; an entry with
//!   `count = 4` is four blocks) and `blocks.width` every entry. Only numbers can be set
//!   ([`NUMERIC_KEYS`]); `blocks.count` takes whole numbers.
//! - [`SceneSweep::new`] checks every key against the scene before anything runs: an
//!   unknown key is one line naming the keys of its table.
//! - A key absent from the file is added (`contact.e_n`; `floor.y` adds a floor). Setting
//!   `solver.dt` drops the file's `solver.steps_per_period` and the reverse, and likewise
//!   `solver.t_end` and `solver.periods`, so that the value set is the one used.
//! - The changed file goes through the scene loader ([`SceneFile::build`]), so every
//!   check of a scene applies; a value it refuses (μ < 0, overlapping blocks) and a run
//!   that stops are the row's `error`, never the sweep's.
//! - [`SceneSweep::points`] is the cartesian product of the overrides' values, the first
//!   override varying slowest.
//!
//! ```
//! use blockstack::studies::scene_sweep::{Override, SceneSweep};
//! use blockstack::RunOptions;
//!
//! let text = blockstack::scenes::find("shaking")?.toml;
//! let overrides: Vec<Override> = vec![
//!     "contact.mu=0.1,0.3".parse().unwrap(),
//!     "base.amplitude=0.1:0.2:0.1".parse().unwrap(),
//! ];
//! let sweep = SceneSweep::new(text, overrides)?;
//! let points = sweep.points();
//! assert_eq!(points.len(), 4);
//! assert_eq!((points[1][0].value, points[1][1].value), (0.1, 0.2));
//! let options = RunOptions { t_end: Some(0.05), ..RunOptions::default() };
//! let row = sweep.row(&points[0], &options);
//! assert!(row.error.is_none() && row.steps > 0);
//! assert_eq!(sweep.csv_header()[..3], ["contact.mu", "base.amplitude", "failure_time"]);
//!
//! let typo = SceneSweep::new(text, vec!["contact.muu=0.1".parse().unwrap()]);
//! assert!(typo.unwrap_err().to_string().contains("mu, e_n, e_f"));
//! # Ok::<(), blockstack::BlockError>(())
//! ```

use crate::error::BlockError;
use crate::record::{finite_text, optional_text};
use crate::scene_file::{LoadedScene, SceneFile};
use crate::simulation::{simulate, BlockPose, RunOptions};
use crate::studies::convergence::row::RowConvergence;
use crate::studies::convergence::Settings;
use crate::studies::shaking::one_line;
use serde::{Deserialize, Serialize};
use std::fmt;
use std::path::PathBuf;
use std::str::FromStr;

/// The tables of a scene file with the keys a sweep can set: every numeric key.
pub const NUMERIC_KEYS: [(&str, &[&str]); 5] = [
    (
        "base",
        &[
            "width",
            "height",
            "amplitude",
            "omega",
            "v0",
            "period",
            "start",
            "scale",
            "scale_to_pga",
            "dt",
        ],
    ),
    (
        "blocks",
        &["width", "height", "mass", "count", "x", "y", "theta"],
    ),
    ("contact", &["mu", "e_n", "e_f"]),
    (
        "solver",
        &[
            "dt",
            "steps_per_period",
            "t_end",
            "periods",
            "rho_inf",
            "r",
            "r_alpha",
            "tol",
            "gravity",
        ],
    ),
    ("floor", &["y"]),
];

/// The numeric keys that are angles (radians) or angular rates (radians per time unit):
/// the only ones whose values may be written in degrees (`blocks.theta=5deg`).
pub const ANGLE_KEYS: [&str; 2] = ["theta", "omega"];

/// The keys of [`NUMERIC_KEYS`] that are [`ANGLE_KEYS`]: `base.omega and blocks.theta`.
fn angle_keys() -> String {
    let keys: Vec<String> = NUMERIC_KEYS
        .iter()
        .flat_map(|(table, fields)| {
            fields
                .iter()
                .filter(|f| ANGLE_KEYS.contains(f))
                .map(move |f| format!("{table}.{f}"))
        })
        .collect();
    keys.join(" and ")
}

/// The keys of a scene file that are not numbers and cannot be swept.
const OTHER_KEYS: [(&str, &str); 8] = [
    ("base", "motion"),
    ("base", "samples"),
    ("base", "shape"),
    ("base", "record"),
    ("base", "units"),
    ("base", "baseline"),
    ("blocks", "name"),
    ("contact", "bodies"),
];

/// The base's own keys; its other numeric keys are a component's motion's: `base.KEY`
/// is the x component's (in `[base.x]` when the file has that table, else in `[base]`),
/// `base.y.KEY` and `base.rotation.KEY` the others'.
const BASE_OWN_KEYS: [&str; 2] = ["width", "height"];

/// The keys of `[base]` itself that give the x motion (the thesis's motions).
const BASE_X_KEYS: [&str; 5] = ["motion", "amplitude", "omega", "v0", "samples"];

/// The components of the base's motion with a table of their own.
const BASE_COMPONENTS: [&str; 3] = ["x", "y", "rotation"];

/// The sub-tables of `[contact]` that override its numbers for one kind of interface
/// (`contact.base.mu`); `contact.pair.K.mu` sets `[[contact.pair]]` entry K.
pub const CONTACT_KINDS: [&str; 3] = ["base", "blocks", "floor"];

/// Pairs of `[solver]` keys that say the same thing two ways: setting one drops the other.
const ALTERNATIVES: [(&str, &str); 2] = [("dt", "steps_per_period"), ("t_end", "periods")];

/// Most combinations one sweep may have (ten million).
pub const MAX_POINTS: usize = 10_000_000;

/// One swept key with its values, as typed: `contact.mu=0.1:0.5:0.1`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Override {
    /// The dotted scene key (`contact.mu`, `blocks.0.width`).
    pub key: String,
    /// Its values, in order.
    pub values: Vec<f64>,
}

impl FromStr for Override {
    type Err = String;

    /// `KEY=VALUES`, the values as [`input::text::parse_values`] reads them: `A:B:STEP`,
    /// one number, or a comma list of them.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let (key, values) = s.split_once('=').ok_or_else(|| {
            format!("'{s}' is not KEY=VALUES (e.g. contact.mu=0.1:0.5:0.1 or base.omega=2,4,8)")
        })?;
        let key = key.trim();
        if key.is_empty() {
            return Err(format!("'{s}' has no key before '='"));
        }
        let field = key.rsplit('.').next().unwrap_or(key);
        if input::text::in_degrees(values) && !ANGLE_KEYS.contains(&field) {
            return Err(format!(
                "{key} is not an angle: '{}' is in degrees (deg is for {}); write {key} \
                 without deg",
                values.trim(),
                angle_keys()
            ));
        }
        let values = input::text::parse_values(values).map_err(|e| format!("{key}: {e}"))?;
        Ok(Self {
            key: key.to_owned(),
            values,
        })
    }
}

/// One key set to one value: a coordinate of a sweep's point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SetValue {
    /// The dotted scene key.
    pub key: String,
    /// The value it is set to.
    pub value: f64,
}

/// Which `[[blocks]]` entries, or which table, a key is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Place {
    /// `[base]`, `[contact]`, `[solver]` or `[floor]`.
    Table(&'static str),
    /// `[contact.base]`, `[contact.blocks]` or `[contact.floor]`: its index in
    /// [`CONTACT_KINDS`].
    ContactKind(usize),
    /// `[[contact.pair]]` entry K, from 0.
    Pair(usize),
    /// `blocks.KEY`: every entry.
    AllBlocks,
    /// `blocks.K.KEY`: entry K, from 0.
    Block(usize),
    /// `base.C.KEY`: the table `[base.C]` of component C (x, y, rotation).
    BaseComponent(&'static str),
}

/// A checked scene key: where it is and which field it names.
#[derive(Debug, Clone, PartialEq, Eq)]
struct SceneKey {
    text: String,
    place: Place,
    field: &'static str,
}

impl SceneKey {
    /// Checks `text` against the keys of a scene file with `entries` `[[blocks]]` entries
    /// and `pairs` `[[contact.pair]]` entries.
    fn parse(text: &str, entries: usize, pairs: usize) -> Result<Self, BlockError> {
        let bad = |why: String| BlockError::Key(format!("scene key '{text}': {why}"));
        let tables = || {
            NUMERIC_KEYS
                .iter()
                .map(|(t, _)| *t)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let parts: Vec<&str> = text.split('.').collect();
        let Some((&table_name, rest)) = parts.split_first() else {
            return Err(bad("empty".into()));
        };
        let Some(&(table, fields)) = NUMERIC_KEYS.iter().find(|(t, _)| *t == table_name) else {
            return Err(bad(format!(
                "no table '{table_name}' (a key is TABLE.KEY, TABLE one of {}; blocks.K.KEY for [[blocks]] entry K)",
                tables()
            )));
        };
        let (place, field) = match (table, rest) {
            ("blocks", [field]) => (Place::AllBlocks, *field),
            ("blocks", [k, field]) => {
                let k: usize = k.parse().map_err(|_| {
                    bad(format!(
                        "'{k}' is not an entry number (blocks.K.KEY, K from 0, or blocks.KEY for every entry)"
                    ))
                })?;
                if k >= entries {
                    return Err(bad(format!(
                        "the scene has {entries} [[blocks]] entr{} (blocks.0 to blocks.{}; an entry with count = N is N blocks)",
                        if entries == 1 { "y" } else { "ies" },
                        entries.saturating_sub(1)
                    )));
                }
                (Place::Block(k), *field)
            }
            ("contact", [kind, field]) if CONTACT_KINDS.contains(kind) => {
                let i = CONTACT_KINDS.iter().position(|k| k == kind).unwrap_or(0);
                (Place::ContactKind(i), *field)
            }
            ("contact", ["pair", k, field]) => (Place::Pair(pair_entry(k, pairs).map_err(bad)?), *field),
            (_, [field]) => (Place::Table(table), *field),
            ("base", [component, field]) => {
                let Some(&c) = BASE_COMPONENTS.iter().find(|c| *c == component) else {
                    return Err(bad(format!(
                        "'{component}' is not a component of the base's motion (base.x.KEY, base.y.KEY, base.rotation.KEY)"
                    )));
                };
                if BASE_OWN_KEYS.contains(field) {
                    return Err(bad(format!("{field} is the base's own: base.{field}")));
                }
                (Place::BaseComponent(c), *field)
            }
            _ => {
                return Err(bad(format!(
                    "expected {table}.KEY{}",
                    match table {
                        "blocks" => " or blocks.K.KEY",
                        "base" => " or base.C.KEY (C one of x, y, rotation)",
                        "contact" => ", contact.base.KEY, contact.blocks.KEY, contact.floor.KEY or contact.pair.K.KEY",
                        _ => "",
                    }
                )))
            }
        };
        let numeric = || fields.join(", ");
        let Some(&field) = fields.iter().find(|f| **f == field) else {
            let header = if table == "blocks" {
                "[[blocks]]".to_owned()
            } else {
                format!("[{table}]")
            };
            let what = if OTHER_KEYS.contains(&(table, field)) {
                "not a number, so it cannot be swept".to_owned()
            } else {
                format!("{header} has no key '{field}'")
            };
            return Err(bad(format!(
                "{what} (the numeric keys of {header}: {})",
                numeric()
            )));
        };
        Ok(Self {
            text: text.to_owned(),
            place,
            field,
        })
    }

    /// Whether two keys set the same number of some table or entry.
    fn overlaps(&self, other: &Self) -> bool {
        let same_place = match (self.place, other.place) {
            // blocks.KEY sets blocks.K.KEY; base.KEY may be set in [base.x].
            (Place::Block(_), Place::AllBlocks)
            | (Place::AllBlocks, Place::Block(_))
            | (Place::Table("base"), Place::BaseComponent("x"))
            | (Place::BaseComponent("x"), Place::Table("base")) => true,
            (a, b) => a == b,
        };
        same_place
            && (self.field == other.field
                || ALTERNATIVES.iter().any(|&(a, b)| {
                    (self.field, other.field) == (a, b) || (self.field, other.field) == (b, a)
                }))
    }

    /// Sets this key to `value` in a scene file's table.
    fn set(&self, file: &mut toml::Table, value: f64) -> Result<(), BlockError> {
        let item = if self.field == "count" {
            if value.fract() != 0.0 || !(0.0..=1e15).contains(&value) {
                return Err(BlockError::Scene(format!(
                    "{} must be a whole number, got {value}",
                    self.text
                )));
            }
            // A whole number in [0, 1e15]: the cast is exact.
            #[allow(clippy::cast_possible_truncation)]
            toml::Value::Integer(value as i64)
        } else {
            toml::Value::Float(value)
        };
        let field = self.field;
        let set_in = |table: &mut toml::Table| {
            table.insert(field.to_owned(), item.clone());
            for &(a, b) in &ALTERNATIVES {
                if field == a {
                    table.remove(b);
                } else if field == b {
                    table.remove(a);
                }
            }
        };
        let not_table = |name: &str| BlockError::Scene(format!("{name} is not a table"));
        match self.place {
            // The x component's keys go where the file gives its x motion.
            Place::Table("base") if !BASE_OWN_KEYS.contains(&field) => {
                let base = subtable(file, "base")?;
                if !base.contains_key("x") && !BASE_X_KEYS.contains(&field) {
                    // A key only [base.x] takes (a record's scale): the x motion moves
                    // there, so that the loader judges the key against it.
                    let x: toml::Table = BASE_X_KEYS
                        .iter()
                        .filter_map(|k| base.remove(*k).map(|v| ((*k).to_owned(), v)))
                        .collect();
                    base.insert("x".to_owned(), toml::Value::Table(x));
                }
                if base.contains_key("x") {
                    set_in(subtable(base, "x")?);
                } else {
                    set_in(base);
                }
            }
            Place::Table(name) => set_in(subtable(file, name)?),
            Place::BaseComponent(c) => set_in(subtable(subtable(file, "base")?, c)?),
            Place::ContactKind(i) => {
                set_in(subtable(subtable(file, "contact")?, CONTACT_KINDS[i])?);
            }
            Place::Pair(k) => set_in(
                subtable(file, "contact")?
                    .get_mut("pair")
                    .and_then(toml::Value::as_array_mut)
                    .and_then(|entries| entries.get_mut(k))
                    .and_then(toml::Value::as_table_mut)
                    .ok_or_else(|| not_table("contact.pair"))?,
            ),
            Place::AllBlocks | Place::Block(_) => {
                let entries = file
                    .get_mut("blocks")
                    .and_then(toml::Value::as_array_mut)
                    .ok_or_else(|| not_table("blocks"))?;
                for (k, entry) in entries.iter_mut().enumerate() {
                    if matches!(self.place, Place::Block(j) if j != k) {
                        continue;
                    }
                    set_in(entry.as_table_mut().ok_or_else(|| not_table("blocks"))?);
                }
            }
        }
        Ok(())
    }
}

/// The table `name` of `file`, added empty when absent.
fn subtable<'a>(file: &'a mut toml::Table, name: &str) -> Result<&'a mut toml::Table, BlockError> {
    file.entry(name)
        .or_insert_with(|| toml::Value::Table(toml::Table::new()))
        .as_table_mut()
        .ok_or_else(|| BlockError::Scene(format!("{name} is not a table")))
}

/// The `[[contact.pair]]` entry number `k` of `contact.pair.K.KEY`, checked against the
/// file's `pairs` entries.
fn pair_entry(k: &str, pairs: usize) -> Result<usize, String> {
    match k.parse::<usize>() {
        Ok(k) if k < pairs => Ok(k),
        _ => Err(format!(
            "'{k}' is not a [[contact.pair]] entry: the scene has {pairs} (contact.pair.K.KEY, K from 0)"
        )),
    }
}

/// A scene file and the keys swept over it, checked.
#[derive(Debug, Clone)]
pub struct SceneSweep {
    file: toml::Table,
    keys: Vec<SceneKey>,
    overrides: Vec<Override>,
    dir: PathBuf,
}

impl SceneSweep {
    /// Reads the scene file `text` and checks the swept keys against it.
    ///
    /// # Errors
    /// A file that does not parse as a scene file ([`SceneFile::parse`]); a key that is
    /// not a numeric key of the scene, with the keys of its table ([`NUMERIC_KEYS`]); a
    /// key given twice, or two keys that set the same number (`blocks.width` and
    /// `blocks.0.width`; `solver.dt` and `solver.steps_per_period`); an override without
    /// values; more than [`MAX_POINTS`] combinations. One line each. Values are not
    /// checked here: a bad value is the error of its rows.
    pub fn new(text: &str, overrides: Vec<Override>) -> Result<Self, BlockError> {
        let parsed = SceneFile::parse(text)?;
        let file: toml::Table = text
            .parse()
            .map_err(|e: toml::de::Error| BlockError::Scene(one_line(e.message())))?;
        let mut keys: Vec<SceneKey> = Vec::with_capacity(overrides.len());
        for o in &overrides {
            let key = SceneKey::parse(&o.key, parsed.blocks.len(), parsed.contact.pair.len())?;
            if let Some(old) = keys.iter().find(|k| k.overlaps(&key)) {
                return Err(BlockError::Key(format!(
                    "scene keys '{}' and '{}' set the same number: sweep one of them",
                    old.text, key.text
                )));
            }
            if o.values.is_empty() {
                return Err(BlockError::Key(format!(
                    "scene key '{}' has no values",
                    o.key
                )));
            }
            keys.push(key);
        }
        let count = overrides
            .iter()
            .try_fold(1usize, |n, o| n.checked_mul(o.values.len()));
        if count.is_none_or(|n| n > MAX_POINTS) {
            return Err(BlockError::Key(format!(
                "the sweep has more than {MAX_POINTS} combinations"
            )));
        }
        Ok(Self {
            file,
            keys,
            overrides,
            dir: PathBuf::new(),
        })
    }

    /// The same sweep of a scene file in the directory `dir`, where the paths of its
    /// records start (by default the working directory).
    #[must_use]
    pub fn in_dir(self, dir: PathBuf) -> Self {
        Self { dir, ..self }
    }

    /// The swept keys, in the order given.
    #[must_use]
    pub fn keys(&self) -> Vec<&str> {
        self.keys.iter().map(|k| k.text.as_str()).collect()
    }

    /// The overrides, as given.
    #[must_use]
    pub fn overrides(&self) -> &[Override] {
        &self.overrides
    }

    /// Every combination of the values ([`cartesian_product`]).
    #[must_use]
    pub fn points(&self) -> Vec<Vec<SetValue>> {
        cartesian_product(&self.overrides)
    }

    /// The scene file with the keys of `point` set.
    ///
    /// # Errors
    /// A key this sweep does not sweep, a count that is not a whole number, or a value
    /// of the wrong type for the file's structure.
    pub fn file(&self, point: &[SetValue]) -> Result<SceneFile, BlockError> {
        let mut file = self.file.clone();
        for set in point {
            let key = self
                .keys
                .iter()
                .find(|k| k.text == set.key)
                .ok_or_else(|| {
                    BlockError::Key(format!("scene key '{}' is not swept here", set.key))
                })?;
            key.set(&mut file, set.value)?;
        }
        file.try_into()
            .map_err(|e: toml::de::Error| BlockError::Scene(one_line(e.message().trim())))
    }

    /// The scene of `point`, through the scene loader and all its checks.
    ///
    /// # Errors
    /// As [`SceneSweep::file`], and every error of [`SceneFile::build`].
    pub fn scene(&self, point: &[SetValue]) -> Result<LoadedScene, BlockError> {
        self.file(point)?.build_at(&self.dir)
    }

    /// Runs the scene of `point` with `options` (its `t_end`, when given, overrides the
    /// scene's); every failure (a value the loader refuses, a run that cannot start or
    /// stops) goes into the row's `error`.
    #[must_use]
    pub fn row(&self, point: &[SetValue], options: &RunOptions) -> SceneRow {
        let mut row = SceneRow {
            set: point.to_vec(),
            failure_time: None,
            opening_time: None,
            t_final: None,
            steps: 0,
            failed_steps: 0,
            branch_points: 0,
            fallback_steps: 0,
            unshifted_steps: 0,
            linear_solves: 0,
            min_gap: None,
            max_penetration: None,
            top_x: None,
            top_y: None,
            top_theta: None,
            error: None,
            wall_time_s: 0.0,
            convergence: None,
        };
        let loaded = match self.scene(point) {
            Ok(l) => l,
            Err(e) => {
                row.error = Some(one_line(&e.to_string()));
                return row;
            }
        };
        let mut last: Option<(f64, Option<BlockPose>)> = None;
        match simulate(&loaded.scene, options, |r| {
            last = Some((r.t, r.poses.last().copied()));
        }) {
            Ok(s) => {
                row.failure_time = s.failure_time;
                row.opening_time = s.opening_time;
                row.steps = s.steps;
                row.failed_steps = s.failed_steps;
                row.branch_points = s.branch_points.len();
                row.fallback_steps = s.fallback_steps;
                row.unshifted_steps = s.unshifted_steps;
                row.linear_solves = s.linear_solves;
                row.min_gap = Some(s.min_gap).filter(|g| g.is_finite());
                row.max_penetration = Some(s.deepest.depth());
                row.error = s.error.map(|e| one_line(&e.to_string()));
                row.wall_time_s = s.wall_time_s;
                if let Some((t, top)) = last {
                    row.t_final = Some(t);
                    row.top_x = top.map(|p| p.x);
                    row.top_y = top.map(|p| p.y);
                    row.top_theta = top.map(|p| p.theta);
                }
            }
            Err(e) => row.error = Some(one_line(&e.to_string())),
        }
        row
    }

    /// [`Self::row`] and, with `settings` (`--convergence K`), the row's verdicts over
    /// Δt/2^k on its failure time ([`RowConvergence`]).
    #[must_use]
    pub fn row_judged(
        &self,
        point: &[SetValue],
        options: &RunOptions,
        settings: Option<Settings>,
    ) -> SceneRow {
        let mut row = self.row(point, options);
        if let (Some(settings), Ok(loaded)) = (settings, self.scene(point)) {
            row.convergence = Some(RowConvergence::of(&loaded.scene, options, settings, |r| {
                r.observed.failure_time
            }));
        }
        row
    }

    /// The columns of the sweep's CSV: the swept keys, then [`SceneRow::MEASURED`].
    #[must_use]
    pub fn csv_header(&self) -> Vec<String> {
        SceneRow::csv_header(&self.keys())
    }
}

/// Every combination of the overrides' values, the first override varying slowest
/// (`a=1,2` and `b=3,4`: (1,3), (1,4), (2,3), (2,4)); one empty combination for no
/// overrides.
#[must_use]
pub fn cartesian_product(overrides: &[Override]) -> Vec<Vec<SetValue>> {
    let mut points: Vec<Vec<SetValue>> = vec![Vec::new()];
    for o in overrides {
        points = points
            .iter()
            .flat_map(|p| {
                o.values.iter().map(move |&value| {
                    let mut q = p.clone();
                    q.push(SetValue {
                        key: o.key.clone(),
                        value,
                    });
                    q
                })
            })
            .collect();
    }
    points
}

/// One run of a scene sweep: the values set, then what the run did.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SceneRow {
    /// The keys set and their values, in the order of the sweep's keys.
    pub set: Vec<SetValue>,
    /// First loss of support of a block (§4.4), or null.
    pub failure_time: Option<f64>,
    /// First full opening of an interface, or null.
    pub opening_time: Option<f64>,
    /// Time of the last state computed, or null when the run did not start.
    pub t_final: Option<f64>,
    /// Steps taken.
    pub steps: usize,
    /// Steps whose first Newton attempt failed.
    pub failed_steps: usize,
    /// Branch points recorded.
    pub branch_points: usize,
    /// Steps taken by the last resort (Moreau–Jean solved by Lemke's method).
    pub fallback_steps: usize,
    /// Steps taken without the friction percussions' half-step shift (`Stage::Unshifted` of the
    /// step policy, docs/method.md §8.2).
    #[serde(default)]
    pub unshifted_steps: usize,
    /// Linear solves of the Newton iterations in every attempt (the run's work).
    pub linear_solves: u64,
    /// Smallest gap among the contacts that can close over the run, or null when none
    /// could.
    pub min_gap: Option<f64>,
    /// The deepest overlap between any two bodies over the run (0 when they only
    /// touch), or null when the run did not start.
    pub max_penetration: Option<f64>,
    /// The top block's centre x at `t_final`.
    pub top_x: Option<f64>,
    /// The top block's centre y at `t_final`.
    pub top_y: Option<f64>,
    /// The top block's angle θ at `t_final` (rad).
    pub top_theta: Option<f64>,
    /// Why the scene was refused, could not start or stopped early; null otherwise.
    pub error: Option<String>,
    /// Solver time (s).
    pub wall_time_s: f64,
    /// With `--convergence K`: the row's verdicts over Δt/2^k, k = 0…K
    /// ([`crate::studies::convergence::row`]); absent otherwise, so that the row, its
    /// JSON and its line in the row log are those of a sweep without it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub convergence: Option<RowConvergence>,
}

impl SceneRow {
    /// The measured columns, after the swept keys' columns.
    pub const MEASURED: [&'static str; 16] = [
        "failure_time",
        "opening_time",
        "t_final",
        "steps",
        "failed_steps",
        "branch_points",
        "fallback_steps",
        "unshifted_steps",
        "linear_solves",
        "min_gap",
        "max_penetration",
        "top_x",
        "top_y",
        "top_theta",
        "error",
        "wall_time_s",
    ];

    /// The CSV columns for the swept `keys`: one per key, then [`Self::MEASURED`].
    #[must_use]
    pub fn csv_header(keys: &[&str]) -> Vec<String> {
        keys.iter()
            .copied()
            .chain(Self::MEASURED)
            .map(str::to_owned)
            .collect()
    }

    /// The row's cells under [`Self::csv_header`]: numbers in shortest round-trip form,
    /// an empty cell for a missing or non-finite value.
    #[must_use]
    pub fn csv_cells(&self) -> Vec<String> {
        let mut cells: Vec<String> = self.set.iter().map(|s| finite_text(s.value)).collect();
        cells.extend([
            optional_text(self.failure_time),
            optional_text(self.opening_time),
            optional_text(self.t_final),
            self.steps.to_string(),
            self.failed_steps.to_string(),
            self.branch_points.to_string(),
            self.fallback_steps.to_string(),
            self.unshifted_steps.to_string(),
            self.linear_solves.to_string(),
            optional_text(self.min_gap),
            optional_text(self.max_penetration),
            optional_text(self.top_x),
            optional_text(self.top_y),
            optional_text(self.top_theta),
            self.error.clone().unwrap_or_default(),
            finite_text(self.wall_time_s),
        ]);
        cells
    }
}

/// One line: the values set, the failure time, the top block's angle and the steps.
impl fmt::Display for SceneRow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let set: Vec<String> = self
            .set
            .iter()
            .map(|s| format!("{} = {}", s.key, s.value))
            .collect();
        let num = |v: Option<f64>| v.map_or_else(|| "none".to_owned(), |v| format!("{v:.4}"));
        let failure = self
            .failure_time
            .map_or_else(|| "never".to_owned(), |t| format!("at t = {t:.4}"));
        write!(
            f,
            "{}: failure {failure}, top theta = {} at t = {}, {} steps",
            set.join(", "),
            num(self.top_theta),
            num(self.t_final),
            self.steps
        )?;
        if let Some(c) = &self.convergence {
            f.write_str(&c.line())?;
        }
        if let Some(e) = &self.error {
            write!(f, ", error: {e}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenes;

    fn shaking() -> &'static str {
        scenes::find("shaking").unwrap().toml
    }

    fn over(text: &str) -> Override {
        text.parse().unwrap()
    }

    fn set(key: &str, value: f64) -> SetValue {
        SetValue {
            key: key.to_owned(),
            value,
        }
    }

    fn key_error(keys: &[&str]) -> String {
        let overrides = keys.iter().map(|k| over(&format!("{k}=1"))).collect();
        let e = SceneSweep::new(shaking(), overrides)
            .unwrap_err()
            .to_string();
        assert!(!e.contains('\n'), "{e}");
        e
    }

    #[test]
    fn overrides_read_key_equals_values() {
        let o = over("contact.mu=0:0.5:0.05");
        assert_eq!(o.key, "contact.mu");
        assert_eq!(o.values.len(), 11);
        assert!(o.values.contains(&0.15) && o.values.contains(&0.35));
        assert_eq!(over(" base.omega = 2,4,8").values, vec![2.0, 4.0, 8.0]);
        for bad in [
            "contact.mu",
            "=1",
            "contact.mu=",
            "contact.mu=1,x",
            "a=1:2:0",
        ] {
            assert!(bad.parse::<Override>().is_err(), "{bad}");
        }
    }

    #[test]
    fn overrides_change_the_scene_through_the_loader() {
        let sweep = SceneSweep::new(
            shaking(),
            vec![
                over("contact.mu=0.3"),
                over("base.omega=6"),
                over("blocks.0.width=0.25"),
                over("blocks.count=2"),
                over("contact.e_n=0.5"),
            ],
        )
        .unwrap();
        let point = &sweep.points()[0];
        let file = sweep.file(point).unwrap();
        assert_eq!(file.contact.mu, 0.3);
        assert_eq!(file.contact.e_n, Some(0.5));
        assert_eq!(file.base.omega, Some(6.0));
        assert_eq!((file.blocks[0].width, file.blocks[0].count), (0.25, 2));
        let scene = sweep.scene(point).unwrap().scene;
        assert_eq!(scene.n_blocks(), 2);
        // steps_per_period = 100 follows the new omega.
        assert!((scene.solver.dt - 2.0 * std::f64::consts::PI / 600.0).abs() < 1e-15);
    }

    #[test]
    fn setting_one_of_two_alternatives_drops_the_other() {
        let sweep = SceneSweep::new(
            shaking(),
            vec![over("solver.dt=0.02"), over("solver.t_end=0.1")],
        )
        .unwrap();
        let file = sweep.file(&sweep.points()[0]).unwrap();
        assert_eq!(
            (file.solver.dt, file.solver.steps_per_period),
            (Some(0.02), None)
        );
        assert_eq!((file.solver.t_end, file.solver.periods), (Some(0.1), None));
        let scene = sweep.scene(&sweep.points()[0]).unwrap().scene;
        assert_eq!((scene.solver.dt, scene.solver.t_end), (0.02, 0.1));
    }

    #[test]
    fn absent_tables_are_added() {
        let lire = scenes::find("lire").unwrap().toml;
        assert!(crate::Scene::from_toml(lire).unwrap().floor().is_none());
        let sweep = SceneSweep::new(lire, vec![over("floor.y=-5")]).unwrap();
        let scene = sweep.scene(&sweep.points()[0]).unwrap().scene;
        assert_eq!(scene.floor().map(|f| f.y), Some(-5.0));
    }

    #[test]
    fn base_keys_go_to_the_table_of_their_component() {
        use crate::base::BaseMotion;
        let text = "[base]\nwidth = 1\nheight = 0.1\n[base.x]\nmotion = \"pulse\"\nshape = \"one-sine\"\namplitude = 0.1\nperiod = 1\n[[blocks]]\nwidth = 0.2\nheight = 0.4\n[contact]\nmu = 0.5\n";
        let sweep = SceneSweep::new(
            text,
            vec![
                over("base.amplitude=0.3"),
                over("base.y.period=0.5"),
                over("base.width=2"),
            ],
        )
        .unwrap();
        let point = &sweep.points()[0];
        let file = sweep.file(point).unwrap();
        assert_eq!(file.base.x.as_ref().unwrap().amplitude, Some(0.3));
        assert_eq!(file.base.amplitude, None);
        assert_eq!(file.base.y.as_ref().unwrap().period, Some(0.5));
        assert_eq!(file.base.width, 2.0);
        // [base.y] has a period but no motion: the loader says what is wrong.
        let e = sweep.scene(point).unwrap_err().to_string();
        assert!(
            e.contains("base.y key 'period' does not apply to motion \"fixed\""),
            "{e}"
        );
        let scene = SceneSweep::new(text, vec![over("base.amplitude=0.3")]).unwrap();
        let base = scene
            .scene(&scene.points()[0])
            .unwrap()
            .scene
            .base()
            .clone();
        assert!(matches!(base.motion, BaseMotion::Pulse(p) if p.amplitude == 0.3));
        // A record's key on a harmonic base given by the keys of [base] is judged
        // against that motion.
        let shaking = scenes::find("shaking").unwrap().toml;
        let scaled = SceneSweep::new(shaking, vec![over("base.scale=2")]).unwrap();
        let e = scaled.scene(&scaled.points()[0]).unwrap_err().to_string();
        assert!(
            e.contains("base.x key 'scale' does not apply to motion \"harmonic\""),
            "{e}"
        );
        assert!(key_error(&["base.z.amplitude"]).contains("not a component"));
        assert!(key_error(&["base.y.width"]).contains("the base's own"));
        assert!(key_error(&["base.amplitude", "base.x.amplitude"]).contains("same number"));
    }

    #[test]
    fn unknown_keys_are_one_line_naming_the_keys_of_their_table() {
        let e = key_error(&["contact.muu"]);
        assert!(
            e.contains("'contact.muu'") && e.contains("mu, e_n, e_f"),
            "{e}"
        );
        let e = key_error(&["colour.red"]);
        assert!(e.contains("base, blocks, contact, solver, floor"), "{e}");
        let e = key_error(&["base.motion"]);
        assert!(
            e.contains("not a number") && e.contains("width, height, amplitude"),
            "{e}"
        );
        let e = key_error(&["blocks.1.width"]);
        assert!(e.contains("1 [[blocks]] entry"), "{e}");
        assert!(key_error(&["blocks.first.width"]).contains("entry number"));
        assert!(key_error(&["blocks.0.colour"]).contains("mass, count"));
        assert!(key_error(&["contact"]).contains("contact.KEY"));
        assert!(key_error(&["contact.mu.x"]).contains("contact.KEY"));
        assert!(key_error(&["contact.mu", "contact.mu"]).contains("same number"));
        assert!(key_error(&["blocks.width", "blocks.0.width"]).contains("same number"));
        assert!(key_error(&["solver.dt", "solver.steps_per_period"]).contains("same number"));
        assert!(SceneSweep::new("[base]\n", vec![]).is_err());
    }

    #[test]
    fn the_numeric_keys_are_every_key_of_a_scene_file() {
        // A file with every key given: its keys are NUMERIC_KEYS and OTHER_KEYS, the keys
        // of a component's table ([base.y]) counted as the base's, and the contact keys
        // again in each of CONTACT_KINDS and in [[contact.pair]].
        let text = "[base]\nwidth = 1\nheight = 0.1\nmotion = \"harmonic\"\namplitude = 0.1\nomega = 1\nv0 = 1\nsamples = [[0, 0], [1, 1]]\n\
            [base.y]\nmotion = \"record\"\nshape = \"ricker\"\nperiod = 1\nstart = 0\nrecord = \"r.csv\"\ndt = 1\nscale = 1\nscale_to_pga = 1\nunits = \"g\"\nbaseline = \"none\"\n\
            [[blocks]]\nwidth = 1\nheight = 1\nmass = 1\ncount = 1\nx = 0\ny = 1\ntheta = 0\nname = \"a\"\n\
            [contact]\nmu = 0.1\ne_n = 0\ne_f = 0\n\
            [contact.base]\nmu = 0.1\ne_n = 0\ne_f = 0\n[contact.blocks]\nmu = 0.1\ne_n = 0\ne_f = 0\n\
            [contact.floor]\nmu = 0.1\ne_n = 0\ne_f = 0\n\
            [[contact.pair]]\nbodies = [\"a\", \"base\"]\nmu = 0.1\ne_n = 0\ne_f = 0\n\
            [solver]\ndt = 0.1\nsteps_per_period = 1\nt_end = 1\nperiods = 1\nrho_inf = 0.5\nr = 1\nr_alpha = 1\ntol = 1e-9\ngravity = 1\n\
            [floor]\ny = 0\n";
        let file = SceneFile::parse(text).unwrap();
        fn keys_of(prefix: &str, v: &toml::Value, out: &mut Vec<String>) {
            let inner = match v {
                toml::Value::Array(a) if a[0].is_table() => a[0].as_table().unwrap(),
                toml::Value::Table(t) => t,
                _ => return out.push(prefix.to_owned()),
            };
            for (k, v) in inner {
                keys_of(&format!("{prefix}.{k}"), v, out);
            }
        }
        let mut seen = Vec::new();
        for (table, v) in &toml::Table::try_from(&file).unwrap() {
            keys_of(table, v, &mut seen);
        }
        // A component's keys (base.y.motion) are the base's (base.motion).
        for key in &mut seen {
            for c in BASE_COMPONENTS {
                if let Some(rest) = key.strip_prefix(&format!("base.{c}.")) {
                    *key = format!("base.{rest}");
                }
            }
        }
        let contact = NUMERIC_KEYS
            .iter()
            .find(|(t, _)| *t == "contact")
            .unwrap()
            .1;
        let mut known: Vec<String> = NUMERIC_KEYS
            .iter()
            .flat_map(|(t, keys)| keys.iter().map(move |k| format!("{t}.{k}")))
            .chain(OTHER_KEYS.iter().map(|(t, k)| match (*t, *k) {
                ("contact", "bodies") => "contact.pair.bodies".to_owned(),
                _ => format!("{t}.{k}"),
            }))
            .chain(
                CONTACT_KINDS
                    .iter()
                    .chain(&["pair"])
                    .flat_map(|kind| contact.iter().map(move |k| format!("contact.{kind}.{k}"))),
            )
            .collect();
        seen.sort();
        seen.dedup();
        known.sort();
        assert_eq!(seen, known);
    }

    #[test]
    fn contact_keys_of_a_kind_or_a_pair_set_their_override() {
        let text = shaking().replace(
            "[[blocks]]",
            "[[blocks]]\nwidth = 0.2\nheight = 0.4\nname = \"first\"\n[[blocks]]",
        ) + "\n[[contact.pair]]\nbodies = [\"base\", \"first\"]\nmu = 0.9\n";
        let sweep = SceneSweep::new(
            &text,
            vec![
                over("contact.base.mu=0.05"),
                over("contact.floor.e_n=0.5"),
                over("contact.pair.0.e_f=0.25"),
            ],
        )
        .unwrap();
        let scene = sweep.scene(&sweep.points()[0]).unwrap().scene;
        let m = scene.materials();
        assert_eq!((m.base.mu, m.floor.e_n), (Some(0.05), Some(0.5)));
        assert_eq!(
            (m.pairs[0].params.mu, m.pairs[0].params.e_f),
            (Some(0.9), Some(0.25))
        );
        let e = key_error(&["contact.pair.0.mu"]);
        assert!(e.contains("the scene has 0"), "{e}");
        let e = key_error(&["contact.walls.mu"]);
        assert!(e.contains("contact.base.KEY"), "{e}");
        assert!(key_error(&["contact.base.muu"]).contains("mu, e_n, e_f"));
        assert!(key_error(&["contact.base.mu", "contact.base.mu"]).contains("same number"));
    }

    #[test]
    fn the_product_varies_the_first_override_slowest() {
        let o = [over("a.x=1,2"), over("b.y=3:5:1")];
        let points = cartesian_product(&o);
        let values: Vec<(f64, f64)> = points.iter().map(|p| (p[0].value, p[1].value)).collect();
        assert_eq!(
            values,
            [
                (1.0, 3.0),
                (1.0, 4.0),
                (1.0, 5.0),
                (2.0, 3.0),
                (2.0, 4.0),
                (2.0, 5.0)
            ]
        );
        assert!(points
            .iter()
            .all(|p| p[0].key == "a.x" && p[1].key == "b.y"));
        assert_eq!(cartesian_product(&[]), vec![Vec::<SetValue>::new()]);
    }

    #[test]
    fn a_bad_value_or_a_stopped_run_is_the_rows_error() {
        let sweep = SceneSweep::new(
            shaking(),
            vec![over("contact.mu=-0.1,0.2"), over("blocks.count=1.5,1")],
        )
        .unwrap();
        let options = RunOptions {
            t_end: Some(0.05),
            ..RunOptions::default()
        };
        let rows: Vec<SceneRow> = sweep
            .points()
            .iter()
            .map(|p| sweep.row(p, &options))
            .collect();
        assert_eq!(rows.len(), 4);
        assert!(
            rows[0].error.as_deref().is_some_and(|e| e.contains("mu")),
            "{:?}",
            rows[0]
        );
        assert!(rows[1].error.as_deref().is_some_and(|e| e.contains("mu")));
        let e = rows[2].error.as_deref().unwrap();
        assert!(e.contains("blocks.count must be a whole number"), "{e}");
        let good = &rows[3];
        assert!(good.error.is_none() && good.steps > 0, "{good:?}");
        // Steps of 2π/400: the last one passes t_end = 0.05.
        assert!(
            good.t_final.is_some_and(|t| (0.05..0.07).contains(&t)),
            "{good:?}"
        );
        assert!(good.top_theta.is_some_and(|a| a.abs() < 1e-3));
        // Failed rows keep their values and leave the measured cells empty.
        let cells = rows[0].csv_cells();
        assert_eq!(cells.len(), sweep.csv_header().len());
        assert_eq!(cells[..4], ["-0.1", "1.5", "", ""]);
        assert_eq!(
            sweep
                .row(&[set("contact.e_f", 0.0)], &options)
                .error
                .as_deref(),
            Some("scene key 'contact.e_f' is not swept here")
        );
        let text = rows[3].to_string();
        assert!(
            text.starts_with("contact.mu = 0.2, blocks.count = 1: failure never"),
            "{text}"
        );
    }

    #[test]
    fn a_row_projected_past_the_time_bound_is_stopped_naming_force() {
        let sweep = SceneSweep::new(shaking(), vec![over("contact.mu=0.2,0.3")]).unwrap();
        // A bound of a microsecond: every row of 100 steps is projected past it.
        let options = RunOptions {
            t_end: Some(0.5),
            time_bound: Some(1e-6),
            ..RunOptions::default()
        };
        for p in sweep.points() {
            let row = sweep.row(&p, &options);
            let e = row.error.as_deref().unwrap_or_default();
            assert!(
                e.starts_with(crate::simulation::STOPPED_BY_WATCHDOG),
                "{row:?}"
            );
            assert!(e.contains("--force") && !e.contains('\n'), "{e}");
        }
    }

    #[test]
    fn the_header_puts_the_keys_first() {
        let sweep = SceneSweep::new(
            shaking(),
            vec![over("contact.mu=0.1"), over("base.omega=1")],
        )
        .unwrap();
        let header = sweep.csv_header();
        assert_eq!(header[..2], ["contact.mu", "base.omega"]);
        assert_eq!(header[2..], SceneRow::MEASURED);
        assert_eq!(sweep.keys(), ["contact.mu", "base.omega"]);
    }
}
