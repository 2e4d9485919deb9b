//! One Moreau–Jean step whose contact problem is a linear complementarity problem solved
//! by Lemke's method ([`crate::lcp`]), which terminates (docs/method.md §6 and §8, step
//! 7). It serves the generalized-α stepper's last resort and the Moreau–Jean baseline
//! when its Newton iteration does not converge.
//!
//! The velocity-level problem, in the form of Anitescu and Potra (1997): with
//! ũ = u_n + Δt M⁻¹h at the midpoint q_M,
//!
//! u⁺ = ũ + M⁻¹(W_N P_N + W_F (β⁺ − β⁻)),
//! 0 ≤ P_N ⟂ ξ_N = W_Nᵀu⁺ + χ_N + e_N ġ_N(u_n) ≥ 0,
//! 0 ≤ β⁺ ⟂ λ + ξ_F ≥ 0,  0 ≤ β⁻ ⟂ λ − ξ_F ≥ 0,  0 ≤ λ ⟂ μ Σ P_N − β⁺ − β⁻ ≥ 0,
//!
//! with ξ_F = W_Fᵀu⁺ + χ_F + e_F γ_F(u_n): Coulomb's law of a planar contact exactly (λ
//! is the slip speed). Which contacts take part is the [`Activation`]. Then
//! q_{n+1} = q_M + ½Δt B u⁺, and, if asked, gaps that end below zero are closed by the
//! least M-norm displacement, itself an LCP: 0 ≤ δ ⟂ g + W_Nᵀ M⁻¹ W_N δ ≥ 0.

use crate::lcp::{lemke, lemke_regularized, LcpFailure};
use crate::linalg::max_norm;
use crate::moreau::advance;
use crate::system::{Evaluation, Layout, System};
use nalgebra::{DMatrix, DVector};

/// Largest complementarity residual (relative to 1 + ‖rhs‖∞, a speed) accepted from a
/// regularized solve of the step's contact problem (`nsga::lcp::lemke_regularized`): an
/// approach speed of that size moves a gap by Δt times as much in the step, and the
/// position projection removes it.
const ACCEPT: f64 = 1e-8;

/// Largest penetration left by the position projection.
const PROJECTION_TOL: f64 = 1e-12;

/// Which contacts take part in the step's contact problem.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Activation {
    /// Those closed at q_M (g_N ≤ 0), with the friction laws of a closed contact: the
    /// Moreau–Jean scheme of §6.
    ClosedAtMidpoint,
    /// Every contact; one still open at q_M has ξ_N = W_Nᵀu⁺ + χ_N + g_N/(½Δt), so that it
    /// is pushed only if its gap would close by the end of the step. (With the contacts
    /// closed at q_M only, a column resting on gaps of 1e-9 sinks by ½Δt‖u‖ in a step.)
    GapAware,
}

/// The outcome of one step.
#[derive(Debug, Clone)]
pub(crate) struct LcpStep {
    pub q: Vec<f64>,
    pub u: Vec<f64>,
    pub p_n: Vec<f64>,
    pub p_f: Vec<f64>,
    pub pivots: usize,
    pub residual: f64,
    /// Largest coordinate change of the projection (0: none needed or asked).
    pub projection: f64,
}

/// Why a step could not be taken.
#[derive(Debug, Clone)]
pub(crate) enum LcpStepError {
    /// The system has what this step does not cover (bilateral constraints, spatial
    /// friction).
    Unsupported(String),
    /// The contact problem has no solution (Lemke's method ended on a ray), or the data
    /// or the result are not finite.
    NoSolution(String),
}

/// The dense pieces of one evaluation the LCPs are built from.
struct Dense {
    m_inv: DMatrix<f64>,
    w_p: DMatrix<f64>,
    w_v: DMatrix<f64>,
}

impl Dense {
    /// M⁻¹ and the first `np` columns of W_p and `nv` of W_v (None: M is singular).
    fn of(eval: &Evaluation<f64>, nu: usize, np: usize, nv: usize) -> Option<Self> {
        let mut m = DMatrix::zeros(nu, nu);
        for &(i, j, v) in &eval.mass.entries {
            m[(i, j)] += v;
        }
        let mut w_p = DMatrix::zeros(nu, np);
        for &(i, c, v) in eval.position_w.entries.iter().filter(|e| e.1 < np) {
            w_p[(i, c)] += v;
        }
        let mut w_v = DMatrix::zeros(nu, nv);
        for &(i, c, v) in eval.velocity_w.entries.iter().filter(|e| e.1 < nv) {
            w_v[(i, c)] += v;
        }
        Some(Self {
            m_inv: m.try_inverse()?,
            w_p,
            w_v,
        })
    }
}

/// Whether [`lcp_step`] covers a system of this layout: planar friction laws and no
/// bilateral constraints.
pub(crate) fn covers(l: &Layout) -> Result<(), LcpStepError> {
    if l.n_bilateral_position + l.n_bilateral_velocity > 0
        || l.friction.iter().any(|f| f.components != 1)
    {
        return Err(LcpStepError::Unsupported(
            "the LCP step covers planar friction without bilateral constraints".into(),
        ));
    }
    Ok(())
}

/// The free acceleration M⁻¹h at (t, q, u), zero if M is singular.
pub(crate) fn free_acceleration<S: System>(
    system: &S,
    l: &Layout,
    t: f64,
    q: &[f64],
    u: &[f64],
) -> Vec<f64> {
    let mut eval = Evaluation::new(l);
    system.evaluate(t, q, u, &mut eval);
    Dense::of(&eval, l.nu, 0, 0).map_or_else(
        || vec![0.0; l.nu],
        |d| {
            (&d.m_inv * DVector::from_column_slice(&eval.forces))
                .iter()
                .copied()
                .collect()
        },
    )
}

/// One step from (t, q, u) to t + `dt` (`t1`, on the caller's grid).
pub(crate) fn lcp_step<S: System>(
    system: &S,
    l: &Layout,
    (t, t1): (f64, f64),
    (q, u): (&[f64], &[f64]),
    dt: f64,
    activation: Activation,
    project: bool,
) -> Result<LcpStep, LcpStepError> {
    covers(l)?;
    let (nu, nn, nf) = (l.nu, l.n_normal(), l.n_friction());
    let q_m = advance(system, t, q, u, 0.5 * dt);
    let t_m = t + 0.5 * dt;
    let mut eval = Evaluation::new(l);
    system.evaluate(t_m, &q_m, u, &mut eval);
    let no_solution = |m: &str| LcpStepError::NoSolution(m.to_owned());
    let d =
        Dense::of(&eval, nu, nn, nf).ok_or_else(|| no_solution("the mass matrix is singular"))?;
    let closed: Vec<usize> = match activation {
        Activation::GapAware => (0..nn).collect(),
        Activation::ClosedAtMidpoint => (0..nn).filter(|&k| eval.position[k] <= 0.0).collect(),
    };
    let active: Vec<usize> = (0..l.friction.len())
        .filter(|&j| l.friction[j].normals.iter().any(|k| closed.contains(k)))
        .collect();
    let u_n = DVector::from_column_slice(u);
    let u_free = &u_n + &d.m_inv * DVector::from_iterator(nu, eval.forces.iter().map(|h| h * dt));
    let xi_n = |k: usize, u: &DVector<f64>| d.w_p.column(k).dot(u) + eval.position_chi[k];
    let xi_f = |j: usize, u: &DVector<f64>| d.w_v.column(j).dot(u) + eval.velocity_chi[j];
    // Unknowns z = (P_N over `closed`, β⁺, β⁻, λ over `active`).
    let (a, b) = (closed.len(), active.len());
    let n = a + 3 * b;
    let cols: Vec<DVector<f64>> = closed
        .iter()
        .map(|&k| d.w_p.column(k).into_owned())
        .chain(active.iter().map(|&j| d.w_v.column(j).into_owned()))
        .collect();
    let g_cols: Vec<DVector<f64>> = cols.iter().map(|c| &d.m_inv * c).collect();
    let mut m = vec![0.0; n * n];
    let mut rhs = vec![0.0; n];
    // The velocity rows: ±(column r)ᵀ M⁻¹ times the percussions, β⁺ − β⁻ for friction.
    for (r, col_r) in cols.iter().enumerate() {
        let rows: Vec<(usize, f64)> = if r < a {
            vec![(r, 1.0)]
        } else {
            vec![(r, 1.0), (r + b, -1.0)]
        };
        for (row, sign) in rows {
            for (c, g_c) in g_cols.iter().enumerate() {
                let v = sign * col_r.dot(g_c);
                m[row * n + c] = v;
                if c >= a {
                    m[row * n + c + b] = -v;
                }
            }
        }
    }
    for (i, &k) in closed.iter().enumerate() {
        let g = eval.position[k];
        rhs[i] = xi_n(k, &u_free)
            + if g <= 0.0 {
                l.e_n[k] * xi_n(k, &u_n)
            } else {
                g / (0.5 * dt)
            };
    }
    for (i, &j) in active.iter().enumerate() {
        let c = xi_f(j, &u_free) + l.friction[j].e_f * xi_f(j, &u_n);
        rhs[a + i] = c;
        rhs[a + b + i] = -c;
        // λ enters both slip rows; the friction bound row closes the system.
        m[(a + i) * n + a + 2 * b + i] = 1.0;
        m[(a + b + i) * n + a + 2 * b + i] = 1.0;
        let row = a + 2 * b + i;
        for &k in &l.friction[j].normals {
            if let Some(p) = closed.iter().position(|&c| c == k) {
                m[row * n + p] = l.friction[j].mu;
            }
        }
        m[row * n + a + i] = -1.0;
        m[row * n + a + b + i] = -1.0;
    }
    let accept = ACCEPT * (1.0 + max_norm(&rhs));
    let (sol, _) = lemke_regularized(&m, &rhs, 50 * n + 50, accept).map_err(|e| match e {
        LcpFailure::Ray { .. } => LcpStepError::NoSolution(format!(
            "the step's contact problem has no solution: {e} (a Painlevé-type inconsistency)"
        )),
        e => LcpStepError::NoSolution(e.to_string()),
    })?;
    let mut u1 = u_free;
    let mut p_n = vec![0.0; nn];
    let mut p_f = vec![0.0; nf];
    for (i, &k) in closed.iter().enumerate() {
        p_n[k] = sol.z[i];
        u1 += &g_cols[i] * sol.z[i];
    }
    for (i, &j) in active.iter().enumerate() {
        p_f[j] = sol.z[a + i] - sol.z[a + b + i];
        u1 += &g_cols[a + i] * p_f[j];
    }
    let u1: Vec<f64> = u1.iter().copied().collect();
    let mut q1 = advance(system, t_m, &q_m, &u1, 0.5 * dt);
    let projection = if project {
        project_onto_gaps(system, l, t1, &mut q1, &u1)
    } else {
        0.0
    };
    if q1.iter().chain(&u1).any(|x| !x.is_finite()) {
        return Err(no_solution("the LCP step gave a non-finite state"));
    }
    Ok(LcpStep {
        q: q1,
        u: u1,
        p_n,
        p_f,
        pivots: sol.pivots,
        residual: sol.residual,
        projection,
    })
}

/// Moves `q` by the least M-norm displacement that closes every negative gap (to
/// round-off, five linearizations at most); returns the size of the displacement in the
/// coordinates (∞-norm).
fn project_onto_gaps<S: System>(
    system: &S,
    l: &Layout,
    t: f64,
    q: &mut Vec<f64>,
    u: &[f64],
) -> f64 {
    let (nu, nn) = (l.nu, l.n_normal());
    let mut moved = 0.0_f64;
    for _ in 0..5 {
        let mut eval = Evaluation::new(l);
        system.evaluate(t, q, u, &mut eval);
        if (0..nn).all(|k| eval.position[k] >= -PROJECTION_TOL) {
            break;
        }
        let Some(d) = Dense::of(&eval, nu, nn, 0) else {
            break;
        };
        // All contacts: closing one gap must not open another below zero.
        let g_cols: Vec<DVector<f64>> = (0..nn).map(|k| &d.m_inv * d.w_p.column(k)).collect();
        let mut m = vec![0.0; nn * nn];
        for r in 0..nn {
            for (c, g_c) in g_cols.iter().enumerate() {
                m[r * nn + c] = d.w_p.column(r).dot(g_c);
            }
        }
        let Ok(sol) = lemke(&m, &eval.position[..nn], 50 * nn + 50) else {
            break;
        };
        let mut du = vec![0.0; nu];
        for (g_c, delta) in g_cols.iter().zip(&sol.z) {
            for (x, y) in du.iter_mut().zip(g_c.iter()) {
                *x += y * delta;
            }
        }
        let before = q.clone();
        *q = advance(system, t, q, &du, 1.0);
        moved = q
            .iter()
            .zip(&before)
            .map(|(a, b)| (a - b).abs())
            .fold(moved, f64::max);
    }
    moved
}
