//! Painlevé's indeterminacy (App. I) found whole: in every case of the corner scan
//! (`examples/painleve_forks.rs`) with B < 0 and A > 0, at μ = 2 and μ = 1.4 and either
//! sign of the spin, the first step's solutions are sliding contact (n ≈ −A/B), jam and
//! lift-off, told apart by their contact states.

use blockstack::studies::painleve::{corner_scan, CornerCase, CornerMotion};

/// The point-contact cases of the scan at `mu` with B < 0: θ = 0 is left out, where both
/// bottom corners touch (line contact, §I.2, a unique solution).
fn point_contact_paradoxes(mu: f64) -> Vec<CornerCase> {
    corner_scan(mu)
        .unwrap()
        .into_iter()
        .filter(|c| c.case.theta != 0.0 && c.b < 0.0)
        .collect()
}

/// Over one step (Δt = 10⁻³) A and B drift with θ and θ̇, by an amount whose sign follows
/// the spin: the step's mean normal force P_N/Δt meets −A/B (taken at the step's start)
/// within this relative tolerance where |B| ≥ [`B_CLEAR`] (within 9.6 % at μ = 2).
const FORCE_TOLERANCE: f64 = 0.1;
/// The least |B| at which the force is compared: nearer b = 0, −A/B is steep in θ.
const B_CLEAR: f64 = 0.13;
/// The least |B| at which the sliding contact must be found: at μ = 1.4, θ = ±0.1 has
/// B = −0.017 and −A/B = 30, and one spin sign's step leaves b ≤ 0 within it.
const B_FOUND: f64 = 0.02;

fn all_three_in_every_case(mu: f64, expected_cases: usize) {
    let cases = point_contact_paradoxes(mu);
    assert_eq!(cases.len(), expected_cases, "μ = {mu}");
    for c in &cases {
        let (case, sols) = (&c.case, &c.solutions);
        let find = |m: CornerMotion| c.find(m);
        let what = format!(
            "μ = {mu}, θ = {:.2}, slip {}, spin {}: {sols:?}",
            case.theta, case.slip, case.spin_sign
        );
        let lift = find(CornerMotion::LiftOff).unwrap_or_else(|| panic!("no lift-off: {what}"));
        assert_eq!(lift.impulse, 0.0, "{what}");
        let jam = find(CornerMotion::Jam).unwrap_or_else(|| panic!("no jam: {what}"));
        // The jam stops a slip of 0.5 within one step: an impulse, P_N/Δt ≫ 1.
        assert!(jam.impulse > 50.0, "{what}");
        if c.b.abs() < B_FOUND {
            continue;
        }
        let slide = find(CornerMotion::SlidingContact)
            .unwrap_or_else(|| panic!("no sliding contact: {what}"));
        if c.b.abs() >= B_CLEAR {
            let error = slide.impulse / c.sliding_force - 1.0;
            assert!(
                error.abs() <= FORCE_TOLERANCE,
                "P_N/Δt off −A/B by {error:.3}: {what}"
            );
        }
    }
}

#[test]
fn painleves_three_solutions_at_mu_2_whatever_the_spin() {
    all_three_in_every_case(2.0, 76);
}

#[test]
fn painleves_three_solutions_at_mu_1_4_whatever_the_spin() {
    all_three_in_every_case(1.4, 28);
}
