//! A wide block that lands flat while it slides slowly: the step of the landing with and
//! without the friction percussions' half-step shift of the position correction
//! (`Options::friction_percussion_shift`, docs/method.md §8.2).
//!
//! At the landing the friction percussion acts at the bottom face, h below the centre.
//! Shifted by ½Δt M⁻¹W_FΛ_F, it turns the block; to keep both corners on the ground the
//! normal position multipliers must turn it back, one of them with κ̂_N < 0, so the sets
//! recomputed from each fixed-set solution open that corner, and opened it sinks: the
//! first attempt cycles. Without the shift the landing converges like any other step.

use nsga::systems::rocking::RockingBlock;
use nsga::{Options, State, Stepper};

/// Half-width 0.2, half-height 0.1 (a block lying on its long side), g = 1, μ = 0.5.
fn wide_block() -> RockingBlock {
    RockingBlock {
        mass: 1.0,
        half_width: 0.2,
        half_height: 0.1,
        gravity: 1.0,
        mu: 0.5,
        e_n: 0.0,
    }
}

/// Tilted by 0.05 on its corner s = −1, turning down at θ̇ = −0.5 about that corner
/// while the corner slides at 0.02.
fn landing_start(block: &RockingBlock) -> ([f64; 3], [f64; 3]) {
    let theta = 0.05_f64;
    let (q0, _) = block.tilted(theta);
    let (s, c) = theta.sin_cos();
    let (b, h) = (block.half_width, block.half_height);
    let (rx, ry) = (b * c - h * s, b * s + h * c);
    let (slide, turn) = (0.02, -0.5);
    (q0, [slide - turn * ry, turn * rx, turn])
}

/// 40 steps of Δt = 0.01 (the landing is at t ≈ 0.1): the failed first attempts, the
/// linear solves and the last state.
fn land(shift: bool) -> (usize, u64, State) {
    let block = wide_block();
    let (q0, u0) = landing_start(&block);
    let options = Options {
        dt: 0.01,
        friction_percussion_shift: shift,
        ..Options::default()
    };
    let mut stepper = Stepper::new(block, 0.0, &q0, &u0, options).unwrap();
    let mut retried = 0;
    for _ in 0..40 {
        retried += usize::from(stepper.step().unwrap().retries > 0);
    }
    (retried, stepper.linear_solves(), stepper.state().clone())
}

#[test]
fn a_block_landing_flat_while_it_slides_needs_no_retry_without_the_shift() {
    let (retried, solves, end) = land(false);
    assert_eq!(retried, 0, "{solves} linear solves");
    // Landed flat and resting: no rotation left, both corners on the ground.
    assert!(
        end.q[2].abs() < 1e-9 && end.u[2].abs() < 1e-9,
        "{:?}",
        end.q
    );
    assert!((end.q[1] - 0.1).abs() < 1e-9, "{:?}", end.q);
    // The paper's shift: the landing step's first attempt fails, and the fallbacks
    // take several times the linear solves for the same 40 steps.
    let (retried_shifted, solves_shifted, end_shifted) = land(true);
    assert!(retried_shifted >= 1, "{solves_shifted} linear solves");
    assert!(solves_shifted > 2 * solves, "{solves_shifted} vs {solves}");
    // Both come to rest; where the sliding stops differs by less than Δt times the
    // sliding speed (the half step of the friction percussion).
    assert!(end_shifted.u.iter().all(|v| v.abs() < 1e-9));
    assert!((end.q[0] - end_shifted.q[0]).abs() < 0.01 * 0.02);
}
