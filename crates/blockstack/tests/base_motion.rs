//! A base that heaves and tilts: the contacts read its full pose, twist and acceleration.

use blockstack::{
    scene::stack_on, Accelerogram, Base, BaseMotion, Block, ContactParams, Scene, SolverParams,
    StepRecord,
};
use blockstack::{simulate, RunOptions};

const MU: f64 = 0.3;

/// One block w = 0.2, h = 0.4 of mass `mass` resting on a base w = 1, h = 0.1 whose y
/// and θ move as given, g = 1, Δt = 0.01.
fn one_block(mass: f64, vertical: BaseMotion, rotation: BaseMotion) -> Scene {
    let base = Base::new(1.0, 0.1, BaseMotion::Fixed)
        .unwrap()
        .moving_also(vertical, rotation);
    let block = Block::new(0.2, 0.4, mass).unwrap();
    let blocks = stack_on(&base, &[(block, 0.0, 0.0)]).unwrap();
    let contact = ContactParams {
        mu: MU,
        e_n: 0.0,
        e_f: 0.0,
    };
    Scene::new(base, blocks, None, contact, SolverParams::default()).unwrap()
}

fn run(scene: &Scene, t_end: f64) -> Vec<StepRecord> {
    let mut records = Vec::new();
    let options = RunOptions {
        t_end: Some(t_end),
        ..RunOptions::default()
    };
    let s = simulate(scene, &options, |r| records.push(r.clone())).unwrap();
    assert_eq!(s.error, None);
    records
}

#[test]
fn a_heaving_base_makes_a_resting_block_feel_g_plus_its_acceleration() {
    // y⁰ = A sin ωt: ÿ⁰ = −Aω² sin ωt, between −0.45 and 0.45 (< g: the block stays on).
    let (mass, amp, omega) = (2.0, 0.05, 3.0);
    let heave = BaseMotion::harmonic(amp, omega).unwrap();
    let scene = one_block(mass, heave.clone(), BaseMotion::Fixed);
    let dt = scene.solver.dt;
    let records = run(&scene, 4.0);
    for r in &records[1..] {
        let a = heave.at(r.t).acceleration;
        let impulse = (r.forces[0].normal[0] + r.forces[0].normal[1]) * dt;
        let expected = mass * (1.0 + a) * dt;
        assert!(
            (impulse - expected).abs() < 1e-9 * expected,
            "t = {}: normal impulse {impulse}, m(g + a)Δt = {expected}",
            r.t
        );
        // The block rides on the base: its centre stays h⁰/2 + h/2 above the base's.
        assert!((r.poses[0].y - r.base.y - 0.25).abs() < 1e-9, "t = {}", r.t);
    }
    // Without the heave, the same impulse is the weight's.
    let still = run(&one_block(mass, BaseMotion::Fixed, BaseMotion::Fixed), 0.5);
    let w = (still[20].forces[0].normal[0] + still[20].forces[0].normal[1]) * dt;
    assert!((w - mass * dt).abs() < 1e-12);
}

/// The time the block starts to slide on a base tilting as θ = αt²/2 from rest: with the
/// block stuck to the base, its centre (at r = 0.25 above the base's) accelerates as
/// that point of the base, so the contact must supply, along the base's face and normal
/// to it, F_t = m(g sin θ − αr) and F_n = m(g cos θ − θ̇²r); it slides once
/// F_t = μ F_n (the block is wide enough not to tip: tan θ < w/h = 0.5). The first
/// root, by bisection between rest and θ = 1 rad.
fn analytic_onset(alpha: f64) -> f64 {
    let r = 0.25;
    let excess = |t: f64| {
        let (th, w) = (0.5 * alpha * t * t, alpha * t);
        (th.sin() - alpha * r) - MU * (th.cos() - w * w * r)
    };
    let (mut lo, mut hi) = (0.0, (2.0 / alpha).sqrt());
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if excess(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

#[test]
fn a_tilting_base_lets_a_block_slide_once_tan_theta_exceeds_mu() {
    // θ̈⁰ = α from rest: a record of constant angular acceleration (no baseline
    // correction), slow enough that tan θ at the onset is μ to 1e-3.
    let alpha = 0.005;
    let tilt = BaseMotion::Record(Accelerogram::new(&[(0.0, alpha), (100.0, alpha)]).unwrap());
    let scene = one_block(1.0, BaseMotion::Fixed, tilt);
    let dt = scene.solver.dt;
    let onset = analytic_onset(alpha);
    let theta = 0.5 * alpha * onset * onset;
    assert!((theta.tan() - MU).abs() < 2e-3, "tan θ = {}", theta.tan());
    let records = run(&scene, onset + 0.5);
    // Slip: the block's velocity along the base's face relative to the base's material
    // point under it.
    let slip = |r: &StepRecord| {
        let b = scene.base().state(r.t);
        let (p, v) = (&r.poses[0], r.velocities[0]);
        let (dx, dy) = (p.x - b.pose.x, p.y - b.pose.y);
        let (vx, vy) = (
            v[0] - (b.twist.vx - b.twist.omega * dy),
            v[1] - (b.twist.vy + b.twist.omega * dx),
        );
        let (c, s) = (b.pose.theta.cos(), b.pose.theta.sin());
        vx * c + vy * s
    };
    let first = records
        .iter()
        .find(|r| slip(r).abs() > 1e-8)
        .expect("the block slides");
    assert!(
        (first.t - onset).abs() <= 2.0 * dt,
        "slides from t = {}, analytic onset {onset}",
        first.t
    );
    // It slides down the slope (θ > 0 lowers the −x side) and keeps sliding.
    assert!(slip(records.last().unwrap()) < -1e-4);
    // It stuck before: the friction was below its bound.
    for r in records.iter().filter(|r| r.t < onset - 2.0 * dt).skip(1) {
        let f = r.forces[0];
        assert!(
            f.friction.abs() < MU * (f.normal[0] + f.normal[1]),
            "t = {}",
            r.t
        );
        assert!(slip(r).abs() < 1e-9, "t = {}: slip {}", r.t, slip(r));
    }
}
