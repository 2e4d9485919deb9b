//! Index sets of the contact laws (paper eqs. 128–142, docs/method.md §3).

/// The active sets of one step: per normal contact A ⊇ B ⊇ C, per friction law D ⊇ E.
///
/// `a[k]`: gap k closed on position level (r g_N − κ̂_N ≤ 0); `b[k]`: closed on
/// velocity level (r ξ_N − P_N ≤ 0); `c[k]`: closed on acceleration level
/// (r g̈_N − λ_N ≤ 0); `d[j]`: friction law j sticks on velocity level
/// (‖r ξ_F − P_F‖ ≤ μ P̂); `e[j]`: sticks on acceleration level (‖r γ̇_F − λ_F‖ ≤ μ λ̂).
/// A law is *active* when one of its normal contacts is in A.
#[derive(Debug, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize)]
pub struct IndexSets {
    /// A: closed gaps (position level), per normal contact.
    pub a: Vec<bool>,
    /// B ⊆ A: closed on velocity level, per normal contact.
    pub b: Vec<bool>,
    /// C ⊆ B: closed on acceleration level, per normal contact.
    pub c: Vec<bool>,
    /// D: sticking on velocity level, per friction law.
    pub d: Vec<bool>,
    /// E ⊆ D: sticking on acceleration level, per friction law.
    pub e: Vec<bool>,
}

/// Written out for `clone_from`, which copies into the five buffers of the sets it
/// overwrites (the derived one would allocate five new ones).
impl Clone for IndexSets {
    fn clone(&self) -> Self {
        Self {
            a: self.a.clone(),
            b: self.b.clone(),
            c: self.c.clone(),
            d: self.d.clone(),
            e: self.e.clone(),
        }
    }

    fn clone_from(&mut self, source: &Self) {
        self.a.clone_from(&source.a);
        self.b.clone_from(&source.b);
        self.c.clone_from(&source.c);
        self.d.clone_from(&source.d);
        self.e.clone_from(&source.e);
    }
}

impl IndexSets {
    /// All sets empty, for `n_normal` contacts and `n_laws` friction laws.
    #[must_use]
    pub fn empty(n_normal: usize, n_laws: usize) -> Self {
        Self {
            a: vec![false; n_normal],
            b: vec![false; n_normal],
            c: vec![false; n_normal],
            d: vec![false; n_laws],
            e: vec![false; n_laws],
        }
    }

    /// Makes these sets [`IndexSets::empty`] for `n_normal` contacts and `n_laws`
    /// friction laws, in their own buffers.
    pub fn reset(&mut self, n_normal: usize, n_laws: usize) {
        for (v, n) in [
            (&mut self.a, n_normal),
            (&mut self.b, n_normal),
            (&mut self.c, n_normal),
            (&mut self.d, n_laws),
            (&mut self.e, n_laws),
        ] {
            v.clear();
            v.resize(n, false);
        }
    }

    /// Whether the sizes match and the nesting A ⊇ B ⊇ C, D ⊇ E holds.
    #[must_use]
    pub fn is_consistent(&self, n_normal: usize, n_laws: usize) -> bool {
        self.a.len() == n_normal
            && self.b.len() == n_normal
            && self.c.len() == n_normal
            && self.d.len() == n_laws
            && self.e.len() == n_laws
            && (0..n_normal).all(|k| (!self.b[k] || self.a[k]) && (!self.c[k] || self.b[k]))
            && (0..n_laws).all(|j| !self.e[j] || self.d[j])
    }

    /// Whether the normal contacts are in the same sets (A, B and C equal), whatever
    /// the friction laws.
    #[must_use]
    pub fn same_normal_sets(&self, other: &IndexSets) -> bool {
        self.a == other.a && self.b == other.b && self.c == other.c
    }

    /// Compact text form, e.g. `A=[0,1] B=[1] C=[] D=[0] E=[]`.
    #[must_use]
    pub fn describe(&self) -> String {
        let f = |v: &[bool]| {
            let idx: Vec<String> = v
                .iter()
                .enumerate()
                .filter(|(_, &x)| x)
                .map(|(i, _)| i.to_string())
                .collect();
            format!("[{}]", idx.join(","))
        };
        format!(
            "A={} B={} C={} D={} E={}",
            f(&self.a),
            f(&self.b),
            f(&self.c),
            f(&self.d),
            f(&self.e)
        )
    }
}

/// The contacts (or laws) of `opening`, ascending, past the `most` whose `strength`
/// (prox argument) is largest: those an update with a limit on openings keeps in their
/// closed or sticking sets. Ties go to the lower index (the sort is stable).
pub(crate) fn beyond_the_strongest(
    mut opening: Vec<usize>,
    most: usize,
    strength: impl Fn(usize) -> f64,
) -> Vec<usize> {
    if opening.len() <= most {
        return Vec::new();
    }
    opening.sort_by(|&i, &j| strength(j).total_cmp(&strength(i)));
    opening.split_off(most)
}

#[cfg(test)]
mod tests {
    use super::{beyond_the_strongest, IndexSets};

    #[test]
    fn the_strongest_open_and_the_others_are_kept() {
        let strength = |k: usize| [0.0, 0.5, 3.0, 0.0, 1.0, 0.0, 0.0, 3.0][k];
        // Ties go to the lower index.
        let mut kept = beyond_the_strongest(vec![1, 2, 4, 7], 1, strength);
        kept.sort_unstable();
        assert_eq!(kept, [1, 4, 7]);
        assert!(beyond_the_strongest(vec![1, 2, 4, 7], 4, strength).is_empty());
    }

    /// A copy of `s` with every set filled, then reset to its sizes.
    fn opened_and_reset(s: &IndexSets) -> IndexSets {
        let mut t = s.clone();
        for v in [&mut t.a, &mut t.b, &mut t.c, &mut t.d, &mut t.e] {
            v.iter_mut().for_each(|x| *x = true);
        }
        t.reset(s.a.len(), s.d.len());
        t
    }

    #[test]
    fn a_copy_from_other_sets_keeps_its_buffers() {
        let mut s = IndexSets::empty(3, 2);
        (s.a[0], s.b[2], s.d[1]) = (true, true, true);
        let mut t = IndexSets::empty(4, 2);
        let buffers = [&t.a, &t.b, &t.c, &t.d, &t.e].map(Vec::as_ptr);
        t.clone_from(&s);
        assert_eq!(t, s);
        assert_eq!([&t.a, &t.b, &t.c, &t.d, &t.e].map(Vec::as_ptr), buffers);
    }

    #[test]
    fn normal_sets_compare_without_the_friction_sets() {
        let mut s = IndexSets::empty(2, 1);
        s.a = vec![true, true];
        let mut slipping = s.clone();
        slipping.d = vec![true];
        assert!(s.same_normal_sets(&slipping));
        let mut reused = opened_and_reset(&s);
        assert_eq!(reused, IndexSets::empty(2, 1));
        reused.reset(1, 3);
        assert_eq!(reused, IndexSets::empty(1, 3));
        let mut opened = s.clone();
        opened.a[1] = false;
        assert!(!s.same_normal_sets(&opened));
        let mut closed_on_velocity = s.clone();
        closed_on_velocity.b[0] = true;
        assert!(!s.same_normal_sets(&closed_on_velocity));
    }
}
