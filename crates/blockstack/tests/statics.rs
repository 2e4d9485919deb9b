//! Statics of the Leaning Tower of Lire with the App. G force directions: the equilibrium
//! h + W_N λ_N + W_F λ_F = 0 of the resting tower, solved for the 8 normal and 4 friction
//! forces of the four interfaces (12 equations, 12 unknowns). §4.3: "the normal force
//! exerted on the kth block by the blocks beneath it is at the outer edge of the k−1th
//! block" — the whole weight above each interface sits on its right (outer) gap.

use blockstack::scenarios::{lire, Perturbation};
use nalgebra::{DMatrix, DVector};

/// The 12 interface forces (left, right normal per interface, then 4 frictions).
fn equilibrium_forces(perturbation: Perturbation) -> Vec<f64> {
    let scene = lire(4, perturbation).unwrap();
    let q = scene.initial_coordinates();
    let u = vec![0.0; q.len()];
    let c = scene.contacts(0.0, &q, &u);
    let mut a = DMatrix::<f64>::zeros(12, 12);
    let rows = c.normals[..8]
        .iter()
        .map(|r| r.expect("supported"))
        .chain(c.slips[..4].iter().copied());
    for (col, row) in rows.enumerate() {
        for (i, w) in row.w.iter() {
            a[(i, col)] += w;
        }
    }
    let h = DVector::from_vec(scene.gravity_forces());
    a.lu()
        .solve(&(-h))
        .expect("the resting tower is statically determinate")
        .as_slice()
        .to_vec()
}

#[test]
fn the_weight_above_each_interface_sits_on_its_outer_edge() {
    let f = equilibrium_forces(Perturbation::None);
    for k in 0..4 {
        let (left, right) = (f[2 * k], f[2 * k + 1]);
        assert!(left.abs() < 1e-12, "interface {k}: left normal {left}");
        // m = g = 1: the blocks above interface k weigh 4 − k.
        assert!(
            (right - (4 - k) as f64).abs() < 1e-12,
            "interface {k}: right normal {right}"
        );
        assert!(
            f[8 + k].abs() < 1e-12,
            "interface {k}: friction {}",
            f[8 + k]
        );
    }
}

#[test]
fn perturbed_towers_cannot_rest() {
    // Top block pushed out by 1 %: its centre of mass is beyond the edge below; holding
    // it would need a pulling (negative) normal force at the inner edge.
    let f = equilibrium_forces(Perturbation::Top);
    assert!(f[6] < -1e-3, "top interface, inner normal {}", f[6]);
    // Lowest block pushed out by 1 %: the centre of mass of the whole column is beyond
    // the table's edge (negative inner force on the table), while the blocks above rest
    // on block 1 with margin and the upper two interfaces are as before.
    let f = equilibrium_forces(Perturbation::Bottom);
    assert!(f[0] < -1e-3, "table interface, inner normal {}", f[0]);
    assert!(f[2] > 1e-3, "interface 1, inner normal {}", f[2]);
    assert!(f[4].abs() < 1e-12 && f[6].abs() < 1e-12);
}
