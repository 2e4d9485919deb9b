//! Where a converged step may have other solutions by Painlevé's indeterminacy (App. I,
//! (I.1.7)–(I.1.9)): a touching contact that slides and whose normal acceleration
//! *decreases* with its own normal force once the friction that force brings is counted,
//! b = w_Nᵀ M⁻¹ (w_N + μ s w_F) ≤ 0 with s the sign of the friction force. There the
//! contact problem of the step can have lift-off, sliding contact and jam at once, which
//! Newton's iterates need not reveal, and the flip probe
//! ([`PolicyOptions::probe_painleve`](crate::PolicyOptions::probe_painleve)) looks for them.
//! Elsewhere (b > 0 for every sliding contact, a block with μ < 4/3 whatever its angle)
//! one contact's problem has one solution and the probe is not run.

use super::Stepper;
use crate::attempt::Trial;
use crate::system::{FrictionLaw, System};

/// The most entries of one column of W that [`Column`] holds: a contact between two planar
/// bodies touches six velocities.
const COLUMN_ENTRIES: usize = 16;

/// One column of W, its entries summed by velocity (no allocation: the check runs at
/// every converged step with a sliding contact).
struct Column {
    entries: [(usize, f64); COLUMN_ENTRIES],
    len: usize,
}

impl Column {
    /// Column `c` of `w`; None when it has more than [`COLUMN_ENTRIES`] velocities.
    fn of(w: &crate::system::Triplets<f64>, c: usize) -> Option<Self> {
        let mut col = Self {
            entries: [(0, 0.0); COLUMN_ENTRIES],
            len: 0,
        };
        for &(i, _, v) in w.entries.iter().filter(|&&(_, k, _)| k == c) {
            match col.entries[..col.len].iter_mut().find(|e| e.0 == i) {
                Some(e) => e.1 += v,
                None if col.len < COLUMN_ENTRIES => {
                    col.entries[col.len] = (i, v);
                    col.len += 1;
                }
                None => return None,
            }
        }
        Some(col)
    }

    fn at(&self, i: usize) -> f64 {
        self.entries[..self.len]
            .iter()
            .find(|e| e.0 == i)
            .map_or(0.0, |e| e.1)
    }

    fn iter(&self) -> impl Iterator<Item = &(usize, f64)> {
        self.entries[..self.len].iter()
    }
}

impl<S: System> Stepper<S> {
    /// Whether some touching normal contact of the converged `trial` (closed in its sets,
    /// or at zero gap at the step's start: Newton's solution may be the lift-off) is
    /// bounded by a one-component friction law that slips at the step's end and has
    /// b ≤ 0 (module docs), the friction force opposing the slip. Read from the
    /// evaluation of the attempt's last iterate, which is `trial`'s; false for a mass
    /// matrix that is not diagonal (its inverse is not at hand).
    pub(super) fn painleve_possible(&mut self, trial: &Trial) -> bool {
        let o = self.off;
        let sets = &trial.stats.sets;
        // Laws that slip (not sticking on velocity level) with one component are the only
        // candidates, and there are none in most steps. A law with a closed normal contact
        // is checked on its closed ones; one without, on those at zero gap at the step's
        // start (kept from the pruning of open contacts, or evaluated once).
        let least = self.system.least_painleve_friction();
        let sliding = |l: &FrictionLaw, j: usize| l.components == 1 && !sets.d[j] && l.mu >= least;
        let closed = |l: &FrictionLaw| l.normals.iter().any(|&k| sets.a[k]);
        // An open contact the attempt pruned cannot close within the step: not touching.
        let unused = &self.work.unused_position;
        let near = |l: &FrictionLaw| {
            l.normals
                .iter()
                .any(|&k| unused.get(o.ng + k) != Some(&true))
        };
        let (mut any, mut by_gap) = (false, false);
        for (j, l) in self.layout.friction.iter().enumerate() {
            if sliding(l, j) && (closed(l) || near(l)) {
                any = true;
                by_gap |= !closed(l);
            }
        }
        if !any {
            return false;
        }
        if by_gap {
            self.state_levels();
        }
        let laws = &self.layout.friction;
        let e = &self.work.eval;
        if e.mass.entries.iter().any(|&(i, j, _)| i != j) {
            return false;
        }
        let inverse_mass = |i: usize| {
            1.0 / e
                .mass
                .entries
                .iter()
                .filter(|m| m.0 == i)
                .map(|m| m.2)
                .sum::<f64>()
        };
        let touching = |j: usize, k: usize| {
            if closed(&laws[j]) {
                sets.a[k]
            } else {
                by_gap && self.at_zero_gap(k)
            }
        };
        let u = &trial.state.u;
        for (j, law) in laws.iter().enumerate() {
            if !sliding(law, j) || !law.normals.iter().any(|&k| touching(j, k)) {
                continue;
            }
            let f = o.nga + self.law_off[j];
            let Some(w_f) = Column::of(&e.velocity_w, f) else {
                return true;
            };
            let slip = e.velocity_chi[f] + w_f.iter().map(|&(i, v)| v * u[i]).sum::<f64>();
            if slip == 0.0 {
                continue;
            }
            // The friction force λ_F w_F opposes the slip and moves with the normal forces
            // it is bounded by as μ s.
            let s = -slip.signum();
            for &k in law.normals.iter().filter(|&&k| touching(j, k)) {
                let Some(w_n) = Column::of(&e.position_w, o.ng + k) else {
                    return true;
                };
                let b: f64 = w_n
                    .iter()
                    .map(|&(i, v)| v * inverse_mass(i) * (v + law.mu * s * w_f.at(i)))
                    .sum();
                if b <= 0.0 {
                    return true;
                }
            }
        }
        false
    }
}
