//! The built-in scenes: the scene files of `crates/blockstack/scenes/`, compiled into the
//! library so that an installed `rollstack` has them (`rollstack blocks scenes` lists
//! them, `rollstack blocks scenes NAME` prints one to start from, `rollstack blocks run
//! NAME` runs one).
//!
//! ```
//! use blockstack::scenes;
//!
//! let shaking = scenes::find("shaking")?;
//! assert!(shaking.toml.contains("steps_per_period = 100"));
//! let loaded = shaking.load()?;
//! assert_eq!(loaded.scene.n_blocks(), 4);
//! let unknown = scenes::find("tower").unwrap_err().to_string();
//! assert!(unknown.contains("lire, lire-collapse, rocking-block, shaking, side-by-side, slide, trilith"), "{unknown}");
//! # Ok::<(), blockstack::BlockError>(())
//! ```

use crate::error::BlockError;
use crate::scene_file::LoadedScene;
use serde::Serialize;

/// One built-in scene: a name, a one-line description and the TOML text of its file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct BuiltinScene {
    /// The name `rollstack blocks run` accepts (the file's stem).
    pub name: &'static str,
    /// What the scene is, on one line.
    pub description: &'static str,
    /// The scene file, comments included (keys: docs/scenes.md).
    #[serde(skip)]
    pub toml: &'static str,
}

impl BuiltinScene {
    /// Parses, builds and validates the scene.
    ///
    /// # Errors
    /// None for the shipped files (a test loads every one); the loader's error otherwise.
    pub fn load(&self) -> Result<LoadedScene, BlockError> {
        LoadedScene::from_toml(self.toml)
    }
}

const BUILTIN: [BuiltinScene; 11] = [
    BuiltinScene {
        name: "abundance",
        description: "Figure 4.5 as the thesis states it: five blocks, mu = 0.3, base x = sin(3πt/2), 60 steps per period, 3 periods, floor (for `blocks explore`)",
        toml: include_str!("../scenes/abundance.toml"),
    },
    BuiltinScene {
        name: "abundance-author",
        description: "Figure 4.5 with the author's scripts' settings: base x = 0.2 sin(3πt/2), 200 steps per period, 4 periods, floor (for `blocks explore`)",
        toml: include_str!("../scenes/abundance-author.toml"),
    },
    BuiltinScene {
        name: "drop",
        description: "a block dropped flat from rest onto a fixed table, e_N = 0.5, mu = 0.5: it bounces on both corners at once, a Zeno sequence that ends at t = 4.74, floor",
        toml: include_str!("../scenes/drop.toml"),
    },
    BuiltinScene {
        name: "drum-column",
        description: "a classical column: five marble drums (0.8 x 1 m, 2160 kg) under a capital (1.2 x 0.4 m) on a plinth moved by a one-sine pulse of 0.82 g lasting 1 s, SI units: the upper drums tip at 1.6 s and the column collapses, floor",
        toml: include_str!("../scenes/drum-column.toml"),
    },
    BuiltinScene {
        name: "lire",
        description: "the Leaning Tower of Lire (§4.3): four blocks at maximum overhang on a fixed table, no floor",
        toml: include_str!("../scenes/lire.toml"),
    },
    BuiltinScene {
        name: "lire-collapse",
        description: "the Lire tower with its lowest block pushed out by 1 % of its width: the whole column collapses (§4.3, Figure 4.4), no floor",
        toml: include_str!("../scenes/lire-collapse.toml"),
    },
    BuiltinScene {
        name: "rocking-block",
        description: "a slender block (0.2 x 1.0, tan alpha = 0.2, mu = 1 on the base, e_N = 0) released tilted by half of alpha on a fixed table: it rocks freely, losing energy at each impact by Housner's ratio (docs/rocking.md), floor",
        toml: include_str!("../scenes/rocking-block.toml"),
    },
    BuiltinScene {
        name: "shaking",
        description: "a column of four blocks on a base shaken as x = 0.2 sin(4t) (§4.4): 100 steps per period, 10 periods, floor",
        toml: include_str!("../scenes/shaking.toml"),
    },
    BuiltinScene {
        name: "side-by-side",
        description: "two crates (0.4 x 0.8 m and 0.6 x 0.6 m, 100 kg) side by side on a base shaken at 0.32 g, 2 Hz, SI units: each rests on the base only, their sides meet through corner contacts, floor",
        toml: include_str!("../scenes/side-by-side.toml"),
    },
    BuiltinScene {
        name: "slide",
        description: "a column of four blocks on a base pulled at v0 = 1 from t = 0 (§4.5): t_end = 3, floor",
        toml: include_str!("../scenes/slide.toml"),
    },
    BuiltinScene {
        name: "trilith",
        description: "a trilith: two stone posts (0.4 x 2 m, 2000 kg) and a lintel (2 x 0.5 m, 2500 kg) resting on both, on a base shaken at 0.45 g, 1.5 Hz, SI units: the lintel has an interface on each post, floor",
        toml: include_str!("../scenes/trilith.toml"),
    },
];

/// Every built-in scene, sorted by name.
#[must_use]
pub fn builtin() -> &'static [BuiltinScene] {
    &BUILTIN
}

/// The names of the built-in scenes, sorted.
#[must_use]
pub fn names() -> Vec<&'static str> {
    BUILTIN.iter().map(|s| s.name).collect()
}

/// The built-in scene called `name`.
///
/// # Errors
/// An unknown name, with the list of the built-in names.
pub fn find(name: &str) -> Result<&'static BuiltinScene, BlockError> {
    BUILTIN
        .iter()
        .find(|s| s.name == name)
        .ok_or_else(|| BlockError::UnknownScene {
            name: name.to_owned(),
            known: names().join(", "),
        })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulation::{simulate, RunOptions};

    #[test]
    fn names_are_sorted_unique_and_found() {
        let n = names();
        let mut sorted = n.clone();
        sorted.sort_unstable();
        sorted.dedup();
        assert_eq!(n, sorted);
        for s in builtin() {
            assert_eq!(find(s.name).unwrap(), s);
            assert!(!s.description.contains('\n'));
            assert!(s.toml.contains("[base]"));
        }
        let e = find("nope").unwrap_err().to_string();
        assert!(
            !e.contains('\n')
                && e.contains(
                    "lire, lire-collapse, rocking-block, shaking, side-by-side, slide, trilith"
                ),
            "{e}"
        );
    }

    #[test]
    fn every_builtin_scene_loads_and_runs() {
        for s in builtin() {
            let loaded = s.load().unwrap_or_else(|e| panic!("{}: {e}", s.name));
            let options = RunOptions {
                t_end: Some(0.05),
                ..RunOptions::default()
            };
            let summary = simulate(&loaded.scene, &options, |_| {}).unwrap();
            assert!(summary.error.is_none(), "{}: {:?}", s.name, summary.error);
            assert!(summary.steps >= 3, "{}: {} steps", s.name, summary.steps);
        }
    }
}
