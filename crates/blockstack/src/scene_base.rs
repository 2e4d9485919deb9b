//! The base's motion in a scene file: one [`MotionFile`] per component, x, y and the
//! rotation, each read into a [`BaseMotion`].
//!
//! The keys of `[base]` itself (`motion`, `amplitude`, `omega`, `v0`, `samples`) are the
//! x component's, as they always were; every motion of any component, pulses and records
//! included, can be given as a table of its own, `[base.x]`, `[base.y]` or
//! `[base.rotation]`. A record's path is relative to the scene file's directory.

use crate::base::{
    load_record, BaseMotion, Baseline, CubicSpline, Pulse, PulseShape, RecordOptions,
};
use crate::error::BlockError;
use serde::{Deserialize, Serialize};
use std::path::Path;

/// A component of the base's motion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Component {
    /// Along E₁.
    X,
    /// Along E₂.
    Y,
    /// The rotation about the base's centre.
    Rotation,
}

impl Component {
    /// The key of its table: `x`, `y`, `rotation`.
    #[must_use]
    pub fn key(self) -> &'static str {
        match self {
            Self::X => "x",
            Self::Y => "y",
            Self::Rotation => "rotation",
        }
    }
}

/// The motion of one component of the base: `[base.x]`, `[base.y]`, `[base.rotation]`
/// (and the x keys of `[base]` itself). docs/scenes.md lists the keys each motion takes.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MotionFile {
    /// One of [`BaseMotion::NAMES`] (absent: `fixed`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub motion: Option<String>,
    /// Harmonic: amplitude A of the displacement; pulse: peak acceleration a_p.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub amplitude: Option<f64>,
    /// Harmonic: angular frequency ω.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub omega: Option<f64>,
    /// Constant-velocity: the rate v₀.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub v0: Option<f64>,
    /// Displacement: samples [t, x].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub samples: Option<Vec<[f64; 2]>>,
    /// Pulse: `one-sine`, `one-cosine` or `ricker`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<String>,
    /// Pulse: period T_p.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub period: Option<f64>,
    /// Pulse: start time t₀ (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub start: Option<f64>,
    /// Record: the file, `.AT2` or CSV, relative to the scene file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub record: Option<String>,
    /// Record: the step of a one-column CSV file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dt: Option<f64>,
    /// Record: a factor on the accelerations (default 1), after `scale_to_pga`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Record: the peak |a| to scale the corrected record to, in its units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale_to_pga: Option<f64>,
    /// Record: `g` (x and y's default) or `model` (the rotation's only units).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub units: Option<String>,
    /// Record: `end-at-rest` (default) or `none`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub baseline: Option<String>,
}

/// What a component's motion is read with: the scene file's directory (for records) and
/// g (a record in g is multiplied by it).
#[derive(Debug, Clone, Copy)]
pub struct MotionContext<'a> {
    /// Where record paths start from.
    pub dir: &'a Path,
    /// The scene's gravity.
    pub gravity: f64,
}

impl MotionFile {
    /// The keys given, with whether each is: every optional key of the table.
    fn given(&self) -> [(&'static str, bool); 13] {
        [
            ("amplitude", self.amplitude.is_some()),
            ("omega", self.omega.is_some()),
            ("v0", self.v0.is_some()),
            ("samples", self.samples.is_some()),
            ("shape", self.shape.is_some()),
            ("period", self.period.is_some()),
            ("start", self.start.is_some()),
            ("record", self.record.is_some()),
            ("dt", self.dt.is_some()),
            ("scale", self.scale.is_some()),
            ("scale_to_pga", self.scale_to_pga.is_some()),
            ("units", self.units.is_some()),
            ("baseline", self.baseline.is_some()),
        ]
    }

    /// Whether any key besides `motion` is given.
    #[must_use]
    pub fn given_any(&self) -> bool {
        self.given().iter().any(|(_, g)| *g)
    }

    /// Whether the table says anything (an absent or empty table is a fixed component).
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// The motion's name (`fixed` when absent).
    #[must_use]
    pub fn name(&self) -> &str {
        self.motion.as_deref().unwrap_or("fixed")
    }

    /// The component's motion. `what` names the component in errors (`base`,
    /// `base.y`).
    ///
    /// # Errors
    /// An unknown motion, a key that does not belong to it, a missing key, a bad value
    /// or an unreadable record: one line naming `what` and the key.
    pub fn to_motion(
        &self,
        what: &str,
        component: Component,
        context: MotionContext<'_>,
    ) -> Result<BaseMotion, BlockError> {
        let name = self.name();
        let keys: &[&str] = match name {
            "fixed" => &[],
            "harmonic" => &["amplitude", "omega"],
            "constant-velocity" => &["v0"],
            "displacement" => &["samples"],
            "pulse" => &["shape", "amplitude", "period", "start"],
            "record" => &["record", "dt", "scale", "scale_to_pga", "units", "baseline"],
            other => {
                return Err(BlockError::Scene(format!(
                    "unknown {what} motion \"{other}\" (expected {})",
                    names_or(&BaseMotion::NAMES)
                )))
            }
        };
        if let Some((key, _)) = self.given().iter().find(|(k, g)| *g && !keys.contains(k)) {
            return Err(BlockError::Scene(format!(
                "{what} key '{key}' does not apply to motion \"{name}\""
            )));
        }
        let need = |key: &str, v: Option<f64>| {
            v.ok_or_else(|| BlockError::Scene(format!("{what} motion \"{name}\" needs '{key}'")))
        };
        let named = |e: BlockError| match e {
            BlockError::Input(e) => BlockError::Input(e.prefixed(what)),
            BlockError::Scene(m) | BlockError::Record(m) => {
                BlockError::Scene(format!("{what}: {m}"))
            }
            other => other,
        };
        match name {
            // Checked here too, to name the component (`base.y omega is not finite`).
            "harmonic" => BaseMotion::harmonic(
                input::finite(
                    &format!("{what} amplitude"),
                    need("amplitude", self.amplitude)?,
                )?,
                input::finite(&format!("{what} omega"), need("omega", self.omega)?)?,
            ),
            "constant-velocity" => BaseMotion::constant_velocity(input::finite(
                &format!("{what} v0"),
                need("v0", self.v0)?,
            )?),
            "displacement" => {
                let s = self.samples.as_ref().ok_or_else(|| {
                    BlockError::Scene(format!("{what} motion \"displacement\" needs 'samples'"))
                })?;
                let pairs: Vec<(f64, f64)> = s.iter().map(|p| (p[0], p[1])).collect();
                Ok(BaseMotion::Displacement(CubicSpline::new(&pairs)?))
            }
            "pulse" => {
                let shape = self.shape.as_deref().ok_or_else(|| {
                    BlockError::Scene(format!("{what} motion \"pulse\" needs 'shape'"))
                })?;
                let pulse = Pulse::new(
                    PulseShape::from_name(shape).map_err(|e| named(BlockError::Scene(e)))?,
                    need("amplitude", self.amplitude)?,
                    need("period", self.period)?,
                    self.start.unwrap_or(0.0),
                )
                .map_err(named)?;
                Ok(BaseMotion::Pulse(pulse))
            }
            "record" => {
                let path = self.record.as_deref().ok_or_else(|| {
                    BlockError::Scene(format!(
                        "{what} motion \"record\" needs 'record' (the file)"
                    ))
                })?;
                self.record_motion(path, what, component, context)
                    .map_err(named)
            }
            _ => Ok(BaseMotion::Fixed),
        }
    }

    /// A `record` motion: the file read and integrated as its keys say.
    fn record_motion(
        &self,
        path: &str,
        what: &str,
        component: Component,
        context: MotionContext<'_>,
    ) -> Result<BaseMotion, BlockError> {
        let rotation = component == Component::Rotation;
        let unit = match self.units.as_deref() {
            Some("model") => 1.0,
            None if rotation => 1.0,
            None | Some("g") if !rotation => context.gravity,
            Some("g") => {
                return Err(BlockError::Scene(format!(
                    "units = \"g\" is for x and y: {what}'s record is in rad per time unit², units = \"model\""
                )))
            }
            Some(other) => {
                return Err(BlockError::Scene(format!(
                    "unknown units \"{other}\" (expected \"g\" or \"model\")"
                )))
            }
            None => 1.0,
        };
        let baseline = match self.baseline.as_deref() {
            None => Baseline::default(),
            Some(b) => Baseline::from_name(b).map_err(BlockError::Scene)?,
        };
        let options = RecordOptions {
            dt: self.dt,
            unit,
            scale: self.scale.unwrap_or(1.0),
            scale_to_pga: self.scale_to_pga,
            baseline,
        };
        let record = load_record(&context.dir.join(path), &options)?;
        Ok(BaseMotion::Record(record))
    }
}

/// `a, b or c`.
fn names_or(names: &[&str]) -> String {
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} or {last}", rest.join(", ")),
        _ => names.join(""),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion(text: &str, component: Component) -> Result<BaseMotion, String> {
        let file: MotionFile = toml::from_str(text).map_err(|e| e.to_string())?;
        let context = MotionContext {
            dir: Path::new(env!("CARGO_MANIFEST_DIR")),
            gravity: 9.81,
        };
        file.to_motion("base.y", component, context)
            .map_err(|e| e.to_string())
    }

    #[test]
    fn a_pulse_table_gives_a_pulse() {
        let m = motion(
            "motion = \"pulse\"\nshape = \"one-cosine\"\namplitude = 0.3\nperiod = 0.5\nstart = 0.1\n",
            Component::Y,
        )
        .unwrap();
        let BaseMotion::Pulse(p) = m else {
            panic!("{m:?}")
        };
        assert_eq!(
            (p.shape, p.amplitude, p.period, p.start),
            (PulseShape::OneCosine, 0.3, 0.5, 0.1)
        );
    }

    #[test]
    fn wrong_keys_are_named() {
        let e = motion(
            "motion = \"pulse\"\nshape = \"ricker\"\nperiod = 1\n",
            Component::Y,
        )
        .unwrap_err();
        assert_eq!(
            e,
            "invalid scene: base.y motion \"pulse\" needs 'amplitude'"
        );
        let e = motion("motion = \"pulse\"\nomega = 1\n", Component::Y).unwrap_err();
        assert_eq!(
            e,
            "invalid scene: base.y key 'omega' does not apply to motion \"pulse\""
        );
        let e = motion(
            "motion = \"pulse\"\nshape = \"box\"\namplitude = 1\nperiod = 1\n",
            Component::Y,
        )
        .unwrap_err();
        assert!(
            e.starts_with("invalid scene: base.y: unknown pulse shape \"box\""),
            "{e}"
        );
        let e = motion(
            "motion = \"pulse\"\nshape = \"ricker\"\namplitude = 1\nperiod = 0\n",
            Component::Y,
        )
        .unwrap_err();
        assert_eq!(e, "base.y pulse period must be positive, got 0");
        let e = motion(
            "motion = \"harmonic\"\namplitude = 1\nomega = nan\n",
            Component::Y,
        )
        .unwrap_err();
        assert_eq!(e, "base.y omega is not finite");
        let e = motion("motion = \"quake\"\n", Component::Y).unwrap_err();
        assert!(
            e.contains(
                "expected fixed, harmonic, constant-velocity, displacement, pulse or record"
            ),
            "{e}"
        );
        let e = motion(
            "motion = \"record\"\nrecord = \"x.csv\"\nunits = \"g\"\n",
            Component::Rotation,
        )
        .unwrap_err();
        assert!(e.contains("units = \"g\" is for x and y"), "{e}");
        let e = motion(
            "motion = \"record\"\nrecord = \"no/such.AT2\"\n",
            Component::Y,
        )
        .unwrap_err();
        assert!(
            e.starts_with("invalid scene: base.y: cannot read record ")
                && e.contains("no/such.AT2"),
            "{e}"
        );
    }
}
