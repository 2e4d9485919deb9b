//! Scene files (TOML): the base, the blocks bottom to top, contact, solver and floor
//! parameters. Unknown keys are errors; every error is one line. docs/scenes.md lists
//! every key with its unit, default and meaning; [`crate::scenes`] holds the built-in
//! scenes.
//!
//! ```toml
//! [base]
//! width = 1.0
//! height = 0.1
//! motion = "harmonic"        # "fixed" | "harmonic" | "constant-velocity" | "displacement"
//! amplitude = 0.2            # harmonic: x = amplitude · sin(omega · t)
//! omega = 4.0
//! # v0 = 1.0                 # constant-velocity
//! # samples = [[0.0, 0.0], [0.5, 0.1], [1.0, 0.0]]   # displacement: [t, x] pairs
//!
//! [[blocks]]                 # bottom to top
//! width = 0.2
//! height = 0.4
//! mass = 1.0                 # default 1
//! count = 4                  # default 1: repeated identical blocks
//! # x = 0.0                  # initial x of the centre (default 0)
//! # y = 0.25                 # initial y (default: resting on the block listed before)
//! # on = ["left", "right"]   # or rest on these bodies ("base" or blocks' names, listed before)
//! # theta = 0.0              # initial angle, radians (default 0)
//! # velocity = [0.0, 0.0, 0.0]   # initial [vx, vy, omega] (default: at rest)
//! # name = "capital"         # for [[contact.pair]] (an entry with count = 1 only)
//!
//! [contact]                  # the defaults of every contact
//! mu = 0.2
//! e_n = 0.0                  # default 0
//! e_f = 0.0                  # default 0
//! # neighbours_only = true   # default false: a block touches only the bodies beneath and above it
//! # [contact.base]           # optional, any of mu, e_n, e_f: base–block interfaces
//! # mu = 0.1                 # ([contact.blocks]: block–block, [contact.floor]: block–floor)
//! # [[contact.pair]]         # optional: one pair of bodies, over its kind's values
//! # bodies = ["base", "capital"]   # base, floor, or a block's name = "..."
//! # mu = 0.6
//!
//! [solver]                   # all optional
//! steps_per_period = 100     # harmonic base only; or dt = 0.0157... (default dt 0.01)
//! periods = 10               # harmonic base only; or t_end = 15.7... (default t_end 10)
//! rho_inf = 0.5
//! # r = 0.3                  # constant prox parameter; absent: scaled per constraint
//! r_alpha = 1.0              # alpha of the scaled prox parameter
//! tol = 1e-10
//! gravity = 1.0
//!
//! [floor]                    # optional: a fixed plane, by default at the base's bottom
//! # y = -0.05
//! ```
//!
//! Block heights are stacked automatically: each block's lowest point rests on the top of
//! the block listed before it, or with `on` on the highest top of the bodies it names
//! (docs/scenes.md, "Any arrangement"). Which bodies each block then rests on, the
//! scene's interfaces, is found from the poses ([`crate::arrangement`]). [`LoadedScene::defaults`] lists the keys a file left out and the
//! values they took; [`Scene::warnings`] says what the scene may do unexpectedly (no
//! floor).

use crate::base::{Base, BaseMotion};
use crate::block::Block;
use crate::error::BlockError;
use crate::floor::Floor;
use crate::materials::{Materials, Override, PairMaterial};
use crate::overlap::Body;
use crate::scene::{check_block_count, stack_on_top, ContactParams, Prox, Scene, SolverParams};
use crate::scene_base::{Component, MotionContext, MotionFile};
use crate::scene_info::Defaults;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The largest scene file a reader takes, bytes (16 MiB): a scene is a few hundred bytes
/// (one `[[blocks]]` entry with every key for each of the most blocks,
/// [`crate::scene::MAX_BLOCKS`], is 200 kB), so a larger file is not a scene
/// (`/dev/zero`) and is refused before it fills the memory.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// The `[base]` table.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseFile {
    /// Width w⁰.
    pub width: f64,
    /// Height h⁰.
    pub height: f64,
    /// "fixed" (default), "harmonic", "constant-velocity" or "displacement".
    #[serde(default = "fixed")]
    pub motion: String,
    /// Harmonic amplitude A.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    /// Harmonic angular frequency ω.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub omega: Option<f64>,
    /// Constant velocity v₀.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v0: Option<f64>,
    /// Displacement samples [t, x].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<Vec<[f64; 2]>>,
    /// The motion along E₁ as a table of its own (any motion), instead of the keys above.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub x: Option<MotionFile>,
    /// The motion along E₂ (absent: fixed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<MotionFile>,
    /// The rotation about the base's centre (absent: fixed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation: Option<MotionFile>,
}

fn fixed() -> String {
    "fixed".into()
}

/// One `[[blocks]]` entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlockFile {
    /// Width w.
    pub width: f64,
    /// Height h.
    pub height: f64,
    /// Mass m (default 1).
    #[serde(default = "one")]
    pub mass: f64,
    /// Initial x of the centre (default 0).
    #[serde(default)]
    pub x: f64,
    /// Initial y of the centre (default: resting on the block below).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<f64>,
    /// Initial angle θ in radians (default 0).
    #[serde(default)]
    pub theta: f64,
    /// Number of identical blocks (default 1): an integer, or a decimal that is one
    /// (`count = 2.0`), as every number of the file may be written.
    #[serde(default = "one_count", deserialize_with = "whole_count")]
    pub count: usize,
    /// Initial velocity [v_x, v_y, ω] of the centre (default: at rest).
    #[serde(default, skip_serializing_if = "is_at_rest")]
    pub velocity: [f64; 3],
    /// A name, for `[[contact.pair]] bodies` and `on` (an entry of one block only).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
    /// The bodies the block rests on (`"base"` or blocks' names, listed before it): its
    /// y puts its lowest point on the highest of their tops. Absent (and no `y`): on the
    /// block listed just before it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub on: Option<OnBodies>,
}

/// `on = "name"` or `on = ["name", "name"]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum OnBodies {
    /// One body.
    One(String),
    /// Several bodies (a lintel on two posts).
    Many(Vec<String>),
}

impl OnBodies {
    /// The names given.
    #[must_use]
    pub fn names(&self) -> &[String] {
        match self {
            Self::One(name) => std::slice::from_ref(name),
            Self::Many(names) => names,
        }
    }
}

fn is_at_rest(v: &[f64; 3]) -> bool {
    *v == [0.0; 3]
}

fn one() -> f64 {
    1.0
}

fn one_count() -> usize {
    1
}

/// Reads `count` from an integer or an integral decimal (`2.0`), refusing `2.5` and
/// negative numbers with a message that names the key.
fn whole_count<'de, D: serde::Deserializer<'de>>(d: D) -> Result<usize, D::Error> {
    struct Count;
    impl serde::de::Visitor<'_> for Count {
        type Value = usize;

        fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str("a whole number of blocks")
        }

        fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<usize, E> {
            usize::try_from(v).map_err(|_| E::custom(format!("count = {v} is too large")))
        }

        fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<usize, E> {
            let v = u64::try_from(v)
                .map_err(|_| E::custom(format!("count must not be negative, got {v}")))?;
            self.visit_u64(v)
        }

        fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<usize, E> {
            // Below 2^53 every whole decimal is exact, so the cast keeps its value.
            if v.fract() == 0.0 && (0.0..9.007_199_254_740_992e15).contains(&v) {
                #[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)]
                return Ok(v as usize);
            }
            Err(E::custom(format!(
                "count must be a whole number of blocks, got {}",
                input::Short(v)
            )))
        }
    }
    d.deserialize_any(Count)
}

/// The `[contact]` table: the defaults of every contact, and their overrides per kind of
/// interface and per pair of bodies ([`crate::materials`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    /// Friction coefficient μ (dimensionless, ≥ 0) of every contact not overridden.
    pub mu: f64,
    /// Normal restitution e_N ∈ [0, 1] (absent: 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e_n: Option<f64>,
    /// Tangential restitution e_F ∈ [0, 1] (absent: 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e_f: Option<f64>,
    /// Contacts between the bodies an interface joins only, as in the thesis's code
    /// ([`Scene::neighbours_only`]; absent: false, any two bodies may touch).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub neighbours_only: Option<bool>,
    /// `[contact.base]`: base–block interfaces.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub base: Option<Override>,
    /// `[contact.blocks]`: block–block interfaces.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blocks: Option<Override>,
    /// `[contact.floor]`: block–floor contacts.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor: Option<Override>,
    /// `[[contact.pair]]`: one pair of bodies each.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub pair: Vec<PairFile>,
}

/// One `[[contact.pair]]` entry: two bodies by name (`base`, `floor`, or a block's
/// `name`) and the values that override their kind's.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PairFile {
    /// The two bodies' names.
    pub bodies: [String; 2],
    /// Any of `mu`, `e_n`, `e_f`.
    #[serde(flatten)]
    pub params: Override,
}

impl<'de> Deserialize<'de> for PairFile {
    /// `bodies`, and the rest of the entry as an [`Override`] (which refuses unknown
    /// keys: serde's `flatten` would let them pass).
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        use serde::de::Error;
        let mut entry = toml::Table::deserialize(d)?;
        let bodies = entry
            .remove("bodies")
            .ok_or_else(|| D::Error::missing_field("bodies"))?
            .try_into()
            .map_err(|e: toml::de::Error| D::Error::custom(format!("bodies: {}", e.message())))?;
        let params = toml::Value::Table(entry)
            .try_into()
            .map_err(|e: toml::de::Error| D::Error::custom(e.message()))?;
        Ok(Self { bodies, params })
    }
}

impl ContactFile {
    /// The overrides, with the pairs' names resolved against the blocks' `names` (one
    /// per block, bottom to top).
    fn materials(&self, names: &[Option<String>]) -> Result<Materials, BlockError> {
        let pairs = self
            .pair
            .iter()
            .enumerate()
            .map(|(k, p)| {
                let body = |name: &str| {
                    body_named(name, names)
                        .map_err(|why| BlockError::Scene(format!("contact.pair.{k} bodies: {why}")))
                };
                Ok(PairMaterial {
                    bodies: [body(&p.bodies[0])?, body(&p.bodies[1])?],
                    label: format!("{}/{}", p.bodies[0], p.bodies[1]),
                    params: p.params,
                })
            })
            .collect::<Result<_, BlockError>>()?;
        Ok(Materials {
            base: self.base.unwrap_or_default(),
            blocks: self.blocks.unwrap_or_default(),
            floor: self.floor.unwrap_or_default(),
            pairs,
        })
    }
}

/// The body a scene file calls `name`: `base`, `floor`, or the block of that `name`.
fn body_named(name: &str, names: &[Option<String>]) -> Result<Body, String> {
    match name {
        "base" => return Ok(Body::Base),
        "floor" => return Ok(Body::Floor),
        _ => {}
    }
    if let Some(k) = names.iter().position(|n| n.as_deref() == Some(name)) {
        return Ok(Body::Block(k + 1));
    }
    let known: Vec<&str> = ["base", "floor"]
        .into_iter()
        .chain(names.iter().flatten().map(String::as_str))
        .collect();
    Err(format!(
        "no body named \"{name}\" (bodies with names: {}; a block is named by its [[blocks]] key name)",
        known.join(", ")
    ))
}

/// The highest point of a placed block.
fn top_of_block(b: &Block) -> f64 {
    b.initial.y + b.half_vertical_extent(b.initial.theta)
}

/// The height a block of `[[blocks]]` entry `e` rests at with `on`: the highest top among
/// the bodies it names (`base`, or blocks listed before it, whose `names` and placed
/// `blocks` are given).
fn top_of_bodies(
    on: &OnBodies,
    e: usize,
    names: &[Option<String>],
    base: &Base,
    blocks: &[Block],
) -> Result<f64, BlockError> {
    let bad = |why: String| BlockError::Scene(format!("[[blocks]] entry {e} on: {why}"));
    let list = on.names();
    if list.is_empty() {
        return Err(bad(
            "names no body: give \"base\" or the name of a block listed before it".into(),
        ));
    }
    let mut top = f64::NEG_INFINITY;
    for name in list {
        let body = match name.as_str() {
            "floor" => {
                return Err(bad(
                    "\"floor\" is not a body to rest on: a block rests on the base or on blocks (place a block on the floor with y)"
                        .into(),
                ))
            }
            _ => body_named(name, names).map_err(|why| {
                bad(format!("{why}; a block rests on the base or on blocks listed before it"))
            })?,
        };
        top = top.max(match body {
            Body::Block(j) => top_of_block(&blocks[j - 1]),
            _ => base.top(),
        });
    }
    Ok(top)
}

/// The names of the blocks, bottom to top (`None` for a block without one).
///
/// # Errors
/// A name on an entry of several blocks, a name given twice, or `base` / `floor`.
fn block_names(entries: &[BlockFile]) -> Result<Vec<Option<String>>, BlockError> {
    let mut names: Vec<Option<String>> = Vec::new();
    for (k, entry) in entries.iter().enumerate() {
        let bad = |why: String| BlockError::Scene(format!("[[blocks]] entry {k} name: {why}"));
        if let Some(name) = &entry.name {
            if entry.count != 1 {
                return Err(bad(format!(
                    "\"{name}\" names one block, but the entry has count = {}",
                    entry.count
                )));
            }
            if name == "base" || name == "floor" || name.is_empty() {
                return Err(bad(format!(
                    "\"{name}\" is not a block name (base and floor are taken)"
                )));
            }
            if names.iter().flatten().any(|n| n == name) {
                return Err(bad(format!(
                    "\"{name}\" is already the name of another block"
                )));
            }
        }
        names.extend(std::iter::repeat_n(entry.name.clone(), entry.count));
    }
    Ok(names)
}

/// The `[solver]` table: every key optional; an absent key takes the thesis's value
/// (§4.2, [`SolverParams::default`]) and is reported ([`LoadedScene::defaults`]).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverFile {
    /// Time step Δt (model time units).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Steps per base period N, instead of `dt`: Δt = 2π/(N|ω|) (harmonic motion only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub steps_per_period: Option<f64>,
    /// End time (model time units).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t_end: Option<f64>,
    /// Base periods P, instead of `t_end`: t_end = P·2π/|ω| (harmonic motion only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub periods: Option<f64>,
    /// Spectral radius at infinite frequency ρ∞ ∈ [0, 1].
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rho_inf: Option<f64>,
    /// Constant prox parameter r > 0 (absent: scaled per constraint with `r_alpha`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r: Option<f64>,
    /// α ∈ (0, 2) of the scaled prox parameter r_k = α/(w_kᵀM⁻¹w_k).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r_alpha: Option<f64>,
    /// Newton tolerance (> 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tol: Option<f64>,
    /// Gravity g (≥ 0, acting along −y; model units: the thesis's g = 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gravity: Option<f64>,
}

/// The `[floor]` table.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FloorFile {
    /// Height of the floor (default: the base's bottom face).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub y: Option<f64>,
}

/// A whole scene file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// The base.
    pub base: BaseFile,
    /// The blocks, bottom to top.
    pub blocks: Vec<BlockFile>,
    /// Friction and restitution.
    pub contact: ContactFile,
    /// Time integration.
    #[serde(default)]
    pub solver: SolverFile,
    /// Optional floor.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub floor: Option<FloorFile>,
}

/// The height of the author's base plate (the thesis's scripts: 1 wide, 0.2 high).
pub const THESIS_BASE_HEIGHT: f64 = 0.2;

impl SceneFile {
    /// The scene as the thesis's code models it (`--preset thesis`): no floor, the base
    /// [`THESIS_BASE_HEIGHT`] high with the blocks stacked on it as the file places them,
    /// and contacts between neighbouring bodies only (`[contact] neighbours_only`).
    #[must_use]
    pub fn as_in_the_thesis_code(mut self) -> Self {
        self.floor = None;
        self.base.height = THESIS_BASE_HEIGHT;
        self.contact.neighbours_only = Some(true);
        self
    }

    /// Parses TOML text (syntax and keys only; see [`SceneFile::to_scene`]).
    ///
    /// # Errors
    /// A TOML syntax error, an unknown key, a missing key or a wrong type, as one line
    /// with its line number.
    pub fn parse(text: &str) -> Result<Self, BlockError> {
        toml::from_str(text).map_err(|e| {
            let start = e.span().map(|s| s.start.min(text.len()));
            let msg = e.message().trim().replace('\n', " ");
            BlockError::Scene(match start {
                Some(at) => {
                    let line = text[..at].lines().count().max(1);
                    match key_at(text, at) {
                        Some(key) => format!("line {line}: {key}: {msg}"),
                        None => format!("line {line}: {msg}"),
                    }
                }
                None => msg,
            })
        })
    }

    /// The base: its size and the motions of its three components.
    fn base(&self, dir: &Path) -> Result<Base, BlockError> {
        let b = &self.base;
        let context = MotionContext {
            dir,
            gravity: self
                .solver
                .gravity
                .unwrap_or(SolverParams::default().gravity),
        };
        let old = MotionFile {
            motion: Some(b.motion.clone()),
            amplitude: b.amplitude,
            omega: b.omega,
            v0: b.v0,
            samples: b.samples.clone(),
            ..MotionFile::default()
        };
        let x = match &b.x {
            Some(table) if old.name() != "fixed" || old.given_any() => {
                let _ = table;
                return Err(BlockError::Scene(
                    "the base's x motion is given both by the keys of [base] and by [base.x]: give one of them".into(),
                ));
            }
            Some(table) => table.to_motion("base.x", Component::X, context)?,
            None => {
                if matches!(old.name(), "pulse" | "record") {
                    return Err(BlockError::Scene(format!(
                        "base motion \"{}\" goes in a table of its own with its keys: [base.x] (or [base.y], [base.rotation])",
                        old.name()
                    )));
                }
                old.to_motion("base", Component::X, context)?
            }
        };
        let of = |table: &Option<MotionFile>, c: Component| {
            table.as_ref().map_or(Ok(BaseMotion::Fixed), |m| {
                m.to_motion(&format!("base.{}", c.key()), c, context)
            })
        };
        let y = of(&b.y, Component::Y)?;
        let rotation = of(&b.rotation, Component::Rotation)?;
        Ok(Base::new(b.width, b.height, x)?.moving_also(y, rotation))
    }

    /// Builds and validates the scene.
    ///
    /// # Errors
    /// As [`SceneFile::build`].
    pub fn to_scene(&self) -> Result<Scene, BlockError> {
        self.build().map(|l| l.scene)
    }

    /// Builds and validates the scene, and lists the keys that took their defaults.
    ///
    /// # Errors
    /// Negative or zero sizes and masses, μ < 0, restitution outside [0, 1], NaN,
    /// overlapping blocks, a bad base motion or solver parameter, `dt` together with
    /// `steps_per_period` (or `t_end` with `periods`), or either of those two for a
    /// base motion that is not harmonic: one line each.
    pub fn build(&self) -> Result<LoadedScene, BlockError> {
        self.build_at(Path::new(""))
    }

    /// [`SceneFile::build`] for a scene file in the directory `dir`, where the paths of
    /// its records start (`""`: the working directory).
    ///
    /// # Errors
    /// As [`SceneFile::build`], and a record that cannot be read or used (naming the
    /// file, and the line of a malformed one).
    pub fn build_at(&self, dir: &Path) -> Result<LoadedScene, BlockError> {
        let base = self.base(dir)?;
        let mut column = Vec::with_capacity(self.block_count()?);
        let names = block_names(&self.blocks)?;
        let mut k = 0;
        for (e, entry) in self.blocks.iter().enumerate() {
            if entry.y.is_some() && entry.on.is_some() {
                return Err(BlockError::Scene(format!(
                    "[[blocks]] entry {e} gives both y and on: give one of them (y places the block's centre, on rests it on bodies)"
                )));
            }
            for _ in 0..entry.count {
                k += 1;
                let [vx, vy, omega] = entry.velocity;
                let block = Block::new(entry.width, entry.height, entry.mass)
                    .and_then(|b| b.moving(vx, vy, omega))
                    .map_err(|e| name_block(e, k))?;
                column.push((block, e, entry));
            }
        }
        let mut blocks: Vec<Block> = Vec::with_capacity(column.len());
        for (k, (block, e, entry)) in column.into_iter().enumerate() {
            let name = |what: &str| format!("block {} {what}", k + 1);
            let (x, th) = (entry.x, entry.theta);
            input::finite(&name("x"), x)?;
            input::finite(&name("theta"), th)?;
            let placed = match (entry.y, &entry.on) {
                // An explicit height: taken as is (the overlap check judges it).
                (Some(y), _) => block.at(x, input::finite(&name("y"), y)?, th)?,
                (None, Some(on)) => {
                    let top = top_of_bodies(on, e, &names[..k], &base, &blocks)?;
                    stack_on_top(top, block, x, th, k)?
                }
                (None, None) => {
                    let top = blocks.last().map_or(base.top(), top_of_block);
                    stack_on_top(top, block, x, th, k)?
                }
            };
            blocks.push(placed);
        }
        let mut defaults = Defaults::default();
        let solver = self.solver_params(&base.motion, &mut defaults)?;
        let c = &self.contact;
        let contact = ContactParams {
            mu: c.mu,
            e_n: defaults.or("contact.e_n", c.e_n, 0.0),
            e_f: defaults.or("contact.e_f", c.e_f, 0.0),
        };
        let floor = self
            .floor
            .map(|f| Floor::new(defaults.or("floor.y", f.y, base.bottom())));
        let materials = c.materials(&names)?;
        let scene = Scene::named(base, blocks, floor, contact, solver, names)?
            .with_materials(materials)?
            .with_neighbours_only(c.neighbours_only.unwrap_or(false));
        Ok(LoadedScene { scene, defaults })
    }

    /// The number of blocks the `[[blocks]]` entries make, checked against
    /// [`crate::scene::MAX_BLOCKS`] before any block is built (a `count` of 10⁹ is refused, not
    /// allocated).
    fn block_count(&self) -> Result<usize, BlockError> {
        let mut total = 0usize;
        for (k, entry) in self.blocks.iter().enumerate() {
            check_block_count(&format!("[[blocks]] entry {k} count"), entry.count)?;
            // Both terms are at most MAX_BLOCKS: no overflow.
            total = check_block_count("the [[blocks]] counts' total", total + entry.count)?;
        }
        Ok(total)
    }

    /// The `[solver]` table resolved: `steps_per_period` and `periods` turned into Δt and
    /// t_end, absent keys given the defaults of [`SolverParams::default`].
    fn solver_params(
        &self,
        motion: &BaseMotion,
        defaults: &mut Defaults,
    ) -> Result<SolverParams, BlockError> {
        let s = &self.solver;
        let d = SolverParams::default();
        // The base period 2π/|ω|, for the keys that count in periods.
        let period = |key: &str| {
            motion.period().ok_or_else(|| {
                BlockError::Scene(match motion {
                    BaseMotion::Harmonic { .. } => {
                        format!("[solver] {key} needs a base that moves (omega = 0 has no period)")
                    }
                    other => format!(
                        "[solver] {key} needs a periodic base (motion = \"harmonic\"), not motion = \"{}\"",
                        other.name()
                    ),
                })
            })
        };
        let dt = match (s.dt, s.steps_per_period) {
            (Some(_), Some(_)) => {
                return Err(BlockError::Scene(
                    "[solver] gives both dt and steps_per_period: give one of them".into(),
                ))
            }
            (Some(dt), None) => dt,
            (None, Some(n)) => {
                let p = period("steps_per_period")?;
                p / input::positive("solver steps_per_period", n)?
            }
            (None, None) => defaults.or("solver.dt", None, d.dt),
        };
        let t_end = match (s.t_end, s.periods) {
            (Some(_), Some(_)) => {
                return Err(BlockError::Scene(
                    "[solver] gives both t_end and periods: give one of them".into(),
                ))
            }
            (Some(t), None) => t,
            (None, Some(n)) => {
                let p = period("periods")?;
                input::positive("solver periods", n)? * p
            }
            (None, None) => defaults.or("solver.t_end", None, d.t_end),
        };
        let rho_inf = defaults.or("solver.rho_inf", s.rho_inf, d.rho_inf);
        let prox = match s.r {
            Some(r) => Prox::Constant(r),
            None => Prox::Scaled(defaults.or("solver.r_alpha", s.r_alpha, 1.0)),
        };
        Ok(SolverParams {
            dt,
            t_end,
            rho_inf,
            prox,
            tol: defaults.or("solver.tol", s.tol, d.tol),
            gravity: defaults.or("solver.gravity", s.gravity, d.gravity),
        })
    }
}

/// A scene built from a file, with the keys the file left out and the values they took.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadedScene {
    /// The validated scene.
    pub scene: Scene,
    /// The optional keys the file did not give (`solver.dt`, `contact.e_n`, `floor.y`, …)
    /// with the values they took: solver keys first, then contact, then floor.
    pub defaults: Defaults,
}

impl LoadedScene {
    /// Parses, builds and validates a TOML scene (see docs/scenes.md).
    ///
    /// # Errors
    /// Any syntax or validation error, as one line.
    pub fn from_toml(text: &str) -> Result<Self, BlockError> {
        SceneFile::parse(text)?.build()
    }

    /// [`LoadedScene::from_toml`] for a scene file in the directory `dir`, where the
    /// paths of its records start.
    ///
    /// # Errors
    /// Any syntax or validation error, as one line.
    pub fn from_toml_at(text: &str, dir: &Path) -> Result<Self, BlockError> {
        SceneFile::parse(text)?.build_at(dir)
    }
}

/// The key whose value starts at byte `at` of a scene file, with its table
/// (`[contact] mu`), so that a wrong type names what the user wrote: toml's own message
/// ("invalid type: string \"a\", expected f64") names only the type. None when `at` is
/// not in a value (a syntax error, a missing key).
fn key_at(text: &str, at: usize) -> Option<String> {
    let line_start = text[..at].rfind('\n').map_or(0, |i| i + 1);
    let before = &text[line_start..at];
    let eq = before.rfind('=')?;
    let key = before[..eq].rsplit(['{', ',']).next()?.trim();
    if key.is_empty() || key.starts_with('#') || key.starts_with('[') {
        return None;
    }
    let table = text[..line_start].lines().rev().find_map(|l| {
        let l = l.trim();
        l.starts_with('[')
            .then(|| l.split('#').next().unwrap_or(l).trim().to_owned())
    });
    Some(match table {
        Some(t) => format!("{t} {key}"),
        None => key.to_owned(),
    })
}

/// Prefixes "block k" to the name in a block-constructor error.
fn name_block(e: BlockError, k: usize) -> BlockError {
    match e {
        BlockError::Input(e) => BlockError::Input(e.prefixed(&format!("block {k}"))),
        other => other,
    }
}

impl Scene {
    /// Parses and validates a TOML scene (keys: docs/scenes.md, [`crate::scene_file`]).
    ///
    /// # Errors
    /// Any syntax or validation error, as one line.
    pub fn from_toml(text: &str) -> Result<Self, BlockError> {
        LoadedScene::from_toml(text).map(|l| l.scene)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    const GOOD: &str = r#"
[base]
width = 1.0
height = 0.1
motion = "harmonic"
amplitude = 0.2
omega = 4.0

[[blocks]]
width = 0.2
height = 0.4
count = 4

[contact]
mu = 0.2

[floor]
"#;

    #[test]
    fn a_good_scene_parses() {
        let s = Scene::from_toml(GOOD).unwrap();
        assert_eq!(s.n_blocks(), 4);
        assert!((s.blocks()[3].initial.y - (0.05 + 1.4)).abs() < 1e-12);
        assert_eq!(s.floor().map(|f| f.y), Some(-0.05));
        assert_eq!(s.solver.prox, Prox::Scaled(1.0));
    }

    fn err(text: &str) -> String {
        let e = Scene::from_toml(text).unwrap_err().to_string();
        assert!(!e.contains('\n'), "one line: {e}");
        e
    }

    #[test]
    fn bad_scenes_are_rejected_with_one_line() {
        assert!(err(&GOOD.replace("count = 4", "count = 4\ncolour = 1")).contains("unknown field"));
        assert!(err(&GOOD.replace("width = 0.2", "width = -0.2"))
            .contains("block 1 width must be positive"));
        assert!(err(&GOOD.replace("mu = 0.2", "mu = -0.1")).contains("mu must not be negative"));
        assert!(err(&GOOD.replace("mu = 0.2", "mu = nan")).contains("mu is not finite"));
        assert!(err(&GOOD.replace("amplitude = 0.2", "")).contains("needs 'amplitude'"));
        let overlap = err(&GOOD.replace(
            "count = 4",
            "count = 2\n[[blocks]]\nwidth = 0.2\nheight = 0.4\ny = 0.7",
        ));
        assert!(overlap.contains("block 2 and block 3 overlap"), "{overlap}");
        assert!(err(&GOOD.replace("[floor]", "[floor]\ny = 0.5")).contains("floor"));
        assert!(err("[base]\nwidth = 1\n").contains("line"));
    }

    #[test]
    fn neighbours_only_is_read_and_the_thesis_model_sets_it() {
        assert!(!Scene::from_toml(GOOD).unwrap().neighbours_only());
        let text = GOOD.replace("mu = 0.2", "mu = 0.2\nneighbours_only = true");
        assert!(Scene::from_toml(&text).unwrap().neighbours_only());
        let e = err(&GOOD.replace("mu = 0.2", "mu = 0.2\nneighbours_only = 1"));
        assert!(e.contains("[contact] neighbours_only: invalid type"), "{e}");
        let thesis = SceneFile::parse(GOOD).unwrap().as_in_the_thesis_code();
        let s = thesis.to_scene().unwrap();
        assert!(s.neighbours_only() && s.floor().is_none());
        assert_eq!(s.base().height(), THESIS_BASE_HEIGHT);
        // The blocks rest on the higher base.
        assert!((s.blocks()[0].initial.y - (s.base().top() + 0.2)).abs() < 1e-12);
    }

    #[test]
    fn a_wrong_type_names_its_key() {
        let e = err(&GOOD.replace("mu = 0.2", "mu = \"0.2\""));
        assert!(e.contains("[contact] mu: invalid type"), "{e}");
        let e = err(&GOOD.replace("count = 4", "count = \"four\""));
        assert!(e.contains("[[blocks]] count:"), "{e}");
        let e = err(&GOOD.replace("omega = 4.0", "omega = [4.0]"));
        assert!(e.contains("[base] omega:"), "{e}");
    }

    #[test]
    fn an_integral_decimal_count_is_a_count() {
        let two = Scene::from_toml(&GOOD.replace("count = 4", "count = 2.0")).unwrap();
        assert_eq!(two.n_blocks(), 2);
        let e = err(&GOOD.replace("count = 4", "count = 2.5"));
        assert!(
            e.contains("count must be a whole number of blocks, got 2.5"),
            "{e}"
        );
        let e = err(&GOOD.replace("count = 4", "count = -1"));
        assert!(e.contains("count must not be negative, got -1"), "{e}");
        assert!(err(&GOOD.replace("count = 4", "count = 1e300")).contains("got 1e300"));
    }

    proptest::proptest! {
        /// Any numbers in a scene give a scene or a one-line error, never a panic.
        #[test]
        fn any_numbers_give_a_scene_or_one_line(
            w in proptest::num::f64::ANY, h in -1.0..1.0f64, mu in -1.0..1.0f64,
            x in -1.0..1.0f64, th in -2.0..2.0f64, count in 0usize..4,
        ) {
            let text = format!(
                "[base]\nwidth = 1.0\nheight = 0.1\n[[blocks]]\nwidth = {w:?}\nheight = {h:?}\nx = {x:?}\ntheta = {th:?}\ncount = {count}\n[contact]\nmu = {mu:?}\n"
            ).replace("NaN", "nan");
            if let Err(e) = Scene::from_toml(&text) {
                proptest::prop_assert!(!e.to_string().contains('\n'));
            }
        }
    }

    #[test]
    fn steps_per_period_and_periods_count_in_base_periods() {
        let text = GOOD.replace(
            "[floor]",
            "[solver]\nsteps_per_period = 100\nperiods = 10\n[floor]",
        );
        let l = LoadedScene::from_toml(&text).unwrap();
        // The numbers the shaking scene used to spell out: 2π/(100·4) and 10·2π/4.
        assert_eq!(l.scene.solver.dt, 0.015707963267948967);
        assert_eq!(l.scene.solver.t_end, 15.707963267948966);
        assert!(l.defaults.get("solver.dt").is_none());
        assert!(l.defaults.get("solver.t_end").is_none());
        // A new omega keeps 100 steps per period and 10 periods.
        let six = Scene::from_toml(&text.replace("omega = 4.0", "omega = 6.0")).unwrap();
        assert!((six.solver.dt - 2.0 * PI / 600.0).abs() < 1e-16);
        assert!((six.solver.t_end - 10.0 * 2.0 * PI / 6.0).abs() < 1e-14);
        // A negative omega has the same period.
        let neg = Scene::from_toml(&text.replace("omega = 4.0", "omega = -4.0")).unwrap();
        assert_eq!(neg.solver.dt, l.scene.solver.dt);
        // Decimal numbers of steps and periods are taken as they are.
        let half = Scene::from_toml(&text.replace("periods = 10", "periods = 0.5")).unwrap();
        assert!((half.solver.t_end - PI / 4.0).abs() < 1e-15);
    }

    #[test]
    fn period_keys_are_refused_where_they_mean_nothing() {
        let solver = |keys: &str| GOOD.replace("[floor]", &format!("[solver]\n{keys}\n[floor]"));
        assert!(err(&solver("dt = 0.01\nsteps_per_period = 100"))
            .contains("both dt and steps_per_period"));
        assert!(err(&solver("t_end = 1.0\nperiods = 10")).contains("both t_end and periods"));
        let fixed = solver("steps_per_period = 100")
            .replace("motion = \"harmonic\"\namplitude = 0.2\nomega = 4.0\n", "");
        let e = err(&fixed);
        assert!(
            e.contains("steps_per_period needs a periodic base")
                && e.contains("motion = \"fixed\""),
            "{e}"
        );
        let sliding = solver("periods = 2").replace(
            "motion = \"harmonic\"\namplitude = 0.2\nomega = 4.0",
            "motion = \"constant-velocity\"\nv0 = 1.0",
        );
        assert!(err(&sliding).contains("periods needs a periodic base"));
        assert!(
            err(&solver("periods = 2").replace("omega = 4.0", "omega = 0.0"))
                .contains("omega = 0 has no period")
        );
        assert!(err(&solver("steps_per_period = 0")).contains("steps_per_period must be positive"));
        assert!(err(&solver("periods = -1")).contains("periods must be positive"));
        assert!(err(&solver("steps_per_period = nan")).contains("steps_per_period"));
    }

    #[test]
    fn round_trip_through_toml() {
        let f = SceneFile::parse(GOOD).unwrap();
        let text = toml::to_string(&f).unwrap();
        assert_eq!(SceneFile::parse(&text).unwrap(), f);
    }
}
