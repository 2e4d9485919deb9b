//! Islands of a step (docs/method.md §7, "Islands"): the bodies that the constraints
//! connect, and the islands whose equations already hold at an attempt's first iterate,
//! which are left out of its linear solves.
//!
//! Two bodies interact only through constraints when the system says so
//! ([`System::unknowns_per_body`]): then the step's equations split into one block per
//! connected component of the graph whose vertices are the bodies and whose edges are
//! the constraints, every constraint the system lists, open or closed (its force
//! direction W names the bodies it acts on). A prescribed base or a floor is not a body,
//! so it joins nothing. Ordered by island, the Newton matrix is block diagonal, and
//! Newton's update of one island does not depend on the others' residuals: an island
//! whose rows of the residual are within the tolerance at the first iterate (a pile at
//! rest, a block in free flight from its predicted start) is already solved, and the
//! attempt goes on with its unknowns fixed and its rows and columns out of the matrix.

use super::prune::{number_kept, Pruning};
use super::unknowns::Offsets;
use super::Stepper;
use crate::system::{Evaluation, FrictionLaw, System};

/// The island of each unknown of x, numbered 0, 1, … (a union–find's roots renumbered).
#[derive(Debug, Default)]
pub(super) struct Islands {
    /// Island of each unknown (length n).
    pub of_unknown: Vec<usize>,
    /// Number of islands.
    pub count: usize,
}

/// A union–find over the vertices 0..n: bodies first, then constraints.
struct Components(Vec<usize>);

impl Components {
    fn new(n: usize) -> Self {
        Self((0..n).collect())
    }

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

impl Islands {
    /// The islands of a system with `per_body` velocity unknowns per body, from the
    /// force directions and mass matrix of the evaluation `e`. The vertices are the
    /// bodies, then the position constraints (g, g_N), then the velocity constraints
    /// (γ, γ_F); a constraint joins the bodies its W acts on, a friction law its normal
    /// contacts, and a mass entry its two bodies.
    pub(super) fn new(
        o: &Offsets,
        per_body: usize,
        e: &Evaluation<f64>,
        laws: &[FrictionLaw],
    ) -> Self {
        let bodies = o.nu.div_ceil(per_body);
        let position = bodies;
        let velocity = position + o.ng + o.nn;
        let mut c = Components::new(velocity + o.nga + o.nf);
        for &(i, k, _) in &e.position_w.entries {
            c.join(i / per_body, position + k);
        }
        // A friction law acts only through its normal contacts' forces: one whose
        // normals have no force direction (an interface that lost its support) cannot
        // close, carries no force, and joins nothing.
        let mut can_close = vec![false; o.nn];
        for &(_, k, _) in &e.position_w.entries {
            if k >= o.ng {
                can_close[k - o.ng] = true;
            }
        }
        let mut acting = vec![true; o.nga + o.nf];
        let mut first = o.nga;
        for law in laws {
            let acts = law.normals.iter().any(|&k| can_close[k]);
            acting[first..first + law.components].fill(acts);
            first += law.components;
        }
        for &(i, k, _) in &e.velocity_w.entries {
            if acting[k] {
                c.join(i / per_body, velocity + k);
            }
        }
        for &(i, j, _) in &e.mass.entries {
            c.join(i / per_body, j / per_body);
        }
        let mut component = velocity + o.nga;
        for law in laws {
            for m in 0..law.components {
                for &k in &law.normals {
                    c.join(component + m, position + o.ng + k);
                }
            }
            component += law.components;
        }
        let vertex_of = |u: usize| -> usize {
            match u {
                u if u < o.kg => (u % o.nu) / per_body,
                u if u < o.cga => position + (u - o.kg) % o.ng.max(1),
                u if u < o.kn => velocity + (u - o.cga) % o.nga.max(1),
                u if u < o.cf => position + o.ng + (u - o.kn) % o.nn.max(1),
                u => velocity + o.nga + (u - o.cf) % o.nf.max(1),
            }
        };
        let mut number = vec![usize::MAX; c.0.len()];
        let mut count = 0;
        let of_unknown = (0..o.n)
            .map(|u| {
                let root = c.root(vertex_of(u));
                if number[root] == usize::MAX {
                    number[root] = count;
                    count += 1;
                }
                number[root]
            })
            .collect();
        Self { of_unknown, count }
    }

    /// The largest |R| over each island's rows (rows and unknowns share their numbering).
    fn residuals(&self, res: &[f64]) -> Vec<f64> {
        let mut largest = vec![0.0_f64; self.count];
        for (&island, &r) in self.of_unknown.iter().zip(res) {
            largest[island] = largest[island].max(r.abs());
        }
        largest
    }
}

/// The islands solved at an attempt's first iterate: which unknowns are fixed.
#[derive(Debug, Clone)]
pub(super) struct Frozen {
    /// Whether each unknown belongs to a solved island.
    pub unknowns: Vec<bool>,
}

impl Frozen {
    /// Whether some row of a fixed island no longer holds within `tol` in `res`: the
    /// constraints changed the islands (a contact gained its force direction within the
    /// step), and the attempt must go on with every island solved.
    pub(super) fn broken(&self, res: &[f64], tol: f64) -> bool {
        self.unknowns
            .iter()
            .zip(res)
            .any(|(&frozen, &r)| frozen && r.abs() > tol)
    }
}

impl<S: System> Stepper<S> {
    /// The islands whose rows of the residual `work.res` (at the current iterate, just
    /// evaluated) hold within the tolerance, when some other island's do not: the
    /// unknowns to fix, and `prune` extended by them (the map full → reduced of the
    /// unknowns left in the linear solve). None when the system has no bodies
    /// ([`System::unknowns_per_body`]), when every island or none is solved.
    pub(super) fn solved_islands(&self, prune: Option<&Pruning>) -> Option<(Frozen, Pruning)> {
        let per_body = self.system.unknowns_per_body()?;
        let o = &self.off;
        let islands = Islands::new(o, per_body, &self.work.eval, &self.layout.friction);
        if islands.count < 2 {
            return None;
        }
        let tol = self.options.tol;
        let solved: Vec<bool> = islands
            .residuals(&self.work.res)
            .iter()
            .map(|&r| r <= tol)
            .collect();
        if solved.iter().all(|&s| s) || !solved.iter().any(|&s| s) {
            return None;
        }
        let unknowns: Vec<bool> = islands.of_unknown.iter().map(|&i| solved[i]).collect();
        let mut map = match prune {
            Some((map, _)) => map.clone(),
            None => vec![0; o.n],
        };
        for (m, &frozen) in map.iter_mut().zip(&unknowns) {
            if frozen {
                *m = usize::MAX;
            }
        }
        let n_red = number_kept(&mut map);
        Some((Frozen { unknowns }, (map, n_red)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::Layout;

    /// Three bodies of one unknown each; body 0 and 1 share a contact, body 2 rests on
    /// the ground by another (W on body 2 alone), and a third contact lists no force
    /// direction.
    #[test]
    fn a_contact_joins_its_bodies_and_the_ground_joins_nothing() {
        let layout = Layout {
            nq: 3,
            nu: 3,
            n_bilateral_position: 0,
            n_bilateral_velocity: 0,
            e_n: vec![0.0; 3],
            friction: vec![FrictionLaw {
                components: 1,
                mu: 0.5,
                e_f: 0.0,
                normals: vec![1],
            }],
        };
        let o = Offsets::new(&layout);
        let mut e = Evaluation::new(&layout);
        for i in 0..3 {
            e.mass.push(i, i, 1.0);
        }
        e.position_w.push(0, 0, -1.0);
        e.position_w.push(1, 0, 1.0);
        e.position_w.push(2, 1, 1.0);
        let islands = Islands::new(&o, 1, &e, &layout.friction);
        let of = |u: usize| islands.of_unknown[u];
        // The bodies 0 and 1 and contact 0's unknowns are one island.
        assert_eq!(of(o.a), of(o.a + 1));
        assert_eq!(of(o.uu), of(o.kn));
        assert_eq!(of(o.qq + 1), of(o.ln));
        // Body 2, contact 1 and its friction law another.
        assert_eq!(of(o.a + 2), of(o.cn + 1));
        assert_eq!(of(o.a + 2), of(o.cf));
        assert_ne!(of(o.a), of(o.a + 2));
        // Contact 2, without W, is an island of its own unknowns.
        assert_eq!(of(o.kn + 2), of(o.ln + 2));
        assert_ne!(of(o.kn + 2), of(o.a));
        assert_ne!(of(o.kn + 2), of(o.a + 2));
        assert_eq!(islands.count, 3);
    }
}
