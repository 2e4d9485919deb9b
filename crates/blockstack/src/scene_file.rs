//! Scene files (TOML): the base, the blocks bottom to top, contact, solver and floor
//! parameters. Unknown keys are errors; every error is one line.
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
//! # y = 0.25                 # initial y (default: resting on the block below)
//! # theta = 0.0              # initial angle, radians (default 0)
//!
//! [contact]
//! mu = 0.2
//! e_n = 0.0
//! e_f = 0.0
//!
//! [solver]                   # all optional
//! dt = 0.01
//! t_end = 10.0
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
//! the block below.

use crate::base::{Base, BaseMotion, CubicSpline};
use crate::block::Block;
use crate::error::BlockError;
use crate::floor::Floor;
use crate::scene::{stack_on_top, ContactParams, Prox, Scene, SolverParams};
use serde::{Deserialize, Serialize};

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
    /// Number of identical blocks (default 1).
    #[serde(default = "one_count")]
    pub count: usize,
}

fn one() -> f64 {
    1.0
}

fn one_count() -> usize {
    1
}

/// The `[contact]` table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactFile {
    /// Friction coefficient μ.
    pub mu: f64,
    /// Normal restitution (default 0).
    #[serde(default)]
    pub e_n: f64,
    /// Tangential restitution (default 0).
    #[serde(default)]
    pub e_f: f64,
}

/// The `[solver]` table (every key optional; defaults of §4.2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SolverFile {
    /// Δt.
    pub dt: f64,
    /// End time.
    pub t_end: f64,
    /// ρ∞.
    pub rho_inf: f64,
    /// Constant prox parameter (absent: scaled).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r: Option<f64>,
    /// α of the scaled prox parameter.
    pub r_alpha: f64,
    /// Newton tolerance.
    pub tol: f64,
    /// Gravity.
    pub gravity: f64,
}

impl Default for SolverFile {
    fn default() -> Self {
        let d = SolverParams::default();
        Self {
            dt: d.dt,
            t_end: d.t_end,
            rho_inf: d.rho_inf,
            r: None,
            r_alpha: 1.0,
            tol: d.tol,
            gravity: d.gravity,
        }
    }
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

impl SceneFile {
    /// Parses TOML text (syntax and keys only; see [`SceneFile::to_scene`]).
    ///
    /// # Errors
    /// A TOML syntax error, an unknown key, a missing key or a wrong type, as one line
    /// with its line number.
    pub fn parse(text: &str) -> Result<Self, BlockError> {
        toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].lines().count().max(1));
            let msg = e.message().trim().replace('\n', " ");
            BlockError::Scene(match line {
                Some(l) => format!("line {l}: {msg}"),
                None => msg,
            })
        })
    }

    fn base_motion(&self) -> Result<BaseMotion, BlockError> {
        let b = &self.base;
        let unexpected = |key: &str| {
            BlockError::Scene(format!(
                "base key '{key}' does not apply to motion \"{}\"",
                b.motion
            ))
        };
        let need = |key: &str, v: Option<f64>| {
            v.ok_or_else(|| {
                BlockError::Scene(format!("base motion \"{}\" needs '{key}'", b.motion))
            })
        };
        let (amp, om, v0, samples) = (
            b.amplitude.is_some(),
            b.omega.is_some(),
            b.v0.is_some(),
            b.samples.is_some(),
        );
        match b.motion.as_str() {
            "fixed" => match () {
                () if amp => Err(unexpected("amplitude")),
                () if om => Err(unexpected("omega")),
                () if v0 => Err(unexpected("v0")),
                () if samples => Err(unexpected("samples")),
                () => Ok(BaseMotion::Fixed),
            },
            "harmonic" => {
                if v0 {
                    return Err(unexpected("v0"));
                }
                if samples {
                    return Err(unexpected("samples"));
                }
                BaseMotion::harmonic(need("amplitude", b.amplitude)?, need("omega", b.omega)?)
            }
            "constant-velocity" => {
                if amp || om || samples {
                    return Err(unexpected(if amp { "amplitude" } else if om { "omega" } else { "samples" }));
                }
                BaseMotion::constant_velocity(need("v0", b.v0)?)
            }
            "displacement" => {
                if amp || om || v0 {
                    return Err(unexpected(if amp { "amplitude" } else if om { "omega" } else { "v0" }));
                }
                let s = b.samples.as_ref().ok_or_else(|| {
                    BlockError::Scene("base motion \"displacement\" needs 'samples'".into())
                })?;
                let pairs: Vec<(f64, f64)> = s.iter().map(|p| (p[0], p[1])).collect();
                Ok(BaseMotion::Displacement(CubicSpline::new(&pairs)?))
            }
            other => Err(BlockError::Scene(format!(
                "unknown base motion \"{other}\" (expected fixed, harmonic, constant-velocity or displacement)"
            ))),
        }
    }

    /// Builds and validates the scene.
    ///
    /// # Errors
    /// Negative or zero sizes and masses, μ < 0, restitution outside [0, 1], NaN,
    /// overlapping blocks, a bad base motion or solver parameter: one line each.
    pub fn to_scene(&self) -> Result<Scene, BlockError> {
        let base = Base::new(self.base.width, self.base.height, self.base_motion()?)?;
        let mut column = Vec::new();
        let mut k = 0;
        for entry in &self.blocks {
            if entry.count == 0 {
                return Err(BlockError::Scene("a [[blocks]] entry has count = 0".into()));
            }
            for _ in 0..entry.count {
                k += 1;
                let block = Block::new(entry.width, entry.height, entry.mass)
                    .map_err(|e| name_block(e, k))?;
                column.push((block, entry.x, entry.y, entry.theta));
            }
        }
        let mut blocks = Vec::with_capacity(column.len());
        for (k, (block, x, y, th)) in column.into_iter().enumerate() {
            let name = |what: &str| format!("block {} {what}", k + 1);
            input::finite(&name("x"), x)?;
            input::finite(&name("theta"), th)?;
            let placed = match y {
                // An explicit height: taken as is (the overlap check judges it).
                Some(y) => block.at(x, input::finite(&name("y"), y)?, th)?,
                None => {
                    let top = blocks.last().map_or(base.top(), |b: &Block| {
                        b.initial.y + b.half_vertical_extent(b.initial.theta)
                    });
                    stack_on_top(top, block, x, th, k)?
                }
            };
            blocks.push(placed);
        }
        let floor = self.floor.map(|f| Floor::new(f.y.unwrap_or(base.bottom())));
        let s = &self.solver;
        let solver = SolverParams {
            dt: s.dt,
            t_end: s.t_end,
            rho_inf: s.rho_inf,
            prox: s.r.map_or(Prox::Scaled(s.r_alpha), Prox::Constant),
            tol: s.tol,
            gravity: s.gravity,
        };
        let c = &self.contact;
        Scene::new(
            base,
            blocks,
            floor,
            ContactParams {
                mu: c.mu,
                e_n: c.e_n,
                e_f: c.e_f,
            },
            solver,
        )
    }
}

/// Prefixes "block k" to the name in a block-constructor error.
fn name_block(e: BlockError, k: usize) -> BlockError {
    match e {
        BlockError::Input(e) => BlockError::Input(e.prefixed(&format!("block {k}"))),
        other => other,
    }
}

impl Scene {
    /// Parses and validates a TOML scene (see [`crate::scene_file`]).
    ///
    /// # Errors
    /// Any syntax or validation error, as one line.
    pub fn from_toml(text: &str) -> Result<Self, BlockError> {
        SceneFile::parse(text)?.to_scene()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn round_trip_through_toml() {
        let f = SceneFile::parse(GOOD).unwrap();
        let text = toml::to_string(&f).unwrap();
        assert_eq!(SceneFile::parse(&text).unwrap(), f);
    }
}
