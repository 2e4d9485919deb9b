//! Contact materials per interface: μ, e_N and e_F of the scene ([`ContactParams`], the
//! defaults), overridden for one kind of interface (base–block, block–block,
//! block–floor) and for one pair of bodies.
//!
//! Each parameter is resolved on its own, the most specific given value winning: the
//! pair's, then its kind's, then the default. A pair that sets only μ takes e_N from its
//! kind (or the default). A scene without overrides gives every contact the default, as
//! before materials existed.
//!
//! ```
//! use blockstack::materials::{Materials, Override, PairMaterial};
//! use blockstack::overlap::Body;
//! use blockstack::ContactParams;
//!
//! let default = ContactParams { mu: 0.5, e_n: 0.0, e_f: 0.0 };
//! let materials = Materials {
//!     base: Override { mu: Some(0.1), ..Override::default() },
//!     pairs: vec![PairMaterial {
//!         bodies: [Body::Block(1), Body::Block(2)],
//!         label: "drum1/capital".into(),
//!         params: Override { e_n: Some(0.3), ..Override::default() },
//!     }],
//!     ..Materials::default()
//! };
//! assert_eq!(materials.between(&default, Body::Base, Body::Block(1)).mu, 0.1);
//! let pair = materials.between(&default, Body::Block(2), Body::Block(1));
//! assert_eq!((pair.mu, pair.e_n), (0.5, 0.3));
//! ```

use crate::error::BlockError;
use crate::overlap::Body;
use crate::scene::ContactParams;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Some of μ, e_N, e_F; an absent one falls through to the less specific level.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Override {
    /// Friction coefficient μ ≥ 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// Normal restitution e_N ∈ [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e_n: Option<f64>,
    /// Tangential restitution e_F ∈ [0, 1].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub e_f: Option<f64>,
}

impl Override {
    /// `under` with the values this override gives put in.
    #[must_use]
    pub fn over(&self, under: ContactParams) -> ContactParams {
        ContactParams {
            mu: self.mu.unwrap_or(under.mu),
            e_n: self.e_n.unwrap_or(under.e_n),
            e_f: self.e_f.unwrap_or(under.e_f),
        }
    }

    /// Whether it gives no value.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// Checks the values given, naming them `{prefix}.mu` etc. (`contact.base.mu`).
    ///
    /// # Errors
    /// The first value out of range.
    pub fn validate(&self, prefix: &str) -> Result<(), BlockError> {
        let name = |field: &str| format!("{prefix}.{field}");
        if let Some(mu) = self.mu {
            input::non_negative(&name("mu"), mu)?;
        }
        for (field, value) in [("e_n", self.e_n), ("e_f", self.e_f)] {
            if let Some(e) = value {
                input::in_range(&name(field), e, 0.0..=1.0, "[0, 1]")?;
            }
        }
        Ok(())
    }
}

impl fmt::Display for Override {
    /// `mu = 0.1, e_n = 0.3`: the values given.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let given: Vec<String> = [("mu", self.mu), ("e_n", self.e_n), ("e_f", self.e_f)]
            .into_iter()
            .filter_map(|(k, v)| v.map(|v| format!("{k} = {v}")))
            .collect();
        f.write_str(&given.join(", "))
    }
}

/// The kind of an interface, by the bodies it joins.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum InterfaceKind {
    /// The base and a block.
    Base,
    /// Two blocks.
    Blocks,
    /// A block and the floor.
    Floor,
}

impl InterfaceKind {
    /// The kind of the interface between bodies `a` and `b` (in either order).
    #[must_use]
    pub fn of(a: Body, b: Body) -> Self {
        match (a, b) {
            (Body::Floor, _) | (_, Body::Floor) => Self::Floor,
            (Body::Base, _) | (_, Body::Base) => Self::Base,
            _ => Self::Blocks,
        }
    }

    /// The scene-file table of this kind's override: `base`, `blocks` or `floor`.
    #[must_use]
    pub fn key(self) -> &'static str {
        match self {
            Self::Base => "base",
            Self::Blocks => "blocks",
            Self::Floor => "floor",
        }
    }
}

/// An override for the contacts of one pair of bodies.
#[derive(Debug, Clone, PartialEq)]
pub struct PairMaterial {
    /// The two bodies, in any order.
    pub bodies: [Body; 2],
    /// How the user named them (`drum3/capital`), for reports.
    pub label: String,
    /// The values given.
    pub params: Override,
}

impl PairMaterial {
    fn joins(&self, a: Body, b: Body) -> bool {
        self.bodies == [a, b] || self.bodies == [b, a]
    }
}

/// The overrides of a scene's contact parameters (none by default).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Materials {
    /// Base–block interfaces.
    pub base: Override,
    /// Block–block interfaces.
    pub blocks: Override,
    /// Block–floor contacts.
    pub floor: Override,
    /// Single pairs of bodies; a later entry for the same pair wins.
    pub pairs: Vec<PairMaterial>,
}

impl Materials {
    /// The override of one kind of interface.
    #[must_use]
    pub fn kind(&self, kind: InterfaceKind) -> &Override {
        match kind {
            InterfaceKind::Base => &self.base,
            InterfaceKind::Blocks => &self.blocks,
            InterfaceKind::Floor => &self.floor,
        }
    }

    /// The parameters of the contacts between bodies `a` and `b`: each of μ, e_N, e_F
    /// from the pair's override if it gives it, else the kind's, else `default`.
    #[must_use]
    pub fn between(&self, default: &ContactParams, a: Body, b: Body) -> ContactParams {
        let kind = self.kind(InterfaceKind::of(a, b)).over(*default);
        self.pairs
            .iter()
            .filter(|p| p.joins(a, b))
            .fold(kind, |params, p| p.params.over(params))
    }

    /// Whether every contact has the default parameters.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == Self::default()
    }

    /// Checks every value and pair of a scene with `n_blocks` blocks.
    ///
    /// # Errors
    /// A value out of range (named `contact.base.mu`, `contact.pair.0.e_n`), a pair
    /// naming a block the scene does not have, a body twice, or the base with the floor
    /// (they never touch).
    pub fn validate(&self, n_blocks: usize) -> Result<(), BlockError> {
        for kind in [
            InterfaceKind::Base,
            InterfaceKind::Blocks,
            InterfaceKind::Floor,
        ] {
            self.kind(kind)
                .validate(&format!("contact.{}", kind.key()))?;
        }
        for (k, p) in self.pairs.iter().enumerate() {
            let key = format!("contact.pair.{k}");
            p.params.validate(&key)?;
            let bad = |why: String| BlockError::Scene(format!("{key} ({}): {why}", p.label));
            if let Some(Body::Block(i)) = p
                .bodies
                .iter()
                .find(|b| matches!(b, Body::Block(i) if *i == 0 || *i > n_blocks))
            {
                return Err(bad(format!("the scene has no block {i}")));
            }
            match p.bodies {
                [a, b] if a == b => return Err(bad("a body cannot touch itself".into())),
                [Body::Base, Body::Floor] | [Body::Floor, Body::Base] => {
                    return Err(bad("the base and the floor never touch".into()))
                }
                _ => {}
            }
        }
        Ok(())
    }

    /// One line per override given (`base: mu = 0.1`, `drum3/capital: e_n = 0.2`), for
    /// reports; empty without overrides.
    #[must_use]
    pub fn lines(&self) -> Vec<String> {
        let kinds = [
            InterfaceKind::Base,
            InterfaceKind::Blocks,
            InterfaceKind::Floor,
        ]
        .into_iter()
        .filter(|&k| !self.kind(k).is_empty())
        .map(|k| format!("{}: {}", k.key(), self.kind(k)));
        let pairs = self
            .pairs
            .iter()
            .filter(|p| !p.params.is_empty())
            .map(|p| format!("{}: {}", p.label, p.params));
        kinds.chain(pairs).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DEFAULT: ContactParams = ContactParams {
        mu: 0.5,
        e_n: 0.1,
        e_f: 0.2,
    };

    fn only_mu(mu: f64) -> Override {
        Override {
            mu: Some(mu),
            ..Override::default()
        }
    }

    #[test]
    fn the_most_specific_value_wins_field_by_field() {
        let m = Materials {
            blocks: Override {
                mu: Some(0.3),
                e_n: Some(0.4),
                e_f: None,
            },
            floor: only_mu(0.9),
            pairs: vec![PairMaterial {
                bodies: [Body::Block(2), Body::Block(3)],
                label: "b/c".into(),
                params: only_mu(0.7),
            }],
            ..Materials::default()
        };
        let at = |a, b| m.between(&DEFAULT, a, b);
        assert_eq!(at(Body::Base, Body::Block(1)), DEFAULT);
        let blocks = at(Body::Block(1), Body::Block(2));
        assert_eq!((blocks.mu, blocks.e_n, blocks.e_f), (0.3, 0.4, 0.2));
        let pair = at(Body::Block(3), Body::Block(2));
        assert_eq!((pair.mu, pair.e_n, pair.e_f), (0.7, 0.4, 0.2));
        assert_eq!(at(Body::Block(3), Body::Floor).mu, 0.9);
    }

    #[test]
    fn bad_values_and_pairs_name_their_key() {
        let bad = |m: Materials| m.validate(3).unwrap_err().to_string();
        let e = bad(Materials {
            base: only_mu(-1.0),
            ..Materials::default()
        });
        assert!(e.contains("contact.base.mu must not be negative"), "{e}");
        let pair = |bodies, params| Materials {
            pairs: vec![PairMaterial {
                bodies,
                label: "x/y".into(),
                params,
            }],
            ..Materials::default()
        };
        let e = bad(pair(
            [Body::Block(1), Body::Block(2)],
            Override {
                e_n: Some(2.0),
                ..Override::default()
            },
        ));
        assert!(e.contains("contact.pair.0.e_n"), "{e}");
        let e = bad(pair([Body::Block(4), Body::Block(2)], only_mu(0.1)));
        assert!(
            e.contains("contact.pair.0 (x/y): the scene has no block 4"),
            "{e}"
        );
        assert!(bad(pair([Body::Block(1), Body::Block(1)], only_mu(0.1))).contains("itself"));
        assert!(bad(pair([Body::Floor, Body::Base], only_mu(0.1))).contains("never touch"));
    }

    #[test]
    fn lines_list_the_overrides_given() {
        let m = Materials {
            base: only_mu(0.1),
            ..Materials::default()
        };
        assert_eq!(m.lines(), ["base: mu = 0.1"]);
        assert!(Materials::default().lines().is_empty());
    }
}
