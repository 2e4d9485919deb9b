//! Consistent initial accelerations and forces at t0 (NSGA-SPEC §5).

use crate::error::StepError;
use crate::linalg::{AutoSolver, LinearSolver};
use crate::stepper::{norm, prox_parameters, Options};
use crate::system::{Evaluation, Layout, System};

/// Accelerations and forces at t0 that satisfy the contact laws on acceleration level.
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// a_0.
    pub a: Vec<f64>,
    /// λ_g of the bilateral position constraints.
    pub lambda_g: Vec<f64>,
    /// λ_γ of the bilateral velocity constraints.
    pub lambda_gamma: Vec<f64>,
    /// λ_N.
    pub lambda_n: Vec<f64>,
    /// λ_F.
    pub lambda_f: Vec<f64>,
}

/// Solves, at (t0, q0, u0), M a = h + W λ with g̈ = 0, γ̇ = 0 for the bilateral
/// constraints and, for the contacts with g_N ≤ tol and ġ_N ≤ tol (closed), the
/// acceleration-level laws g̈_N ≥ 0 ⟂ λ_N ≥ 0 and Coulomb on λ_F (sliding contacts
/// along −γ_F/‖γ_F‖, sticking ones by the prox on γ̇_F), by semismooth Newton.
///
/// # Errors
/// [`StepError::Start`] when Newton does not converge or the matrix is singular.
#[allow(clippy::too_many_lines)]
pub fn consistent_start<S: System>(
    system: &S,
    layout: &Layout,
    t0: f64,
    q0: &[f64],
    u0: &[f64],
    options: &Options,
) -> Result<Start, StepError> {
    let (prox, tol, max_iter) = (options.prox, options.start_tol, options.max_iter);
    let (nu, ng, nga, nn, nf) = (
        layout.nu,
        layout.n_bilateral_position,
        layout.n_bilateral_velocity,
        layout.n_normal(),
        layout.n_friction(),
    );
    let (np, nv) = (layout.n_position(), layout.n_velocity());
    let law_off = layout.friction_offsets();
    let mut e = Evaluation::<f64>::new(layout);
    system.evaluate(t0, q0, u0, &mut e);
    let (mut r_pos, mut r_vel, mut r_law) = (Vec::new(), Vec::new(), Vec::new());
    prox_parameters(prox, layout, &e, &mut r_pos, &mut r_vel, &mut r_law);
    let mut rate = e.position_chi.clone();
    for &(r, c, v) in &e.position_w.entries {
        rate[c] += v * u0[r];
    }
    let mut slip = e.velocity_chi.clone();
    for &(r, c, v) in &e.velocity_w.entries {
        slip[c] += v * u0[r];
    }
    let closed: Vec<bool> = (0..nn)
        .map(|k| e.position[ng + k] <= tol && rate[ng + k] <= tol)
        .collect();
    // Unknowns y = (a, λ_g, λ_γ, λ_N, λ_F).
    let (oa, olg, olga, oln, olf) = (0, nu, nu + ng, nu + ng + nga, nu + ng + nga + nn);
    let n = olf + nf;
    let lam_col_p = |c: usize| if c < ng { olg + c } else { oln + c - ng };
    let lam_col_v = |c: usize| if c < nga { olga + c } else { olf + c - nga };
    let mut y = vec![0.0; n];
    let mut solver = AutoSolver::default();
    let mut jac: Vec<(usize, usize, f64)> = Vec::new();
    // Multiplier rows whose contact law is closed (sticking) at this iterate.
    let mut closed_rows: Vec<usize> = Vec::new();
    let mut res = vec![0.0; n];
    let scale = 1.0 + e.forces.iter().fold(0.0_f64, |m, h| m.max(h.abs()));
    for _ in 0..=max_iter {
        // Acceleration levels p̈ = W_pᵀa + ζ_p, v̇ = W_vᵀa + ζ_v.
        let mut acc_p = e.position_zeta.clone();
        for &(r, c, v) in &e.position_w.entries {
            acc_p[c] += v * y[oa + r];
        }
        let mut acc_v = e.velocity_zeta.clone();
        for &(r, c, v) in &e.velocity_w.entries {
            acc_v[c] += v * y[oa + r];
        }
        res.iter_mut().for_each(|x| *x = 0.0);
        jac.clear();
        closed_rows.clear();
        for &(i, j, m) in &e.mass.entries {
            res[oa + i] += m * y[oa + j];
            jac.push((oa + i, oa + j, m));
        }
        for i in 0..nu {
            res[oa + i] -= e.forces[i];
        }
        for &(i, c, v) in &e.position_w.entries {
            res[oa + i] -= v * y[lam_col_p(c)];
            jac.push((oa + i, lam_col_p(c), -v));
        }
        for &(i, c, v) in &e.velocity_w.entries {
            res[oa + i] -= v * y[lam_col_v(c)];
            jac.push((oa + i, lam_col_v(c), -v));
        }
        // Rows "r · level" with ∂/∂a = r Wᵀ.
        let push_level = |jac: &mut Vec<(usize, usize, f64)>,
                          w: &crate::system::Triplets<f64>,
                          c0: usize,
                          row: usize,
                          r: f64| {
            for &(i, c, v) in &w.entries {
                if c == c0 {
                    jac.push((row, oa + i, r * v));
                }
            }
        };
        for i in 0..ng {
            res[olg + i] = r_pos[i] * acc_p[i];
            push_level(&mut jac, &e.position_w, i, olg + i, r_pos[i]);
        }
        for i in 0..nga {
            res[olga + i] = r_vel[i] * acc_v[i];
            push_level(&mut jac, &e.velocity_w, i, olga + i, r_vel[i]);
        }
        for k in 0..nn {
            let pk = ng + k;
            let lam = y[oln + k];
            if closed[k] && r_pos[pk] * acc_p[pk] - lam <= 0.0 {
                res[oln + k] = r_pos[pk] * acc_p[pk];
                push_level(&mut jac, &e.position_w, pk, oln + k, r_pos[pk]);
                closed_rows.push(oln + k);
            } else {
                res[oln + k] = lam;
                jac.push((oln + k, oln + k, 1.0));
            }
        }
        for (j, law) in layout.friction.iter().enumerate() {
            let f0 = law_off[j];
            let nc = law.components;
            let vs = nga + f0;
            let active = law.normals.iter().any(|&k| closed[k]);
            let l_sum: f64 = law.normals.iter().map(|&k| y[oln + k]).sum();
            let radius = law.mu * l_sum.max(0.0);
            let sliding = norm(&slip[vs..vs + nc]) > tol;
            let stick = active && !sliding && {
                let d: f64 = (0..nc)
                    .map(|m| (r_law[j] * acc_v[vs + m] - y[olf + f0 + m]).powi(2))
                    .sum();
                d.sqrt() <= radius
            };
            let dir_src: &[f64] = if sliding {
                &slip[vs..vs + nc]
            } else {
                &acc_v[vs..vs + nc]
            };
            let dn = norm(dir_src);
            for m in 0..nc {
                let row = olf + f0 + m;
                if stick {
                    res[row] = r_law[j] * acc_v[vs + m];
                    push_level(&mut jac, &e.velocity_w, vs + m, row, r_law[j]);
                    closed_rows.push(row);
                    continue;
                }
                res[row] = y[row];
                jac.push((row, row, 1.0));
                if !active || dn == 0.0 || l_sum <= 0.0 {
                    continue;
                }
                let dm = dir_src[m] / dn;
                res[row] += radius * dm;
                for &k in &law.normals {
                    jac.push((row, oln + k, law.mu * dm));
                }
                if !sliding {
                    // ∂(γ̇/‖γ̇‖)/∂a through γ̇ = W_vᵀ a + ζ_v.
                    for mp in 0..nc {
                        let proj = f64::from(u8::from(m == mp)) - dm * dir_src[mp] / dn;
                        push_level(&mut jac, &e.velocity_w, vs + mp, row, radius * proj / dn);
                    }
                }
            }
        }
        let r = res.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        if !r.is_finite() {
            break;
        }
        if r <= 1e-12 * scale {
            let _ = (np, nv);
            return Ok(Start {
                a: y[oa..oa + nu].to_vec(),
                lambda_g: y[olg..olg + ng].to_vec(),
                lambda_gamma: y[olga..olga + nga].to_vec(),
                lambda_n: y[oln..oln + nn].to_vec(),
                lambda_f: y[olf..olf + nf].to_vec(),
            });
        }
        let mut dy: Vec<f64> = res.iter().map(|r| -r).collect();
        let mut solved = solver.solve(n, &jac, &mut dy);
        let eps = options.regularization;
        if solved.is_err() && eps > 0.0 {
            // Redundant closed contacts (see `Options::regularization`): ε on the
            // multiplier diagonal of every closed row.
            jac.extend(closed_rows.iter().map(|&r| (r, r, eps)));
            dy.iter_mut().zip(&res).for_each(|(d, r)| *d = -r);
            solved = solver.solve(n, &jac, &mut dy);
        }
        solved.map_err(|e| StepError::Start {
            t: t0,
            message: e.0,
        })?;
        for (yi, d) in y.iter_mut().zip(&dy) {
            *yi += d;
        }
    }
    Err(StepError::Start {
        t: t0,
        message: "semismooth Newton did not converge".into(),
    })
}
