//! The prox parameter of each constraint (docs/method.md §4): r_k = α/(w_kᵀM⁻¹w_k),
//! or one constant.

use crate::options::Prox;
use crate::system::{Evaluation, Layout, Triplets};
use nalgebra::DMatrix;

/// Per-constraint prox parameters r for position- and velocity-level constraints
/// and friction laws (docs/method.md §4): r_k = α/(w_kᵀ M⁻¹ w_k), or a constant.
///
/// The stepper calls this at the start of every Newton attempt: the quadratic forms
/// are accumulated in the output vectors themselves and `diag` is the caller's scratch
/// for the diagonal of M, so that a call allocates nothing once the buffers have grown.
pub(crate) fn prox_parameters(
    prox: Prox,
    layout: &Layout,
    eval: &Evaluation<f64>,
    (r_pos, r_vel, r_law): (&mut Vec<f64>, &mut Vec<f64>, &mut Vec<f64>),
    diag: &mut Vec<f64>,
) {
    let (np, nv) = (layout.n_position(), layout.n_velocity());
    r_pos.clear();
    r_vel.clear();
    r_law.clear();
    let alpha = match prox {
        Prox::Constant(r) => {
            r_pos.resize(np, r);
            r_vel.resize(nv, r);
            r_law.resize(layout.friction.len(), r);
            return;
        }
        Prox::Scaled(a) => a,
    };
    let nu = layout.nu;
    // wᵀM⁻¹w, into r_pos and r_vel until r_of below turns them into r: exact through a
    // dense factorisation for small systems, Jacobi (diagonal of M) for large ones,
    // exact for the block-diagonal masses of rigid bodies with diagonal inertia.
    r_pos.resize(np, 0.0);
    r_vel.resize(nv, 0.0);
    // A diagonal M (point masses, planar rigid bodies) is inverted exactly below.
    let diagonal_mass = eval.mass.entries.iter().all(|&(r, c, _)| r == c);
    if nu <= 60 && !diagonal_mass {
        let columns = |w: &Triplets<f64>, n: usize| {
            let mut cols: Vec<Vec<(usize, f64)>> = vec![Vec::new(); n];
            for &(r, c, v) in &w.entries {
                cols[c].push((r, v));
            }
            cols
        };
        let mut m = DMatrix::<f64>::zeros(nu, nu);
        for &(r, c, v) in &eval.mass.entries {
            m[(r, c)] += v;
        }
        if let Some(minv) = m.try_inverse() {
            let quad = |col: &[(usize, f64)]| {
                let mut s = 0.0;
                for &(i, wi) in col {
                    for &(j, wj) in col {
                        s += wi * minv[(i, j)] * wj;
                    }
                }
                s
            };
            for (k, c) in columns(&eval.position_w, np).iter().enumerate() {
                r_pos[k] = quad(c);
            }
            for (k, c) in columns(&eval.velocity_w, nv).iter().enumerate() {
                r_vel[k] = quad(c);
            }
        }
    } else {
        diag.clear();
        diag.resize(nu, 0.0);
        for &(r, c, v) in &eval.mass.entries {
            if r == c {
                diag[r] += v;
            }
        }
        // Σ w_i²/M_ii per column, accumulated straight from the triplets.
        let accumulate = |w: &Triplets<f64>, quad: &mut [f64]| {
            for &(i, c, v) in &w.entries {
                if diag[i] > 0.0 {
                    quad[c] += v * v / diag[i];
                }
            }
        };
        accumulate(&eval.position_w, r_pos);
        accumulate(&eval.velocity_w, r_vel);
    }
    let r_of = |w: f64| {
        if w > 1e-300 && w.is_finite() {
            alpha / w
        } else {
            alpha
        }
    };
    // A law's r from the largest wᵀM⁻¹w of its components, read before r_vel becomes r.
    let mut component = layout.n_bilateral_velocity;
    for law in &layout.friction {
        let w = r_vel[component..component + law.components]
            .iter()
            .copied()
            .fold(0.0, f64::max);
        r_law.push(r_of(w));
        component += law.components;
    }
    for r in r_pos.iter_mut().chain(r_vel.iter_mut()) {
        *r = r_of(*r);
    }
}
