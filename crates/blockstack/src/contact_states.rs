//! The contact state of one interface (App. H, Tables H.1–H.2), read from a step's index
//! sets.
//!
//! Each interface k (between the body beneath, base or block, and block k) has a left
//! and a right gap, each in the nested sets A ⊇ B ⊇ C of its normal law (H.1.1), and one
//! friction law in D ⊇ E (H.2.2), which has a state only when the interface is in
//! A = A¹ ∪ A² (H.2.1). Table H.1 lists the 16 normal states (4 per gap, nested) and
//! Table H.2 the 3 friction states of an interface in A: 15 × 3 + 1 = 46 states.

use nsga::IndexSets;
use std::fmt;

/// The state of one gap: which of the nested sets A ⊇ B ⊇ C (H.1.1) it is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum GapState {
    /// Not in A: the gap is open at the end of the step.
    Open,
    /// In A, not B: closed, but its velocity is separating (an impact may end here).
    Separating,
    /// In B, not C: closed with zero relative velocity, the acceleration separates.
    LiftingOff,
    /// In C: closed and pressed (it may carry a force).
    Closed,
}

impl GapState {
    /// The state of normal contact `k` in `sets`.
    #[must_use]
    pub fn of(sets: &IndexSets, k: usize) -> Self {
        match (sets.a[k], sets.b[k], sets.c[k]) {
            (false, ..) => Self::Open,
            (true, false, _) => Self::Separating,
            (true, true, false) => Self::LiftingOff,
            (true, true, true) => Self::Closed,
        }
    }

    /// One letter: `o`, `s`, `l`, `c`.
    #[must_use]
    pub fn letter(self) -> char {
        match self {
            Self::Open => 'o',
            Self::Separating => 's',
            Self::LiftingOff => 'l',
            Self::Closed => 'c',
        }
    }
}

/// The state of an interface's friction law: which of D ⊇ E (H.2.2) it is in.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrictionState {
    /// The interface is open (not in A): friction has no state.
    Inactive,
    /// In A, not D: slipping.
    Slipping,
    /// In D, not E: sticking on velocity level, starting to slip on acceleration level.
    StartingToSlip,
    /// In E: sticking.
    Sticking,
}

impl FrictionState {
    /// One letter: `-`, `S` (slip), `T` (starting to slip), `K` (stick).
    #[must_use]
    pub fn letter(self) -> char {
        match self {
            Self::Inactive => '-',
            Self::Slipping => 'S',
            Self::StartingToSlip => 'T',
            Self::Sticking => 'K',
        }
    }
}

/// The contact state of one interface (one row of Tables H.1 × H.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, serde::Serialize)]
pub struct InterfaceState {
    /// The left gap (A¹, B¹, C¹).
    pub left: GapState,
    /// The right gap (A², B², C²).
    pub right: GapState,
    /// The friction law (D, E), inactive when both gaps are open.
    pub friction: FrictionState,
}

impl InterfaceState {
    /// The state of interface `k` (normal contacts 2k and 2k + 1, friction law k, the
    /// stack's numbering) in `sets`.
    #[must_use]
    pub fn of(sets: &IndexSets, k: usize) -> Self {
        let (left, right) = (GapState::of(sets, 2 * k), GapState::of(sets, 2 * k + 1));
        let friction = if left == GapState::Open && right == GapState::Open {
            FrictionState::Inactive
        } else {
            match (sets.d[k], sets.e[k]) {
                (false, _) => FrictionState::Slipping,
                (true, false) => FrictionState::StartingToSlip,
                (true, true) => FrictionState::Sticking,
            }
        };
        Self {
            left,
            right,
            friction,
        }
    }

    /// Every state an interface can be in: the 46 of Tables H.1–H.2.
    #[must_use]
    pub fn all() -> Vec<Self> {
        use GapState::{Closed, LiftingOff, Open, Separating};
        let gaps = [Open, Separating, LiftingOff, Closed];
        let mut out = Vec::new();
        for left in gaps {
            for right in gaps {
                if left == Open && right == Open {
                    out.push(Self {
                        left,
                        right,
                        friction: FrictionState::Inactive,
                    });
                    continue;
                }
                for friction in [
                    FrictionState::Slipping,
                    FrictionState::StartingToSlip,
                    FrictionState::Sticking,
                ] {
                    out.push(Self {
                        left,
                        right,
                        friction,
                    });
                }
            }
        }
        out
    }
}

impl fmt::Display for InterfaceState {
    /// Three letters: left gap, right gap, friction (`cc K`: both closed, sticking).
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}{}{}",
            self.left.letter(),
            self.right.letter(),
            self.friction.letter()
        )
    }
}

/// The states of the stack's `n` interfaces (bottom to top) in `sets`.
#[must_use]
pub fn interface_states(sets: &IndexSets, n: usize) -> Vec<InterfaceState> {
    (0..n).map(|k| InterfaceState::of(sets, k)).collect()
}

/// The interfaces (1-based, bottom to top) whose states differ between any two of the
/// candidates' sets.
#[must_use]
pub fn differing_interfaces(candidates: &[&IndexSets], n: usize) -> Vec<usize> {
    (0..n)
        .filter(|&k| {
            let first = candidates.first().map(|s| InterfaceState::of(s, k));
            candidates
                .iter()
                .any(|s| Some(InterfaceState::of(s, k)) != first)
        })
        .map(|k| k + 1)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tables_h1_and_h2_count_46_states() {
        let all = InterfaceState::all();
        assert_eq!(all.len(), 46);
        let mut unique = all.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), 46);
    }

    #[test]
    fn states_read_from_nested_sets() {
        let mut sets = IndexSets::empty(4, 2);
        sets.a[2] = true;
        sets.b[2] = true;
        sets.c[2] = true;
        sets.a[3] = true;
        sets.d[1] = true;
        let s = interface_states(&sets, 2);
        assert_eq!(s[0].to_string(), "oo-");
        assert_eq!(s[1].left, GapState::Closed);
        assert_eq!(s[1].right, GapState::Separating);
        assert_eq!(s[1].friction, FrictionState::StartingToSlip);
        let mut other = sets.clone();
        other.e[1] = true;
        assert_eq!(differing_interfaces(&[&sets, &other], 2), vec![2]);
    }
}
