//! Islands of a Newton attempt, each watched for a settled cycle of its own
//! (docs/method.md §8.1, "Islands cycle on their own").
//!
//! In a system of bodies that interact only through constraints
//! ([`System::unknowns_per_body`]), the bodies that closed contacts join make an island,
//! and a prescribed base or a floor joins nothing. Ordered by island, the Newton matrix
//! is block diagonal: each island's update depends on its own rows alone, and its index
//! sets follow a course of their own. Blocks scattered over a floor are dozens of
//! islands, and where several cycle with different periods the sets of the whole system
//! combine their phases into sets that are mostly new, so that [`settled_cycle`] on the
//! whole system never recognizes the cycle and the attempt runs its whole budget. Here
//! each island's sets and largest residual row are recorded per iterate, and the attempt
//! gives up as soon as one island has settled into a cycle without progress: the whole
//! system cannot converge while one island's iterates repeat.
//!
//! [`System::unknowns_per_body`]: crate::System::unknowns_per_body

use super::unknowns::Offsets;
use crate::newton::settled_cycle;
use crate::sets::IndexSets;
use crate::system::{Evaluation, FrictionLaw};
use crate::Tuning;
use std::collections::hash_map::DefaultHasher;
use std::hash::{Hash, Hasher};

/// A union–find over the bodies 0..n.
struct Components(Vec<usize>);

impl Components {
    fn root(&mut self, mut v: usize) -> usize {
        while self.0[v] != v {
            // Path halving: each visited vertex points to its grandparent.
            self.0[v] = self.0[self.0[v]];
            v = self.0[v];
        }
        v
    }

    fn join(&mut self, a: usize, b: usize) {
        let (ra, rb) = (self.root(a), self.root(b));
        if ra != rb {
            self.0[ra.max(rb)] = ra.min(rb);
        }
    }
}

/// The islands of one attempt and, per island, the sets and residuals of its iterates.
#[derive(Debug)]
pub(super) struct IslandHistory {
    per_body: usize,
    /// Island of each body, numbered 0, 1, … in the order of their least body.
    of_body: Vec<usize>,
    /// Island of each normal contact: that of the bodies its force direction acts on;
    /// None for a contact without one (it cannot close and joins nothing).
    of_contact: Vec<Option<usize>>,
    /// Per island: the fingerprints of the sets it visited (first-visit order), the id
    /// of each iterate's sets among them, and each iterate's largest residual row.
    visited: Vec<Vec<u64>>,
    history: Vec<Vec<usize>>,
    residuals: Vec<Vec<f64>>,
}

impl IslandHistory {
    /// The islands of a system with `per_body` velocity unknowns per body, joined by
    /// the bilateral position constraints and the normal contacts `closed` (on position
    /// level), each through the bodies its force direction in `e` acts on.
    pub(super) fn new(o: &Offsets, per_body: usize, e: &Evaluation<f64>, closed: &[bool]) -> Self {
        let bodies = o.nu.div_ceil(per_body);
        let mut components = Components((0..bodies).collect());
        // The first body each position constraint acts on; the others join it.
        let mut first = vec![None; o.ng + o.nn];
        for &(i, k, _) in &e.position_w.entries {
            let body = i / per_body;
            match first[k] {
                None => first[k] = Some(body),
                Some(f) if k < o.ng || closed[k - o.ng] => components.join(f, body),
                Some(_) => {}
            }
        }
        let mut number = vec![None; bodies];
        let mut count = 0;
        let of_body: Vec<usize> = (0..bodies)
            .map(|b| {
                let root = components.root(b);
                *number[root].get_or_insert_with(|| {
                    count += 1;
                    count - 1
                })
            })
            .collect();
        let of_contact = first[o.ng..]
            .iter()
            .map(|f| f.map(|b| of_body[b]))
            .collect();
        Self {
            per_body,
            of_body,
            of_contact,
            visited: vec![Vec::new(); count],
            history: vec![Vec::new(); count],
            residuals: vec![Vec::new(); count],
        }
    }

    fn count(&self) -> usize {
        self.visited.len()
    }

    /// Records an iterate: per island, its contacts' and friction laws' sets in `sets`
    /// (a 64-bit fingerprint: two sets of one island that collide would be one) and
    /// its largest row of the residual `res` (its bodies' a, U, Q rows and its contacts'
    /// and laws' rows). Nothing for a system of one island, which the whole system's
    /// cycle test covers.
    pub(super) fn record(
        &mut self,
        sets: &IndexSets,
        res: &[f64],
        o: &Offsets,
        (law_off, laws): (&[usize], &[FrictionLaw]),
    ) {
        let count = self.count();
        if count < 2 {
            return;
        }
        let mut fingerprints = vec![DefaultHasher::new(); count];
        let mut largest = vec![0.0_f64; count];
        let mut add_rows = |island: usize, rows: &mut dyn Iterator<Item = usize>| {
            for r in rows {
                largest[island] = largest[island].max(res[r].abs());
            }
        };
        for (k, island) in self.of_contact.iter().enumerate() {
            if let Some(island) = *island {
                (k, sets.a[k], sets.b[k], sets.c[k]).hash(&mut fingerprints[island]);
                add_rows(island, &mut [o.kn + k, o.cn + k, o.ln + k].into_iter());
            }
        }
        for (j, law) in laws.iter().enumerate() {
            // A law acts on its normal contacts' bodies; one whose normals have no force
            // direction belongs to no island.
            let Some(island) = law.normals.iter().find_map(|&k| self.of_contact[k]) else {
                continue;
            };
            (j, sets.d[j], sets.e[j]).hash(&mut fingerprints[island]);
            let components = law_off[j]..law_off[j] + law.components;
            add_rows(island, &mut components.flat_map(|c| [o.cf + c, o.lf + c]));
        }
        for (v, body) in (0..o.nu).map(|v| (v, v / self.per_body)) {
            let island = self.of_body[body];
            add_rows(island, &mut [o.a + v, o.uu + v, o.qq + v].into_iter());
        }
        for (island, fingerprint) in fingerprints.iter().enumerate() {
            let key = fingerprint.finish();
            let visited = &mut self.visited[island];
            let id = visited.iter().position(|&v| v == key).unwrap_or_else(|| {
                visited.push(key);
                visited.len() - 1
            });
            self.history[island].push(id);
            self.residuals[island].push(largest[island]);
        }
    }

    /// Whether some island has settled into a cycle without progress
    /// ([`settled_cycle`] on its own sets and residuals).
    pub(super) fn cycles(&self, tuning: &Tuning) -> bool {
        self.history
            .iter()
            .zip(&self.residuals)
            .any(|(history, residuals)| settled_cycle(history, residuals, tuning))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::Layout;

    /// Three bodies of one unknown each and three contacts: contact 0 joins bodies 0
    /// and 1, contact 1 presses body 2 on the ground, contact 2 would join bodies 1 and
    /// 2; body 2 has a friction law on contact 1.
    fn three_bodies() -> (Offsets, Evaluation<f64>, Vec<FrictionLaw>) {
        let friction = vec![FrictionLaw {
            components: 1,
            mu: 0.5,
            e_f: 0.0,
            normals: vec![1],
        }];
        let layout = Layout {
            nq: 3,
            nu: 3,
            n_bilateral_position: 0,
            n_bilateral_velocity: 0,
            e_n: vec![0.0; 3],
            friction: friction.clone(),
        };
        let mut e = Evaluation::new(&layout);
        for (body, contact, w) in [
            (0, 0, -1.0),
            (1, 0, 1.0),
            (2, 1, 1.0),
            (1, 2, -1.0),
            (2, 2, 1.0),
        ] {
            e.position_w.push(body, contact, w);
        }
        (Offsets::new(&layout), e, friction)
    }

    fn sets(a: [bool; 3], d: bool) -> IndexSets {
        IndexSets {
            a: a.to_vec(),
            b: a.to_vec(),
            c: a.to_vec(),
            d: vec![d],
            e: vec![d],
        }
    }

    #[test]
    fn closed_contacts_join_their_bodies_and_the_ground_joins_nothing() {
        let (o, e, _) = three_bodies();
        // Contact 2 open: bodies 0 and 1 are one island, body 2 another.
        let islands = IslandHistory::new(&o, 1, &e, &[true, true, false]);
        assert_eq!(islands.of_body, [0, 0, 1]);
        assert_eq!(islands.of_contact, [Some(0), Some(1), Some(0)]);
        // Contact 2 closed: one island.
        let islands = IslandHistory::new(&o, 1, &e, &[true, true, true]);
        assert_eq!(islands.of_body, [0, 0, 0]);
    }

    /// One island cycles with period 2 and no progress while the other's sets change
    /// at every iterate: the whole system's sets never repeat, so its own cycle test
    /// cannot see the cycle; the island's does.
    #[test]
    fn an_island_that_cycles_is_seen_while_the_whole_sets_never_repeat() {
        let (o, e, laws) = three_bodies();
        let mut islands = IslandHistory::new(&o, 1, &e, &[true, true, false]);
        let tuning = Tuning::default();
        let mut res = vec![0.0; o.n];
        let mut whole = Vec::new();
        let mut gave_up_at = None;
        for iterate in 0..12 {
            // Island 0 (bodies 0, 1; contacts 0 and 2) alternates contact 2's sets at a
            // flat residual; island 1 (body 2, contact 1 and its law) takes a new
            // friction state and a smaller residual at every iterate.
            let flip = iterate % 2 == 1;
            let s = sets([true, iterate % 3 == 0, flip], iterate % 4 < 2);
            res[o.cn + 2] = if flip { 2e-3 } else { 3e-3 };
            res[o.cn + 1] = 1e-2 * 0.9_f64.powi(iterate);
            islands.record(&s, &res, &o, (&[0], &laws));
            whole.push(s);
            if gave_up_at.is_none() && islands.cycles(&tuning) {
                gave_up_at = Some(iterate);
            }
        }
        // Period 2 takes three repetitions: the sixth iterate.
        assert_eq!(gave_up_at, Some(5));
        let distinct = |n: usize| (0..n).filter(|&i| !whole[..i].contains(&whole[i])).count();
        assert!(distinct(6) >= 5, "the whole sets repeat: {}", distinct(6));
    }
}
