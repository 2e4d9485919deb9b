//! Painlevé's indeterminacy (App. I) found whole: in every case of the corner scan
//! (`examples/painleve_forks.rs`) with B < 0 and A > 0, at μ = 2 and μ = 1.4 and either
//! sign of the spin, the first step's solutions are sliding contact (n ≈ −A/B), jam and
//! lift-off, told apart by their contact states, at the scan's Δt or, near b = 0, at a
//! finer one (`SCAN_STEPS`).

use blockstack::studies::painleve::{corner_scan, CornerCase, CornerMotion, SCAN_STEPS};

/// The point-contact cases of the scan at `mu` with B < 0: θ = 0 is left out, where both
/// bottom corners touch (line contact, §I.2, a unique solution).
fn point_contact_paradoxes(mu: f64) -> Vec<CornerCase> {
    let scan = corner_scan(mu).unwrap();
    let line: Vec<f64> = scan
        .iter()
        .filter(|c| c.line_contact)
        .map(|c| c.case.theta)
        .collect();
    assert!(
        line.iter().all(|&t| t == 0.0) && !line.is_empty(),
        "{line:?}"
    );
    scan.into_iter()
        .filter(|c| !c.line_contact && c.b < 0.0)
        .collect()
}

/// Over one step (Δt = 10⁻³) A and B drift with θ and θ̇, by an amount whose sign follows
/// the spin: the step's mean normal force P_N/Δt meets −A/B (taken at the step's start)
/// within this relative tolerance where |B| ≥ [`B_CLEAR`] (within 9.6 % at μ = 2).
const FORCE_TOLERANCE: f64 = 0.1;
/// The least |B| at which the force is compared: nearer b = 0, −A/B is steep in θ.
const B_CLEAR: f64 = 0.13;

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

/// Near b = 0 the discrete step's B differs from App. I's by O(Δt): at μ = 1.4, θ = ±0.1
/// (B = −0.017) one spin sign's first step at Δt = 10⁻³ has no sliding contact, and the
/// scan finds it at 10⁻⁴, its force then near −A/B = 30.
#[test]
fn near_b_zero_the_sliding_contact_is_found_at_a_finer_step() {
    let refined: Vec<CornerCase> = point_contact_paradoxes(1.4)
        .into_iter()
        .filter(|c| c.dt < SCAN_STEPS[0])
        .collect();
    assert_eq!(refined.len(), 2, "{refined:?}");
    for c in refined {
        assert!((c.case.theta.abs() - 0.1).abs() < 1e-12, "{c:?}");
        assert_eq!(c.dt, SCAN_STEPS[1]);
        let slide = c.find(CornerMotion::SlidingContact).unwrap();
        assert!((slide.impulse / c.sliding_force - 1.0).abs() < 0.1, "{c:?}");
    }
}
