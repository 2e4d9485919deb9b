//! The twelve Euler-angle sets, their Euler basis and dual basis, and angular velocity
//! (Honein 2024, App. A and (2.5.1)–(2.5.6)).
//!
//! Convention: the set i-j-k with angles (a1, a2, a3) rotates first by a1 about Eᵢ, then
//! by a2 about the once-rotated j-axis, then by a3 about the twice-rotated k-axis. As a
//! product of rotations about the fixed basis this is
//! R = R(a1, Eᵢ) R(a2, Eⱼ) R(a3, Eₖ), and R = Σ eₘ ⊗ Eₘ. For 3-1-3 with (ψ, ϑ, φ) this
//! is (A.1.1)–(A.1.3).

use crate::RotationError;
use nalgebra::{Matrix3, Rotation3, Vector3};
use serde::{Deserialize, Serialize};
use std::fmt;
use std::str::FromStr;

/// Whether the first and third axes of a set coincide.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum EulerKind {
    /// i-j-i (for example 3-1-3): a2 ∈ [0, π], singular at a2 = 0 and π.
    Symmetric,
    /// i-j-k all different (for example 3-2-1): a2 ∈ [−π/2, π/2], singular at ±π/2.
    Asymmetric,
}

/// One of the twelve Euler-angle sets, named like `3-1-3` (axes numbered 1, 2, 3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub struct EulerSet {
    /// The three axes, 0-based.
    axes: [usize; 3],
}

/// Below this value of cos a2 (asymmetric) or sin a2 (symmetric) the first angle is not
/// determined by the rotation and is set to 0.
const SINGULAR: f64 = 1e-14;

impl EulerSet {
    /// All twelve sets: the six symmetric ones, then the six asymmetric ones.
    pub const ALL: [EulerSet; 12] = [
        Self::at(3, 1, 3),
        Self::at(3, 2, 3),
        Self::at(1, 2, 1),
        Self::at(1, 3, 1),
        Self::at(2, 1, 2),
        Self::at(2, 3, 2),
        Self::at(3, 2, 1),
        Self::at(3, 1, 2),
        Self::at(1, 2, 3),
        Self::at(1, 3, 2),
        Self::at(2, 1, 3),
        Self::at(2, 3, 1),
    ];

    const fn at(i: usize, j: usize, k: usize) -> Self {
        Self {
            axes: [i - 1, j - 1, k - 1],
        }
    }

    /// The set with axes i-j-k, numbered 1..=3.
    ///
    /// # Errors
    /// [`RotationError::UnknownEulerSet`] unless i ≠ j, j ≠ k and all are in 1..=3.
    pub fn new(i: usize, j: usize, k: usize) -> Result<Self, RotationError> {
        let valid = (1..=3).contains(&i)
            && (1..=3).contains(&j)
            && (1..=3).contains(&k)
            && i != j
            && j != k;
        if valid {
            Ok(Self::at(i, j, k))
        } else {
            Err(RotationError::UnknownEulerSet(format!("{i}-{j}-{k}")))
        }
    }

    /// Parses `3-1-3`, `313` or `3,1,3`.
    ///
    /// # Errors
    /// [`RotationError::UnknownEulerSet`] for anything else.
    pub fn from_name(name: &str) -> Result<Self, RotationError> {
        let digits: Vec<usize> = name
            .chars()
            .filter(|c| !matches!(c, '-' | ',' | ' '))
            .map(|c| c.to_digit(10).map(|d| d as usize))
            .collect::<Option<_>>()
            .ok_or_else(|| RotationError::UnknownEulerSet(name.to_owned()))?;
        match digits.as_slice() {
            [i, j, k] => {
                Self::new(*i, *j, *k).map_err(|_| RotationError::UnknownEulerSet(name.to_owned()))
            }
            _ => Err(RotationError::UnknownEulerSet(name.to_owned())),
        }
    }

    /// The axes, numbered 1..=3.
    #[must_use]
    pub fn axes(&self) -> [usize; 3] {
        self.axes.map(|a| a + 1)
    }

    /// Symmetric (i-j-i) or asymmetric (i-j-k).
    #[must_use]
    pub fn kind(&self) -> EulerKind {
        if self.axes[0] == self.axes[2] {
            EulerKind::Symmetric
        } else {
            EulerKind::Asymmetric
        }
    }

    /// The range of the second angle returned by [`EulerSet::angles`].
    #[must_use]
    pub fn second_angle_range(&self) -> (f64, f64) {
        use std::f64::consts::{FRAC_PI_2, PI};
        match self.kind() {
            EulerKind::Symmetric => (0.0, PI),
            EulerKind::Asymmetric => (-FRAC_PI_2, FRAC_PI_2),
        }
    }

    /// The rotation R = R(a1, Eᵢ) R(a2, Eⱼ) R(a3, Eₖ).
    #[must_use]
    pub fn rotation(&self, angles: [f64; 3]) -> Rotation3<f64> {
        let [i, j, k] = self.axes;
        Rotation3::from_matrix_unchecked(
            elementary(i, angles[0]) * elementary(j, angles[1]) * elementary(k, angles[2]),
        )
    }

    /// The Euler angles of a rotation: a1, a3 ∈ (−π, π], a2 in
    /// [`EulerSet::second_angle_range`].
    ///
    /// a1 and a2 are read from the column R Eₖ (spherical coordinates of e_k, which
    /// they reproduce exactly), and a3 from the remaining rotation
    /// R(a2, Eⱼ)ᵀ R(a1, Eᵢ)ᵀ R about Eₖ, so the composed rotation reproduces R to
    /// round-off even next to a singularity.
    ///
    /// **Singular values of the second angle** (a2 = 0 or π for symmetric sets, ±π/2 for
    /// asymmetric ones): only a1 ± a3 is determined. rollstack then sets **a1 = 0** and
    /// gives the whole rotation about the common axis to a3; the angles are finite and
    /// [`EulerSet::rotation`] of them is still R.
    #[must_use]
    pub fn angles(&self, rotation: &Rotation3<f64>) -> [f64; 3] {
        let m = rotation.matrix();
        let [i, j, k] = self.axes;
        let (a1, a2) = match self.kind() {
            EulerKind::Symmetric => {
                // Column i: cos a2 Eᵢ + sin a2 sin a1 Eⱼ − ε sin a2 cos a1 Eₗ (l the third axis).
                let l = 3 - i - j;
                let eps = levi_civita(i, j, l);
                let (rji, rli) = (m[(j, i)], m[(l, i)]);
                let s2 = rji.hypot(rli);
                let a1 = if s2 < SINGULAR {
                    0.0
                } else {
                    rji.atan2(-eps * rli)
                };
                (a1, s2.atan2(m[(i, i)]))
            }
            EulerKind::Asymmetric => {
                // Column k: ε sin a2 Eᵢ − ε cos a2 sin a1 Eⱼ + cos a2 cos a1 Eₖ.
                let eps = levi_civita(i, j, k);
                let (rjk, rkk) = (m[(j, k)], m[(k, k)]);
                let c2 = rjk.hypot(rkk);
                let a1 = if c2 < SINGULAR {
                    0.0
                } else {
                    (-eps * rjk).atan2(rkk)
                };
                (a1, (eps * m[(i, k)]).atan2(c2))
            }
        };
        let rest: Matrix3<f64> = elementary(j, a2).transpose() * elementary(i, a1).transpose() * m;
        let (k1, k2) = ((k + 1) % 3, (k + 2) % 3);
        let a3 = rest[(k2, k1)].atan2(rest[(k1, k1)]);
        [a1, a2, a3]
    }

    /// Whether the angles sit at a singular value of the second angle, where the Euler
    /// basis is not a basis (its determinant is below `tolerance` in magnitude).
    #[must_use]
    pub fn is_singular(&self, angles: [f64; 3], tolerance: f64) -> bool {
        self.basis_determinant(angles).abs() <= tolerance
    }

    /// The Euler basis {g1, g2, g3}: the axes of the three successive rotations,
    /// (A.1.4): g1 = Eᵢ, g2 = R(a1, Eᵢ) Eⱼ, g3 = R(a1, Eᵢ) R(a2, Eⱼ) Eₖ = R Eₖ.
    #[must_use]
    pub fn basis(&self, angles: [f64; 3]) -> [Vector3<f64>; 3] {
        let [i, j, k] = self.axes;
        let r1 = elementary(i, angles[0]);
        let r12 = r1 * elementary(j, angles[1]);
        [unit(i), r1 * unit(j), r12 * unit(k)]
    }

    /// g1 · (g2 × g3): ±cos a2 for asymmetric sets, ±sin a2 for symmetric ones.
    #[must_use]
    pub fn basis_determinant(&self, angles: [f64; 3]) -> f64 {
        let [g1, g2, g3] = self.basis(angles);
        g1.dot(&g2.cross(&g3))
    }

    /// The dual Euler basis {g¹, g², g³} with gₖ · gⁱ = δₖⁱ, (A.2.2); `None` at the
    /// singular values of the second angle (|g1 · (g2 × g3)| < 1e-12).
    #[must_use]
    pub fn dual_basis(&self, angles: [f64; 3]) -> Option<[Vector3<f64>; 3]> {
        let [g1, g2, g3] = self.basis(angles);
        let det = g1.dot(&g2.cross(&g3));
        if det.abs() < 1e-12 {
            return None;
        }
        Some([
            g2.cross(&g3) / det,
            g3.cross(&g1) / det,
            g1.cross(&g2) / det,
        ])
    }

    /// ω = ȧ1 g1 + ȧ2 g2 + ȧ3 g3, (A.2.1), components on E1, E2, E3.
    #[must_use]
    pub fn angular_velocity(&self, angles: [f64; 3], rates: [f64; 3]) -> Vector3<f64> {
        let [g1, g2, g3] = self.basis(angles);
        rates[0] * g1 + rates[1] * g2 + rates[2] * g3
    }

    /// The angle rates ȧᵢ = ω · gⁱ (A.2.2); `None` at a singular value of the second angle.
    #[must_use]
    pub fn angle_rates(&self, angles: [f64; 3], omega: &Vector3<f64>) -> Option<[f64; 3]> {
        self.dual_basis(angles).map(|d| d.map(|g| omega.dot(&g)))
    }
}

impl fmt::Display for EulerSet {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [i, j, k] = self.axes();
        write!(f, "{i}-{j}-{k}")
    }
}

impl FromStr for EulerSet {
    type Err = RotationError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::from_name(s)
    }
}

/// The basis vector E_{axis+1}.
fn unit(axis: usize) -> Vector3<f64> {
    let mut v = Vector3::zeros();
    v[axis] = 1.0;
    v
}

/// R(angle, E_{axis+1}) as a matrix.
fn elementary(axis: usize, angle: f64) -> Matrix3<f64> {
    let (s, c) = angle.sin_cos();
    let (a, b) = ((axis + 1) % 3, (axis + 2) % 3);
    let mut m = Matrix3::zeros();
    m[(axis, axis)] = 1.0;
    m[(a, a)] = c;
    m[(b, b)] = c;
    m[(b, a)] = s;
    m[(a, b)] = -s;
    m
}

/// ε_{ijk} for distinct 0-based indices: +1 when cyclic, −1 otherwise.
fn levi_civita(i: usize, j: usize, k: usize) -> f64 {
    if (j + 3 - i) % 3 == 1 && (k + 3 - j) % 3 == 1 {
        1.0
    } else {
        debug_assert!(i != j && j != k && i != k);
        -1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rotation_from_axis_angle;

    #[test]
    fn names() {
        assert_eq!(EulerSet::ALL.len(), 12);
        for set in EulerSet::ALL {
            assert_eq!(EulerSet::from_name(&set.to_string()).unwrap(), set);
        }
        assert_eq!(EulerSet::from_name("313").unwrap().to_string(), "3-1-3");
        for bad in ["3-3-1", "1-1-1", "4-1-2", "3-1", "x-y-z", "", "3-1-3-1"] {
            assert!(EulerSet::from_name(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn elementary_is_axis_angle() {
        for axis in 0..3 {
            let r = rotation_from_axis_angle(0.7, &unit(axis)).unwrap();
            assert!((r.matrix() - elementary(axis, 0.7)).norm() < 1e-15);
        }
    }

    #[test]
    fn thesis_313_basis() {
        // (A.1.1)-(A.1.4): g1 = E3, g2 = e'1 = cos ψ E1 + sin ψ E2, g3 = e3.
        let (psi, theta, phi) = (0.4, 1.1, -0.8);
        let set = EulerSet::from_name("3-1-3").unwrap();
        let [g1, g2, g3] = set.basis([psi, theta, phi]);
        let q = set.rotation([psi, theta, phi]);
        assert!((g1 - Vector3::z()).norm() < 1e-15);
        assert!((g2 - Vector3::new(psi.cos(), psi.sin(), 0.0)).norm() < 1e-15);
        assert!((g3 - q * Vector3::z()).norm() < 1e-15);
        // e3 = sin ϑ sin ψ E1 − sin ϑ cos ψ E2 + cos ϑ E3.
        let e3 = Vector3::new(
            theta.sin() * psi.sin(),
            -theta.sin() * psi.cos(),
            theta.cos(),
        );
        assert!((g3 - e3).norm() < 1e-15);
        // (A.2.1) in the e basis.
        let (pd, td, fd) = (0.3, -0.2, 1.5);
        let w = set.angular_velocity([psi, theta, phi], [pd, td, fd]);
        let wb = q.transpose() * w;
        let expect = Vector3::new(
            td * phi.cos() + pd * theta.sin() * phi.sin(),
            -td * phi.sin() + pd * theta.sin() * phi.cos(),
            fd + pd * theta.cos(),
        );
        assert!((wb - expect).norm() < 1e-14);
    }

    #[test]
    fn levi() {
        assert_eq!(levi_civita(0, 1, 2), 1.0);
        assert_eq!(levi_civita(2, 0, 1), 1.0);
        assert_eq!(levi_civita(2, 1, 0), -1.0);
        assert_eq!(levi_civita(0, 2, 1), -1.0);
    }
}
