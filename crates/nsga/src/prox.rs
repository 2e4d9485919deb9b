//! The prox parameter of each constraint (docs/method.md §4): r_k = α/(w_kᵀM⁻¹w_k),
//! or one constant.

use crate::options::Prox;
use crate::system::{Evaluation, Layout, Triplets};
use nalgebra::DMatrix;

/// Per-constraint prox parameters r for position- and velocity-level constraints
/// and friction laws (docs/method.md §4): r_k = α/(w_kᵀ M⁻¹ w_k), or a constant.
pub(crate) fn prox_parameters(
    prox: Prox,
    layout: &Layout,
    eval: &Evaluation<f64>,
    r_pos: &mut Vec<f64>,
    r_vel: &mut Vec<f64>,
    r_law: &mut Vec<f64>,
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
    // wᵀM⁻¹w: exact through a dense factorisation for small systems, Jacobi (diagonal
    // of M) for large ones, exact for the block-diagonal masses of rigid bodies with
    // diagonal inertia.
    let mut quad_pos = vec![0.0; np];
    let mut quad_vel = vec![0.0; nv];
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
                quad_pos[k] = quad(c);
            }
            for (k, c) in columns(&eval.velocity_w, nv).iter().enumerate() {
                quad_vel[k] = quad(c);
            }
        }
    } else {
        let mut diag = vec![0.0; nu];
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
        accumulate(&eval.position_w, &mut quad_pos);
        accumulate(&eval.velocity_w, &mut quad_vel);
    }
    let r_of = |w: f64| {
        if w > 1e-300 && w.is_finite() {
            alpha / w
        } else {
            alpha
        }
    };
    r_pos.extend(quad_pos.iter().map(|&w| r_of(w)));
    r_vel.extend(quad_vel.iter().map(|&w| r_of(w)));
    let ngam = layout.n_bilateral_velocity;
    for (law, f0) in layout.friction.iter().zip(layout.friction_offsets()) {
        let off = ngam + f0;
        let w = (0..law.components)
            .map(|m| quad_vel[off + m])
            .fold(0.0, f64::max);
        r_law.push(r_of(w));
    }
}
