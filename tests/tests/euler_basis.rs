//! The 3-1-3 parameterisation of App. A, written out component by component from
//! (A.1.1)–(A.1.3), against the generic Euler-set code of the rotations crate.

use nalgebra::Vector3;
use rotations::EulerSet;

#[test]
fn three_one_three_matches_appendix_a() {
    let set = EulerSet::from_name("3-1-3").unwrap();
    for &(psi, theta, phi) in &[(0.3, 0.9, -1.4), (-2.0, 2.5, 0.1), (1.0, 0.01, 3.0)] {
        let (sp, cp) = f64::sin_cos(psi);
        let (st, ct) = f64::sin_cos(theta);
        let (sf, cf) = f64::sin_cos(phi);
        // (A.1.1)
        let e1p = Vector3::new(cp, sp, 0.0);
        let e2p = Vector3::new(-sp, cp, 0.0);
        let e3p = Vector3::z();
        // (A.1.2)
        let e2pp = ct * e2p + st * e3p;
        let e3pp = -st * e2p + ct * e3p;
        // (A.1.3)
        let e1 = cf * e1p + sf * e2pp;
        let e2 = -sf * e1p + cf * e2pp;
        let e3 = e3pp;
        let q = set.rotation([psi, theta, phi]);
        // Q = Σ eᵢ ⊗ Eᵢ: column i of Q is eᵢ.
        for (i, e) in [e1, e2, e3].iter().enumerate() {
            assert!((q.matrix().column(i) - e).norm() < 1e-15);
        }
        // (A.1.4): g1 = E3, g2 = e'1, g3 = e3.
        let g = set.basis([psi, theta, phi]);
        assert!((g[0] - Vector3::z()).norm() < 1e-15);
        assert!((g[1] - e1p).norm() < 1e-15);
        assert!((g[2] - e3).norm() < 1e-15);
    }
}
