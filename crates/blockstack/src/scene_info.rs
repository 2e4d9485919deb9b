//! What a user should know about a scene besides its numbers: the keys a scene file left
//! to their defaults ([`Defaults`]), what the scene may do that its author may not expect
//! ([`SceneWarning`], [`Scene::warnings`]), and the parameters a run really uses
//! ([`SceneReport`]: Δt, t_end, steps per base period, …, after defaults and overrides).
//!
//! ```
//! use blockstack::scene_file::LoadedScene;
//! use blockstack::{RunOptions, SceneReport, SceneWarning};
//!
//! let text = "[base]\nwidth = 1.0\nheight = 0.1\n\
//!             [[blocks]]\nwidth = 0.2\nheight = 0.4\n\
//!             [contact]\nmu = 0.2\n";
//! let loaded = LoadedScene::from_toml(text)?;
//! // No [solver] table: the thesis's Δt = 0.01, t_end = 10, g = 1, … were taken.
//! assert_eq!(loaded.defaults.get("solver.dt"), Some(0.01));
//! assert_eq!(loaded.defaults.get("solver.gravity"), Some(1.0));
//! // No [floor]: a block that leaves the base would fall without limit.
//! assert!(matches!(loaded.scene.warnings()[..], [SceneWarning::NoFloor { .. }]));
//! let report = SceneReport::new(&loaded.scene, &RunOptions::default(), &loaded.defaults);
//! assert_eq!((report.steps, report.t_end), (1000, 10.0));
//! # Ok::<(), blockstack::BlockError>(())
//! ```

use crate::coordinates::Vec2;
use crate::overlap::extent;
use crate::scene::{Prox, Scene};
use crate::simulation::{step_count, RunOptions};
use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;

/// The optional keys a scene file left out (`solver.dt`, `contact.e_n`, `floor.y`, …) and
/// the values they took, in the order the loader resolved them. Serializes as a JSON
/// object keyed by the key.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Defaults(Vec<(&'static str, f64)>);

impl Defaults {
    /// `given`, or `default` recorded as taken for `key`.
    pub fn or(&mut self, key: &'static str, given: Option<f64>, default: f64) -> f64 {
        given.unwrap_or_else(|| {
            self.0.push((key, default));
            default
        })
    }

    /// The value `key` took by default, if it did.
    #[must_use]
    pub fn get(&self, key: &str) -> Option<f64> {
        self.0.iter().find(|(k, _)| *k == key).map(|(_, v)| *v)
    }

    /// The keys and values, in order.
    pub fn iter(&self) -> impl Iterator<Item = (&'static str, f64)> + '_ {
        self.0.iter().copied()
    }

    /// Whether no default was taken.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The same without `key` (a run option overrode it).
    #[must_use]
    pub fn without(&self, key: &str) -> Self {
        Self(self.0.iter().copied().filter(|(k, _)| *k != key).collect())
    }
}

impl Serialize for Defaults {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (k, v) in &self.0 {
            map.serialize_entry(k, v)?;
        }
        map.end()
    }
}

impl fmt::Display for Defaults {
    /// `solver.dt = 0.01, solver.t_end = 10`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let parts: Vec<String> = self
            .0
            .iter()
            .map(|(k, v)| format!("{k} = {}", short(*v)))
            .collect();
        f.write_str(&parts.join(", "))
    }
}

/// Something a valid scene may do that its author may not expect. It serializes as its
/// message.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneWarning {
    /// The scene has no floor, so a block that slides or topples off the base (or off
    /// the block below) falls freely, without limit: its y decreases like −g t²/2 until
    /// t_end. The criterion is only "no floor": any block can leave the base by toppling.
    NoFloor {
        /// Blocks (1-based, bottom to top) whose initial horizontal extent already reaches
        /// beyond the base's edges.
        beyond_base: Vec<usize>,
    },
    /// Blocks that rest on nothing at the start (given a height in the air, or beside
    /// the bodies below them): they have no interface ([`crate::arrangement`]) and fall
    /// until they meet a body or the floor.
    RestsOnNothing {
        /// The blocks (1-based, in the scene's order), as messages name them
        /// (`block 3 (statue)`).
        blocks: Vec<String>,
    },
}

impl fmt::Display for SceneWarning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::RestsOnNothing { blocks } => match blocks.as_slice() {
                [one] => write!(
                    f,
                    "{one} rests on nothing at the start (no base or block under its bottom face, no floor): it falls"
                ),
                many => write!(
                    f,
                    "{} rest on nothing at the start (no base or block under their bottom faces, no floor): they fall",
                    many.join(", ")
                ),
            },
            Self::NoFloor { beyond_base } => {
                write!(
                    f,
                    "no floor: a block that slides or topples off the base falls freely, \
                     without limit (a [floor] table in a scene file lands it)"
                )?;
                match beyond_base.as_slice() {
                    [] => Ok(()),
                    [k] => write!(f, "; block {k} already reaches beyond the base's edge"),
                    ks => {
                        let list: Vec<String> = ks.iter().map(ToString::to_string).collect();
                        write!(
                            f,
                            "; blocks {} already reach beyond the base's edge",
                            list.join(", ")
                        )
                    }
                }
            }
        }
    }
}

impl Serialize for SceneWarning {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

/// Relative tolerance of "beyond the base's edge" (of the base width).
const EDGE_TOL: f64 = 1e-9;

impl Scene {
    /// What this scene may do unexpectedly (docs/scenes.md, "Warnings"): a scene
    /// without a floor gets [`SceneWarning::NoFloor`], naming the blocks that start
    /// beyond the edges of the base (their corners' x range at t = 0 against the base's);
    /// blocks that rest on no body and not on the floor, [`SceneWarning::RestsOnNothing`].
    #[must_use]
    pub fn warnings(&self) -> Vec<SceneWarning> {
        let mut out = Vec::new();
        if self.floor().is_none() {
            let base = self.base();
            let half = 0.5 * base.width();
            let x0 = base.state(0.0).pose.x;
            let tol = EDGE_TOL * base.width();
            let beyond_base = self
                .blocks()
                .iter()
                .enumerate()
                .filter(|(_, b)| {
                    let th = b.initial.theta;
                    let reach =
                        0.5 * b.width() * th.cos().abs() + 0.5 * b.height() * th.sin().abs();
                    (b.initial.x - x0).abs() + reach > half + tol
                })
                .map(|(k, _)| k + 1)
                .collect();
            out.push(SceneWarning::NoFloor { beyond_base });
        }
        let falling: Vec<String> = (1..=self.n_blocks())
            .filter(|&k| {
                self.arrangement().seats_of(k).is_empty() && !self.on_floor(k) && !self.on_a_body(k)
            })
            .map(|k| self.body_label(crate::overlap::Body::Block(k)))
            .collect();
        if !falling.is_empty() {
            out.push(SceneWarning::RestsOnNothing { blocks: falling });
        }
        out
    }

    /// Whether block k (1-based) starts with its lowest point on the highest point of
    /// another body (the base or a block, within `REST_TOL` of its height) and over that
    /// body along a positive length: a block lying on its side across others, which has
    /// no interface (those join faces turned by less than 90°) but rests on them
    /// through corner contacts. Both bodies' extents are their corners' ranges at t = 0.
    fn on_a_body(&self, k: usize) -> bool {
        let extent = |j: usize| {
            let pose = if j == 0 {
                self.base().state(0.0).pose
            } else {
                self.blocks()[j - 1].initial
            };
            let size = self.size(j);
            let c = crate::corners::corners(&pose, size.width, size.height);
            let along = |x: f64, y: f64| extent(&c, &Vec2::new(x, y));
            (along(1.0, 0.0), along(0.0, 1.0))
        };
        let ((left, right), (low, _)) = extent(k);
        let tol = crate::arrangement::REST_TOL * self.size(k).height;
        (0..=self.n_blocks()).filter(|&j| j != k).any(|j| {
            let ((l, r), (_, top)) = extent(j);
            (low - top).abs() <= tol && left.max(l) < right.min(r)
        })
    }

    /// Whether block k (1-based) starts with its lowest corner on the floor.
    fn on_floor(&self, k: usize) -> bool {
        self.floor().is_some_and(|floor| {
            let b = &self.blocks()[k - 1];
            let low = b.initial.y - b.half_vertical_extent(b.initial.theta);
            low - floor.y <= crate::arrangement::REST_TOL * b.height()
        })
    }
}

/// The parameters a run of a scene really uses, after the scene file's defaults and the
/// run's overrides (`--t-end`, `--prox-constant`): what `rollstack blocks run` prints and
/// writes into run.json as `scene`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneReport {
    /// Number of free blocks.
    pub blocks: usize,
    /// The base's motion along x: `fixed`, `harmonic`, `constant-velocity`,
    /// `displacement`, `pulse` or `record`.
    pub motion: &'static str,
    /// The motions of the base's other components that move, `y` and `rotation`, by
    /// component (absent from the JSON when the base moves along x only).
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub other_motions: BTreeMap<&'static str, &'static str>,
    /// Height of the floor (length units), or null without a floor.
    pub floor: Option<f64>,
    /// Friction coefficient μ (dimensionless).
    pub mu: f64,
    /// Normal restitution e_N.
    pub e_n: f64,
    /// Tangential restitution e_F.
    pub e_f: f64,
    /// The overrides of μ, e_N, e_F per kind of interface and per pair, one line each
    /// (`base: mu = 0.1`, `drum3/capital: e_n = 0.2`); absent from JSON when none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub materials: Vec<String>,
    /// Time step Δt (model time units).
    pub dt: f64,
    /// End time of the run (model time units).
    pub t_end: f64,
    /// Steps planned to reach t_end.
    pub steps: usize,
    /// Harmonic base: steps per base period, 2π/(|ω|Δt); null for other motions.
    pub steps_per_period: Option<f64>,
    /// Harmonic base: base periods simulated, t_end|ω|/(2π); null for other motions.
    pub periods: Option<f64>,
    /// Spectral radius at infinite frequency ρ∞.
    pub rho_inf: f64,
    /// Newton tolerance.
    pub tol: f64,
    /// Gravity g (model units).
    pub gravity: f64,
    /// The prox parameter: text `scaled, alpha = 1` or `constant r = 0.3`, JSON
    /// `"scaled(alpha=1)"` or `"constant(r=0.3)"` ([`Prox::label`]).
    #[serde(serialize_with = "serialize_prox")]
    pub prox: Prox,
    /// The scene-file keys that took their defaults, with their values (empty for scenes
    /// built in code); a key a run option overrides is not listed.
    pub defaults: Defaults,
}

/// Serializes a prox parameter as its one-token label (`"scaled(alpha=1)"`,
/// `"constant(r=0.3)"`, [`Prox::label`]).
///
/// # Errors
/// The serializer's.
pub fn serialize_prox<S: Serializer>(prox: &Prox, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&prox.label())
}

/// `v`, snapped to the nearest integer when it is one up to round-off (2π/(ω·(2π/(100ω)))
/// is 100 within a few ulps).
fn snapped(v: f64) -> f64 {
    let r = v.round();
    if (v - r).abs() <= 1e-9 * v.abs().max(1.0) {
        r
    } else {
        v
    }
}

impl SceneReport {
    /// The report of a run of `scene` with `options`; `defaults` from the scene file
    /// ([`crate::scene_file::LoadedScene::defaults`]; empty for scenes built in code).
    #[must_use]
    pub fn new(scene: &Scene, options: &RunOptions, defaults: &Defaults) -> Self {
        let s = &scene.solver;
        let t_end = options.t_end.unwrap_or(s.t_end);
        let prox: Prox = options.prox.unwrap_or(s.prox);
        let mut defaults = defaults.clone();
        if options.t_end.is_some() {
            defaults = defaults.without("solver.t_end");
        }
        if options.prox.is_some() {
            defaults = defaults.without("solver.r_alpha");
        }
        let period = scene.base().motion.period();
        Self {
            blocks: scene.n_blocks(),
            motion: scene.base().motion.name(),
            other_motions: scene.base().other_motions().into_iter().collect(),
            floor: scene.floor().map(|f| f.y),
            mu: scene.contact.mu,
            e_n: scene.contact.e_n,
            e_f: scene.contact.e_f,
            materials: scene.materials().lines(),
            dt: s.dt,
            t_end,
            steps: if t_end > 0.0 && s.dt > 0.0 {
                step_count(t_end, s.dt)
            } else {
                0
            },
            steps_per_period: period.map(|p| snapped(p / s.dt)),
            periods: period.map(|p| snapped(t_end / p)),
            rho_inf: s.rho_inf,
            tol: s.tol,
            gravity: s.gravity,
            prox,
            defaults,
        }
    }
}

impl fmt::Display for SceneReport {
    /// One line of the scene and its solver, then, if any, a line of the materials'
    /// overrides and one of the defaults taken.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let floor = self
            .floor
            .map_or_else(|| "no floor".to_owned(), |y| format!("floor at y = {y}"));
        let others: Vec<String> = self
            .other_motions
            .iter()
            .map(|(c, m)| format!("{c} {m}"))
            .collect();
        let others = if others.is_empty() {
            String::new()
        } else {
            format!(" ({})", others.join(", "))
        };
        let per = |v: Option<f64>, what: &str| {
            v.map_or_else(String::new, |n| format!(", {} {what}", short(n)))
        };
        write!(
            f,
            "scene: {} block{}, base {}{others}, {floor}, mu = {}, e_n = {}, e_f = {}; dt = {}{}, t_end = {}{} ({} steps), rho_inf = {}, tol = {:e}, g = {}, prox {}",
            self.blocks,
            if self.blocks == 1 { "" } else { "s" },
            self.motion,
            self.mu,
            self.e_n,
            self.e_f,
            short(self.dt),
            per(self.steps_per_period, "steps per period"),
            short(self.t_end),
            per(self.periods, "periods"),
            self.steps,
            self.rho_inf,
            self.tol,
            self.gravity,
            self.prox,
        )?;
        if !self.materials.is_empty() {
            write!(f, "\nmaterials: {}", self.materials.join("; "))?;
        }
        if !self.defaults.is_empty() {
            write!(f, "\ndefaults taken: {}", self.defaults)?;
        }
        Ok(())
    }
}

/// Six decimals at most, no trailing zeros (`0.015708`, `15.707963`, `10`); below 1e-3,
/// the shortest exponent form (`1e-5`).
fn short(v: f64) -> String {
    if v != 0.0 && v.abs() < 1e-3 {
        return format!("{v:e}");
    }
    let text = format!("{v:.6}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" || text.is_empty() {
        "0".to_owned()
    } else {
        text.to_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_file::LoadedScene;

    const HARMONIC: &str = "[base]\nwidth = 1.0\nheight = 0.1\nmotion = \"harmonic\"\namplitude = 0.2\nomega = 4.0\n[[blocks]]\nwidth = 0.2\nheight = 0.4\ncount = 2\n[contact]\nmu = 0.2\n";

    #[test]
    fn defaults_are_listed_in_order_and_serialize_as_a_map() {
        let l = LoadedScene::from_toml(&format!("{HARMONIC}[floor]\n")).unwrap();
        let keys: Vec<&str> = l.defaults.iter().map(|(k, _)| k).collect();
        assert_eq!(
            keys,
            [
                "solver.dt",
                "solver.t_end",
                "solver.rho_inf",
                "solver.r_alpha",
                "solver.tol",
                "solver.gravity",
                "contact.e_n",
                "contact.e_f",
                "floor.y",
            ]
        );
        assert_eq!(l.defaults.get("floor.y"), Some(-0.05));
        let json = serde_json::to_value(&l.defaults).unwrap();
        assert_eq!(json["solver.t_end"], 10.0);
        assert!(l
            .defaults
            .to_string()
            .starts_with("solver.dt = 0.01, solver.t_end = 10,"));
        assert!(l.defaults.to_string().ends_with("floor.y = -0.05"));
        // Every key given: nothing defaulted.
        let full = HARMONIC.replace("mu = 0.2\n", "mu = 0.2\ne_n = 0.0\ne_f = 0.0\n")
            + "[solver]\ndt = 0.01\nt_end = 1.0\nrho_inf = 0.5\nr = 0.3\ntol = 1e-10\ngravity = 1.0\n[floor]\ny = -0.05\n";
        assert!(LoadedScene::from_toml(&full).unwrap().defaults.is_empty());
    }

    #[test]
    fn no_floor_warns_and_names_the_blocks_beyond_the_base() {
        let s = LoadedScene::from_toml(HARMONIC).unwrap().scene;
        assert_eq!(
            s.warnings(),
            [SceneWarning::NoFloor {
                beyond_base: vec![]
            }]
        );
        let with_floor = LoadedScene::from_toml(&format!("{HARMONIC}[floor]\n")).unwrap();
        assert!(with_floor.scene.warnings().is_empty());
        // The Lire tower: every block overhangs the table's right edge (w/8 for the
        // lowest).
        let lire = crate::scenarios::lire(4, crate::scenarios::Perturbation::None).unwrap();
        let w = lire.warnings();
        assert_eq!(
            w,
            [SceneWarning::NoFloor {
                beyond_base: vec![1, 2, 3, 4]
            }]
        );
        let text = w[0].to_string();
        assert!(
            text.starts_with("no floor:")
                && text.ends_with("blocks 1, 2, 3, 4 already reach beyond the base's edge"),
            "{text}"
        );
        assert_eq!(
            serde_json::to_value(&w[0]).unwrap(),
            serde_json::Value::String(text)
        );
    }

    #[test]
    fn the_report_resolves_periods_and_overrides() {
        let text = format!("{HARMONIC}[solver]\nsteps_per_period = 100\nperiods = 10\n[floor]\n");
        let l = LoadedScene::from_toml(&text).unwrap();
        let r = SceneReport::new(&l.scene, &RunOptions::default(), &l.defaults);
        assert_eq!(r.steps_per_period, Some(100.0));
        assert_eq!(r.periods, Some(10.0));
        assert_eq!(r.steps, 1000);
        assert_eq!(r.motion, "harmonic");
        assert!(r.defaults.get("solver.dt").is_none() && r.defaults.get("solver.t_end").is_none());
        let line = r.to_string();
        assert!(
            line.contains(
                "dt = 0.015708, 100 steps per period, t_end = 15.707963, 10 periods (1000 steps)"
            ),
            "{line}"
        );
        // --t-end and --prox-constant replace the scene's values and their defaults.
        let l = LoadedScene::from_toml(HARMONIC).unwrap();
        let options = RunOptions {
            t_end: Some(0.5),
            prox: Some(Prox::Constant(0.3)),
            ..RunOptions::default()
        };
        let r = SceneReport::new(&l.scene, &options, &l.defaults);
        assert_eq!((r.t_end, r.steps, r.prox), (0.5, 50, Prox::Constant(0.3)));
        assert!(r
            .to_string()
            .contains(", prox constant r = 0.3\ndefaults taken: "));
        assert_eq!(serde_json::to_value(&r).unwrap()["prox"], "constant(r=0.3)");
        assert!(r.defaults.get("solver.t_end").is_none());
        assert!(r.defaults.get("solver.r_alpha").is_none());
        assert_eq!(r.defaults.get("solver.dt"), Some(0.01));
        assert!(r.to_string().contains("\ndefaults taken: solver.dt = 0.01"));
        assert_eq!(short(1e-10), "1e-10");
        assert_eq!(short(2.5), "2.5");
    }
}
