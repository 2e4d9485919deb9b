//! The root-finding route of App. C, kept as an independent check of [`crate::planner`].
//!
//! For a quaternion (a, q) of the target (a = q0; both signs are tried, and the
//! conjugate for clockwise travel), (C.2.3) gives a = q0, b = q2, c = q1² + q3², and
//! (C.2.4)–(C.2.5) is the single equation
//!
//! g±(φ2) = 1 ± √(1 − c / sin²(φ2/2)) + 2b cot φ2 − 2a = 0
//!
//! on the admissible set (C.2.7): φ2 ≠ nπ and sin²(φ2/2) ≥ c. Every root on (0, 3π) is
//! bracketed by sampling both branches on each admissible interval, refined by Brent's
//! method, and kept only if the residual is small (sign changes across the poles of
//! cot φ2 are rejected). The end points of the admissible intervals, where the two
//! branches meet, are tested directly. The cases φ2 = (2n − 1)π of C.1 (b = 0) are
//! handled separately: there (C.2.2)₁ gives ϑ directly. Then ϑ follows from (C.2.8)
//! (both ±arccos), φ1 from (C.2.1) modulo π, and every candidate is verified by the
//! forward product (2.4.2) against the target; duplicates are merged.
//!
//! The result is the same set as [`crate::plan_rectangles`] (tested), at a much higher
//! cost: use the closed-form planner in practice.

use crate::planner::PlannedRectangle;
use crate::rectangle::{rectangle_holonomy, Direction, Rectangle};
use crate::HolonomyError;
use nalgebra::Rotation3;
use rotations::{quaternion_from_matrix, rotation_distance};
use std::f64::consts::{PI, TAU};

/// Samples per admissible interval when bracketing roots of (C.2.4).
const SAMPLES: usize = 4000;
/// Largest |g| accepted at a refined root, and largest error of a verified rectangle.
const RESIDUAL: f64 = 1e-8;
const VERIFY: f64 = 1e-9;

/// Every rectangle with φ2 ∈ (0, 3π] producing `target`, by the root finding of App. C.
///
/// # Errors
/// As [`crate::plan_rectangles`].
pub fn plan_by_root_finding(
    target: &Rotation3<f64>,
) -> Result<Vec<PlannedRectangle>, HolonomyError> {
    if !target.matrix().iter().all(|v| v.is_finite()) {
        return Err(HolonomyError::Input(input::InputError::NonFinite(
            "target rotation".into(),
        )));
    }
    let q = quaternion_from_matrix(target.matrix());
    if q.vector().norm() == 0.0 {
        return Err(HolonomyError::IdentityTarget);
    }
    let mut out: Vec<PlannedRectangle> = Vec::new();
    for direction in [Direction::Ccw, Direction::Cw] {
        let qd = if direction == Direction::Ccw {
            q
        } else {
            q.conjugate()
        };
        for sign in [1.0, -1.0] {
            let (a, s1, b, s3) = (sign * qd.w, sign * qd.i, sign * qd.j, sign * qd.k);
            let c = s1 * s1 + s3 * s3;
            for phi2 in roots_c24(a, b, c) {
                for theta in thetas_c28(a, phi2) {
                    for phi1 in phi1_candidates(s1, s3, phi2) {
                        let Ok(rect) = Rectangle::new(theta, phi1, phi2, direction) else {
                            continue;
                        };
                        let error = rotation_distance(target, &rectangle_holonomy(&rect));
                        let duplicate = out.iter().any(|p| {
                            p.rectangle.direction == direction
                                && (p.rectangle.theta - theta).abs() < 1e-7
                                && (p.rectangle.phi1 - phi1).abs() < 1e-7
                                && (p.rectangle.phi2 - phi2).abs() < 1e-7
                        });
                        if error < VERIFY && !duplicate {
                            out.push(PlannedRectangle {
                                rectangle: rect,
                                error,
                                phi1_free: false,
                            });
                        }
                    }
                }
            }
        }
    }
    Ok(out)
}

/// g±(φ2) of (C.2.4)–(C.2.5), or `None` outside the domain (C.2.6).
fn g(phi2: f64, branch: f64, a: f64, b: f64, c: f64) -> Option<f64> {
    let s2 = (0.5 * phi2).sin().powi(2);
    let sin_phi2 = phi2.sin();
    if s2 == 0.0 || sin_phi2 == 0.0 {
        return None;
    }
    let radicand = 1.0 - c / s2;
    (radicand >= -1e-15).then(|| {
        1.0 + branch * radicand.max(0.0).sqrt() + 2.0 * b * phi2.cos() / sin_phi2 - 2.0 * a
    })
}

/// All roots φ2 ∈ (0, 3π] of (C.2.4), both branches, plus the C.1 cases φ2 = π, 3π.
fn roots_c24(a: f64, b: f64, c: f64) -> Vec<f64> {
    let mut roots = Vec::new();
    // C.1: φ2 = (2n − 1)π needs b = 0 ((C.2.2)₂); ϑ then follows from (C.2.2)₁.
    if b.abs() < 1e-14 {
        roots.extend([PI, 3.0 * PI]);
    }
    // The admissible intervals (C.2.7), extended to (0, 3π].
    let edge = 2.0 * c.sqrt().min(1.0).asin();
    let intervals = [(edge, PI), (PI, TAU - edge), (TAU + edge, 3.0 * PI)];
    for (lo, hi) in intervals {
        if hi <= lo {
            continue;
        }
        for branch in [1.0, -1.0] {
            let f = |x: f64| g(x, branch, a, b, c);
            // End points where the branches meet (the square root vanishes).
            for end in [lo, hi] {
                if f(end).is_some_and(|v| v.abs() < RESIDUAL) {
                    roots.push(end);
                }
            }
            let mut prev: Option<(f64, f64)> = None;
            for i in 0..=SAMPLES {
                #[allow(clippy::cast_precision_loss)]
                let x = lo + (hi - lo) * (i as f64) / (SAMPLES as f64);
                let Some(v) = f(x) else {
                    prev = None;
                    continue;
                };
                if v == 0.0 {
                    roots.push(x);
                } else if let Some((xp, vp)) = prev {
                    if vp * v < 0.0 {
                        if let Some(r) = brent(&|t| f(t).unwrap_or(f64::NAN), xp, x, vp, v) {
                            if f(r).is_some_and(|fr| fr.abs() < RESIDUAL) {
                                roots.push(r);
                            }
                        }
                    }
                }
                prev = Some((x, v));
            }
        }
    }
    roots.sort_by(f64::total_cmp);
    roots.dedup_by(|x, y| (*x - *y).abs() < 1e-10);
    roots
}

/// ϑ from (C.2.8) (or (C.2.2)₁ at φ2 = nπ), both ±arccos, in [0, 2π).
fn thetas_c28(a: f64, phi2: f64) -> Vec<f64> {
    let cphi = phi2.cos();
    if (1.0 - cphi).abs() < 1e-15 {
        return Vec::new();
    }
    let cos_theta = (2.0 * a - 1.0 - cphi) / (1.0 - cphi);
    if !(-1.0 - 1e-12..=1.0 + 1e-12).contains(&cos_theta) {
        return Vec::new(); // not a real ϑ: disregarded, as App. C says
    }
    let t = cos_theta.clamp(-1.0, 1.0).acos();
    vec![t, TAU - t]
}

/// φ1 from (C.2.1): tan φ1 = tan(φ2/2 − atan(s1/s3)), all values modulo π in
/// [φ2 − 2π, φ2] ∩ [0, φ2] (the forward check then keeps the right ones).
fn phi1_candidates(s1: f64, s3: f64, phi2: f64) -> Vec<f64> {
    // atan2 form of (C.2.1), also valid when s·A3 = 0.
    let base = 0.5 * phi2 - s1.atan2(s3);
    let mut out = Vec::new();
    for k in -4..=4 {
        let v = base + f64::from(k) * PI;
        if v >= (phi2 - TAU).max(0.0) - 1e-12 && v <= phi2 + 1e-12 {
            out.push(v.clamp(0.0, phi2));
        }
    }
    out
}

/// Brent's method on [x0, x1] with f(x0) = f0, f(x1) = f1 of opposite signs.
fn brent(f: &dyn Fn(f64) -> f64, x0: f64, x1: f64, f0: f64, f1: f64) -> Option<f64> {
    let (mut a, mut b, mut fa, mut fb) = (x0, x1, f0, f1);
    if fa * fb > 0.0 {
        return None;
    }
    if fa.abs() < fb.abs() {
        std::mem::swap(&mut a, &mut b);
        std::mem::swap(&mut fa, &mut fb);
    }
    let (mut c, mut fc, mut d) = (a, fa, b - a);
    let mut bisected = true;
    for _ in 0..200 {
        if fb == 0.0 || (b - a).abs() < 4.0 * f64::EPSILON * b.abs().max(1.0) {
            return Some(b);
        }
        let mut s = if fa != fc && fb != fc {
            // Inverse quadratic interpolation.
            a * fb * fc / ((fa - fb) * (fa - fc))
                + b * fa * fc / ((fb - fa) * (fb - fc))
                + c * fa * fb / ((fc - fa) * (fc - fb))
        } else {
            b - fb * (b - a) / (fb - fa) // secant
        };
        let lo = (3.0 * a + b) / 4.0;
        let between = if lo < b {
            (lo..=b).contains(&s)
        } else {
            (b..=lo).contains(&s)
        };
        let slow = if bisected {
            (s - b).abs() >= 0.5 * (b - c).abs()
        } else {
            (s - b).abs() >= 0.5 * (c - d).abs()
        };
        if !between || slow || !s.is_finite() {
            s = 0.5 * (a + b);
            bisected = true;
        } else {
            bisected = false;
        }
        let fs = f(s);
        if !fs.is_finite() {
            return None;
        }
        d = c;
        c = b;
        fc = fb;
        if fa * fs < 0.0 {
            b = s;
            fb = fs;
        } else {
            a = s;
            fa = fs;
        }
        if fa.abs() < fb.abs() {
            std::mem::swap(&mut a, &mut b);
            std::mem::swap(&mut fa, &mut fb);
        }
    }
    Some(b)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn brent_finds_a_cubic_root() {
        let f = |x: f64| x * x * x - 2.0;
        let r = brent(&f, 0.0, 2.0, f(0.0), f(2.0)).unwrap();
        assert!((r - 2f64.cbrt()).abs() < 1e-14);
    }
}
