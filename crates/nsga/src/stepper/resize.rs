//! Contacts that come and go between steps (docs/method.md §10).
//!
//! A system whose set of contacts changes during a run (a broad phase that adds the
//! contacts of two bodies when they come close) keeps its layout fixed *within* a step
//! and changes it only between steps, in two ways the stepper supports:
//!
//! - **growth**: the system appends normal contacts and friction laws at the end of its
//!   lists ([`Stepper::extend_layout`]); every existing contact keeps its index, its
//!   forces and its place in the next Newton start, and the new ones start open with
//!   zero forces;
//! - **reuse**: a contact slot whose pair of bodies has separated is given to another
//!   pair ([`Stepper::forget_contacts`]); its forces, percussions and Newton start are
//!   zeroed, because they belong to the old pair. A slot is only reused when its contact
//!   is open by more than the broad phase's margin, so what is forgotten was (up to the
//!   decay of the generalized-α auxiliary forces) zero already.
//!
//! Growth drops the kept factorization of the Newton matrix and the predicted start's
//! history, whose sizes are the old layout's. Reuse keeps both and zeroes the forgotten
//! entries of the history: the kept factors only give simplified updates, which each
//! attempt judges by the residual they leave (docs/method.md §7), and a slot open by the
//! margin is pruned from the matrix before and after. Dropping them cost the next step
//! a factorization and its prediction, and a contact beside a teetering block can change
//! hands every other step (docs/contacts.md, "How the system's size changes").

use super::{Offsets, Stepper, Work};
use crate::error::StepError;
use crate::system::System;

impl<S: System> Stepper<S> {
    /// Re-reads the system's layout after it appended normal contacts and friction laws
    /// (see the module docs). The state is carried over: the old contacts keep their
    /// indices and values, the new ones start with zero forces.
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] when the new layout is invalid or does not extend the
    /// old one (other sizes of q, u or the bilateral constraints, or a changed contact);
    /// nothing changes then.
    pub fn extend_layout(&mut self) -> Result<(), StepError> {
        let new = self.system.layout();
        new.validate().map_err(StepError::InvalidInput)?;
        let old = &self.layout;
        let extends = new.nq == old.nq
            && new.nu == old.nu
            && new.n_bilateral_position == old.n_bilateral_position
            && new.n_bilateral_velocity == old.n_bilateral_velocity
            && new.e_n.len() >= old.e_n.len()
            && new.e_n[..old.e_n.len()] == old.e_n[..]
            && new.friction.len() >= old.friction.len()
            && new.friction[..old.friction.len()] == old.friction[..];
        if !extends {
            return Err(StepError::InvalidInput(
                "the new layout does not extend the old one: only normal contacts and \
                 friction laws appended at the end are allowed"
                    .into(),
            ));
        }
        let (from, to) = (self.off, Offsets::new(&new));
        let st = &mut self.state;
        for v in [&mut st.lambda_n, &mut st.lambda_n_bar, &mut st.p_n] {
            v.resize(to.nn, 0.0);
        }
        for v in [&mut st.lambda_f, &mut st.lambda_f_bar, &mut st.p_f] {
            v.resize(to.nf, 0.0);
        }
        st.x = carried_unknowns(&st.x, &from, &to);
        let solves = self.work.linear_solves;
        self.work = Work::new(&new, &self.options);
        self.work.linear_solves = solves;
        self.law_off = new.friction_offsets();
        self.comp_ef = new.friction_restitution();
        self.off = to;
        self.layout = new;
        self.forget_solutions();
        Ok(())
    }

    /// Zeroes the forces, percussions and Newton start of the given normal contacts and
    /// friction laws, whose slots now hold other pairs of bodies (see the module docs).
    ///
    /// # Errors
    /// [`StepError::InvalidInput`] for an index out of range; nothing changes then.
    pub fn forget_contacts(&mut self, normals: &[usize], laws: &[usize]) -> Result<(), StepError> {
        let o = self.off;
        if normals.iter().any(|&k| k >= o.nn) || laws.iter().any(|&j| j >= self.law_off.len()) {
            return Err(StepError::InvalidInput(
                "a contact to forget is out of range".into(),
            ));
        }
        let mut forgotten = Vec::new();
        let st = &mut self.state;
        for &k in normals {
            st.lambda_n[k] = 0.0;
            st.lambda_n_bar[k] = 0.0;
            st.p_n[k] = 0.0;
            for start in [o.kn, o.cn, o.ln] {
                st.x[start + k] = 0.0;
                forgotten.push(start + k);
            }
        }
        for &j in laws {
            let first = self.law_off[j];
            for c in first..first + self.layout.friction[j].components {
                st.lambda_f[c] = 0.0;
                st.lambda_f_bar[c] = 0.0;
                st.p_f[c] = 0.0;
                st.x[o.cf + c] = 0.0;
                st.x[o.lf + c] = 0.0;
                forgotten.extend([o.cf + c, o.lf + c]);
            }
        }
        // The forgotten slots' past unknowns belong to other pairs of bodies; everything
        // else the last steps left is kept (see the module docs). An island held at rest
        // keeps resting unless one of its contacts is forgotten: a new pair's contact
        // that reaches it changes its rows, and wakes it.
        self.predictor.forget(&forgotten);
        self.forget_levels();
        self.islands.forget_contacts(normals);
        Ok(())
    }
}

/// The unknowns x (eq. 126) of layout `from` placed in the blocks of layout `to`: every
/// block keeps its leading entries, the appended contacts' entries are zero.
fn carried_unknowns(x: &[f64], from: &Offsets, to: &Offsets) -> Vec<f64> {
    let mut out = vec![0.0; to.n];
    let blocks = [
        (from.a, to.a, 3 * from.nu),
        (from.kg, to.kg, 3 * from.ng + 2 * from.nga),
        (from.kn, to.kn, from.nn),
        (from.cn, to.cn, from.nn),
        (from.ln, to.ln, from.nn),
        (from.cf, to.cf, from.nf),
        (from.lf, to.lf, from.nf),
    ];
    for (src, dst, len) in blocks {
        out[dst..dst + len].copy_from_slice(&x[src..src + len]);
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::options::Options;
    use crate::system::{Evaluation, FrictionLaw, Layout, Scalar, System};
    use crate::Stepper;

    /// A unit point mass falling onto the ground, with `extra` copies of its ground
    /// contact appended (each with its own friction law): the growth of a layout.
    /// `spring` pulls it horizontally towards x = 0 (its forces then change in time).
    #[derive(Debug, Clone)]
    struct Falling {
        extra: usize,
        spring: f64,
    }

    impl System for Falling {
        fn layout(&self) -> Layout {
            let laws = 1 + self.extra;
            Layout {
                nq: 2,
                nu: 2,
                e_n: vec![0.0; laws],
                friction: (0..laws)
                    .map(|k| FrictionLaw {
                        components: 1,
                        mu: 0.5,
                        e_f: 0.0,
                        normals: vec![k],
                    })
                    .collect(),
                ..Layout::default()
            }
        }

        fn evaluate<T: Scalar>(&self, _t: f64, q: &[T], _u: &[T], out: &mut Evaluation<T>) {
            out.mass.push(0, 0, T::from(1.0));
            out.mass.push(1, 1, T::from(1.0));
            out.forces[0] = -q[0] * self.spring;
            out.forces[1] = T::from(-9.81);
            // The first contact is the ground; the copies are a wall far away (open).
            out.position[0] = q[1];
            out.position_w.push(1, 0, T::from(1.0));
            out.velocity_w.push(0, 0, T::from(1.0));
            for k in 1..=self.extra {
                out.position[k] = T::from(10.0) - q[0];
                out.position_w.push(0, k, T::from(-1.0));
                out.velocity_w.push(1, k, T::from(1.0));
            }
        }
    }

    /// [`Falling`] with `extra` copies of its contact and no spring.
    fn falling(extra: usize) -> Falling {
        Falling { extra, spring: 0.0 }
    }

    fn options() -> Options {
        Options {
            dt: 1e-2,
            ..Options::default()
        }
    }

    #[test]
    fn a_grown_layout_gives_the_motion_of_the_layout_built_whole() {
        let (q0, u0) = ([0.0, 0.3], [1.0, 0.0]);
        let mut grown = Stepper::new(falling(0), 0.0, &q0, &u0, options()).unwrap();
        let mut whole = Stepper::new(falling(2), 0.0, &q0, &u0, options()).unwrap();
        for k in 0..60 {
            if k == 20 {
                grown.system_mut().extra = 2;
                grown.extend_layout().unwrap();
            }
            grown.step().unwrap();
            whole.step().unwrap();
        }
        let (a, b) = (grown.state(), whole.state());
        assert_eq!(a.lambda_n.len(), 3);
        for (x, y) in a.q.iter().chain(&a.u).zip(b.q.iter().chain(&b.u)) {
            assert!((x - y).abs() < 1e-12, "{x} vs {y}");
        }
        assert!(a.q[1].abs() < 1e-8, "the mass landed and rests");
    }

    #[test]
    fn a_shrunk_or_changed_layout_is_refused() {
        let mut s = Stepper::new(falling(2), 0.0, &[0.0, 0.3], &[0.0; 2], options()).unwrap();
        s.system_mut().extra = 1;
        assert!(s.extend_layout().is_err());
        assert_eq!(s.layout().e_n.len(), 3, "nothing changed");
    }

    #[test]
    fn forgotten_contacts_lose_their_forces() {
        let mut s = Stepper::new(falling(1), 0.0, &[0.0, 0.0], &[0.0; 2], options()).unwrap();
        s.step().unwrap();
        assert!(s.state().lambda_n[0] > 9.0, "the mass rests on the ground");
        s.forget_contacts(&[0], &[0]).unwrap();
        assert_eq!(s.state().lambda_n[0], 0.0);
        assert!(s.forget_contacts(&[2], &[]).is_err());
        s.step().unwrap();
        assert!(
            (s.state().lambda_n[0] - 9.81).abs() < 1e-8,
            "and gets it back"
        );
    }

    /// A slot given to another pair while it is open (the broad phase's case) changes
    /// nothing the next step needs: the step after it is predicted and served by the
    /// kept factors as in a run without the reuse, and ends where that run ends.
    #[test]
    fn forgetting_an_open_slot_keeps_the_factors_and_the_prediction() {
        // The mass slides on the ground against a spring (its sets the same every step,
        // its acceleration changing); slot 1, a wall far away, is open throughout.
        let (q0, u0) = ([0.0, 0.0], [2.0, 0.0]);
        let system = Falling {
            extra: 1,
            spring: 4.0,
        };
        let mut opts = options();
        opts.linear.reuse_factorization = true;
        opts.linear.low_rank_updates = true;
        let mut reused = Stepper::new(system.clone(), 0.0, &q0, &u0, opts.clone()).unwrap();
        let mut kept = Stepper::new(system, 0.0, &q0, &u0, opts).unwrap();
        for k in 0..10 {
            if k == 6 {
                reused.forget_contacts(&[1], &[1]).unwrap();
            }
            reused.step().unwrap();
            kept.step().unwrap();
        }
        assert_eq!(reused.linear_solves(), kept.linear_solves());
        assert_eq!(
            reused.newton_work().evaluations,
            kept.newton_work().evaluations
        );
        let (a, b) = (reused.state(), kept.state());
        for (x, y) in a.q.iter().chain(&a.u).zip(b.q.iter().chain(&b.u)) {
            assert!((x - y).abs() < 1e-12, "{x} vs {y}");
        }
        assert!(a.u[0] > 0.5, "still sliding");
    }
}
