//! Falling blocks stay solid: thrown, dropped, falling past the base, a toppling column.
//! No two bodies overlap beyond the tolerance, the energy of these unforced scenes never
//! grows, and everything comes to rest on the floor, the base or another block.

use blockstack::broad_phase::corner_gap_of;
use blockstack::overlap::Body;
use blockstack::simulation::{simulate, RunOptions, RunSummary};
use blockstack::{Corner, Scene, SceneFile};

/// A fixed base 0.4 × 0.1 at the origin, the floor at its bottom (y = −0.05), g = 1,
/// μ = 0.3, e_N = e_F = 0, and the given `[[blocks]]` entries.
fn scene(blocks: &str) -> Scene {
    let text = format!(
        "[base]\nwidth = 0.4\nheight = 0.1\n{blocks}\n[contact]\nmu = 0.3\n[solver]\n\
         dt = 0.005\n[floor]\n"
    );
    SceneFile::parse(&text)
        .and_then(|f| f.to_scene())
        .unwrap_or_else(|e| panic!("{e}\n{text}"))
}

/// Runs to `t_end`; returns the summary and the last velocities.
fn run(scene: &Scene, t_end: f64) -> (RunSummary, Vec<[f64; 3]>) {
    let options = RunOptions {
        t_end: Some(t_end),
        ..Default::default()
    };
    let mut last = Vec::new();
    let summary = simulate(scene, &options, |r| last.clone_from(&r.velocities)).unwrap();
    assert!(summary.error.is_none(), "{:?}", summary.error);
    (summary, last)
}

/// Block k (1-based) touches, within `tol`, the floor or a body whose centre is lower.
fn rests_on_something(scene: &Scene, q: &[f64], k: usize, tol: f64) -> bool {
    let size = scene.size(k);
    let pose = blockstack::Pose::from_slice(&q[3 * k - 3..]);
    let lowest = blockstack::corners::corners(&pose, size.width, size.height)
        .iter()
        .map(|c| c.y)
        .fold(f64::INFINITY, f64::min);
    if lowest - scene.floor().unwrap().y < tol {
        return true;
    }
    let y_of = |b: Body| match b {
        Body::Block(j) => q[3 * j - 2],
        _ => 0.0,
    };
    let touching = |a: Body, b: Body| {
        Corner::ALL
            .iter()
            .any(|&corner| corner_gap_of(scene, 0.0, q, a, corner, b).abs() < tol)
    };
    let me = Body::Block(k);
    std::iter::once(Body::Base)
        .chain((1..=scene.n_blocks()).map(Body::Block))
        .filter(|&b| b != me && y_of(b) < y_of(me))
        .any(|b| touching(me, b) || touching(b, me))
}

/// What every scene here must show.
fn assert_solid_and_at_rest(scene: &Scene, summary: &RunSummary, last: &[[f64; 3]]) {
    assert!(
        summary.deepest.depth() < summary.penetration_tol,
        "penetration {:?} beyond {}",
        summary.deepest,
        summary.penetration_tol
    );
    // The energy scale of these scenes is m g h ~ 0.4: a rise from a body pushed out of
    // another would be of that order; 1e-6 leaves room only for the O(Δt²) settling of
    // generalized-α's auxiliary acceleration ā after an impact.
    assert!(
        summary.max_energy_increase < 1e-6,
        "the energy grew by {}",
        summary.max_energy_increase
    );
    let speed = last.iter().flatten().map(|v| v.abs()).fold(0.0, f64::max);
    assert!(speed < 1e-6, "still moving at {speed}");
    let q: Vec<f64> = summary
        .final_poses
        .iter()
        .flat_map(|p| [p.x, p.y, p.theta])
        .collect();
    for k in 1..=scene.n_blocks() {
        assert!(
            rests_on_something(scene, &q, k, 1e-6),
            "block {k} rests on nothing: {:?}",
            summary.final_poses[k - 1]
        );
    }
}

#[test]
fn two_blocks_thrown_at_each_other_meet_and_land_together() {
    // Closing at 8 length units per time unit: 0.04 per step, a fifth of a block width.
    let s = scene(
        "[[blocks]]\nwidth = 0.2\nheight = 0.4\nx = -1.0\ny = 0.6\nvelocity = [4.0, 0.0, 0.0]\n\
         [[blocks]]\nwidth = 0.2\nheight = 0.4\nx = 1.0\ny = 0.6\nvelocity = [-4.0, 0.0, 0.0]\n",
    );
    let (summary, last) = run(&s, 6.0);
    assert!(summary.corner_contacts > 0);
    assert_solid_and_at_rest(&s, &summary, &last);
    // A plastic impact of equal masses at equal speeds: they stop where they meet, on
    // either side of x = 0, and fall onto the base.
    let [a, b] = [&summary.final_poses[0], &summary.final_poses[1]];
    assert!(
        a.x < 0.0 && b.x > 0.0 && (b.x - a.x - 0.2).abs() < 1e-6,
        "{a:?} {b:?}"
    );
    assert!(
        (a.y - 0.25).abs() < 1e-6 && (b.y - 0.25).abs() < 1e-6,
        "on the base"
    );
}

#[test]
fn a_block_dropped_on_a_lying_block_comes_to_rest_on_it() {
    let s = scene(
        "[[blocks]]\nwidth = 0.2\nheight = 0.4\nx = 1.5\ny = 0.05\ntheta = 1.5707963267948966\n\
         [[blocks]]\nwidth = 0.2\nheight = 0.4\nx = 1.45\ny = 1.0\ntheta = 0.3\n",
    );
    let (summary, last) = run(&s, 12.0);
    assert_solid_and_at_rest(&s, &summary, &last);
    assert!(summary.corner_contacts > 0);
}

#[test]
fn a_block_falling_past_the_base_lands_beside_it() {
    // Overhanging the base's right edge by three quarters, tilted: it strikes the edge,
    // turns off it and falls past the base's side to the floor.
    let s = scene("[[blocks]]\nwidth = 0.2\nheight = 0.4\nx = 0.25\ny = 0.6\ntheta = -0.4\n");
    let (summary, last) = run(&s, 12.0);
    assert_solid_and_at_rest(&s, &summary, &last);
    let p = &summary.final_poses[0];
    assert!(p.x > 0.2, "beside the base, to the right: {p:?}");
}

#[test]
fn a_toppling_column_comes_to_rest_on_the_floor_and_on_itself() {
    // Each block 0.08 right of the one below: blocks 2–4 overhang block 1 by 0.16 > 0.1.
    let blocks: String = (0..4)
        .map(|k| {
            format!(
                "[[blocks]]\nwidth = 0.2\nheight = 0.4\nx = {}\n",
                0.08 * f64::from(k)
            )
        })
        .collect();
    let s = scene(&blocks);
    let (summary, last) = run(&s, 20.0);
    assert!(summary.failure_time.is_some(), "the column falls");
    assert_solid_and_at_rest(&s, &summary, &last);
}
