//! Any arrangement of blocks ([`blockstack::arrangement`]): the interfaces of a scene come
//! from which bodies each block rests on, so a lintel across two posts has two, blocks
//! side by side have one each (with the base), a column has the thesis's; support is lost
//! per interface, and placements with `on` are checked.

use blockstack::events::EventKind;
use blockstack::overlap::Body;
use blockstack::simulation::RunReport;
use blockstack::{scenes, RunOptions, Scene, Seat};

mod common;
use common::{builtin, run};

/// The trilith on a base that does not move (amplitude 0).
fn resting_trilith() -> Scene {
    Scene::from_toml(&builtin(
        "trilith",
        &[("amplitude = 0.05 ", "amplitude = 0.0 ")],
    ))
    .unwrap()
}

fn seat(lower: Body, upper: usize) -> Seat {
    Seat { lower, upper }
}

#[test]
fn a_column_has_the_thesis_interfaces() {
    let scene = scenes::find("shaking").unwrap().load().unwrap().scene;
    let expected: Vec<Seat> = (1..=4)
        .map(|k| {
            seat(
                if k == 1 {
                    Body::Base
                } else {
                    Body::Block(k - 1)
                },
                k,
            )
        })
        .collect();
    assert_eq!(scene.arrangement().seats(), expected.as_slice());
    assert_eq!(scene.n_interfaces(), 4);
    assert_eq!(
        scene.interface_between(Body::Block(3), Body::Block(2)),
        Some(2)
    );
    assert_eq!(
        scene.interface_between(Body::Block(1), Body::Block(3)),
        None
    );
}

/// A block of a column turned by 1.2 rad (more than the 60° up to which the interface's
/// gaps hold the contact) rests on a corner on the block below (moved left by 0.15 so
/// that its lowest corner, 0.15 right of its centre, lies on the middle of the lower
/// block's top face): it keeps its interface, as in the thesis's column, and does not
/// count as resting on nothing.
#[test]
fn a_turned_block_on_a_corner_keeps_its_interface() {
    let text = "[base]\nwidth = 1.0\nheight = 0.1\n\
        [[blocks]]\nwidth = 0.2\nheight = 0.4\n\
        [[blocks]]\nwidth = 0.2\nheight = 0.4\nx = -0.15\ntheta = 1.2\n\
        [contact]\nmu = 0.5\n[floor]\n";
    let scene = Scene::from_toml(text).unwrap();
    assert_eq!(
        scene.arrangement().seats(),
        [seat(Body::Base, 1), seat(Body::Block(1), 2)].as_slice()
    );
    assert!(scene.warnings().is_empty(), "{:?}", scene.warnings());
}

#[test]
fn a_lintel_rests_on_both_posts_and_side_by_side_blocks_on_the_base_only() {
    let trilith = resting_trilith();
    let expected = [
        seat(Body::Base, 1),
        seat(Body::Base, 2),
        seat(Body::Block(1), 3),
        seat(Body::Block(2), 3),
    ];
    assert_eq!(trilith.arrangement().seats(), expected.as_slice());
    let pair = scenes::find("side-by-side").unwrap().load().unwrap().scene;
    assert_eq!(
        pair.arrangement().seats(),
        [seat(Body::Base, 1), seat(Body::Base, 2)].as_slice()
    );
    // The two crates touch: their common face is 0 apart, yet neither rests on the other.
    assert_eq!(pair.interface_between(Body::Block(1), Body::Block(2)), None);
    assert!(pair.warnings().is_empty(), "{:?}", pair.warnings());
}

/// A trilith on a fixed base stands still: no event, no gap below −1e-10, no block moved.
#[test]
fn a_trilith_at_rest_on_a_fixed_base_stays_at_rest() {
    let scene = resting_trilith();
    let q0 = scene.initial_coordinates();
    let mut lowest = f64::INFINITY;
    let summary = run(&scene, 1.0, |r| lowest = lowest.min(r.min_gap));
    assert!(summary.events.is_empty(), "{:?}", summary.events);
    assert!(lowest >= -1e-10, "a gap of {lowest:e}");
    for (k, p) in summary.final_poses.iter().enumerate() {
        let moved = (p.x - q0[3 * k]).abs() + (p.y - q0[3 * k + 1]).abs();
        assert!(
            moved < 1e-9 && p.theta.abs() < 1e-9,
            "block {}: {p:?}",
            k + 1
        );
    }
}

/// The lintel, centred on two equal posts, weighs on each with half its weight: the
/// normal forces of its two interfaces (each the sum of its two gaps' forces) are equal at
/// every step, and together carry it. Measured: 12262.500015 and 12262.499985 N against
/// m g / 2 = 12262.5 N, a difference of 1.2·10⁻⁹ of the weight, where the Newton
/// tolerance (10⁻¹⁰) stops the iteration.
#[test]
fn the_lintel_weight_splits_equally_between_the_posts() {
    let scene = resting_trilith();
    let lintel = &scene.blocks()[2];
    let weight = lintel.mass() * scene.solver.gravity;
    let [on_left, on_right] = [Body::Block(1), Body::Block(2)]
        .map(|post| scene.interface_between(post, Body::Block(3)).unwrap());
    let mut checked = 0;
    let summary = run(&scene, 0.2, |r| {
        if r.t == 0.0 {
            return;
        }
        let carried = |k: usize| r.forces[k].normal[0] + r.forces[k].normal[1];
        let (left, right) = (carried(on_left), carried(on_right));
        assert!(
            (left - right).abs() <= 1e-8 * weight,
            "t = {}: {left} and {right}",
            r.t
        );
        assert!(
            (left + right - weight).abs() <= 1e-6 * weight,
            "t = {}: {left} + {right} against the lintel's weight {weight}",
            r.t
        );
        checked += 1;
    });
    assert_eq!(checked, summary.steps);
}

/// Shaken hard, the frame rocks, a post tips and the lintel loses its support on it: the
/// event names the lintel and the post, and the report's lines read so.
#[test]
fn a_hard_shaken_trilith_loses_its_lintel_on_a_post() {
    let text = builtin("trilith", &[("amplitude = 0.05 ", "amplitude = 0.3 ")]);
    let loaded = blockstack::LoadedScene::from_toml(&text).unwrap();
    let scene = &loaded.scene;
    let summary = run(scene, 3.0, |_| {});
    let lost: Vec<_> = summary
        .events
        .iter()
        .filter(|e| e.kind == EventKind::SupportLost)
        .collect();
    let first = lost.first().expect("the lintel loses its support");
    assert_eq!(first.block, Some(3), "{lost:?}");
    let post = first.on.expect("a lintel's event names the post");
    assert!(matches!(post, Body::Block(1 | 2)), "{post:?}");
    let report = RunReport::new(
        &summary,
        scene,
        &RunOptions::default(),
        &loaded.defaults,
        summary.final_poses.len() as f64,
    );
    let text = report.to_string();
    let name = if post == Body::Block(1) {
        "left-post"
    } else {
        "right-post"
    };
    let line = format!("block 3 (lintel) on {post} ({name}) at t = {:.4}", first.t);
    assert!(text.contains(&line), "{line:?} not in\n{text}");
    let json = serde_json::to_value(first).unwrap();
    assert_eq!(json["on"], post.to_string());
}

#[test]
fn blocks_side_by_side_on_a_fixed_base_do_not_fail() {
    let text = builtin("side-by-side", &[("amplitude = 0.02 ", "amplitude = 0.0 ")]);
    let scene = Scene::from_toml(&text).unwrap();
    let summary = run(&scene, 1.0, |_| {});
    assert!(summary.events.is_empty(), "{:?}", summary.events);
    assert!(summary.failure_time.is_none());
}

/// The shaken crates stand: they slide a little, push each other, and neither loses its
/// support, tips or falls.
#[test]
fn blocks_side_by_side_on_a_shaken_base_stand() {
    let scene = scenes::find("side-by-side").unwrap().load().unwrap().scene;
    let summary = run(&scene, scene.solver.t_end, |_| {});
    assert!(summary.events.is_empty(), "{:?}", summary.events);
    let depth = summary.deepest.depth();
    assert!(depth < 1e-6, "{depth}");
}

/// Two blocks placed into each other: refused, naming both (by name where they have one)
/// and the depth.
#[test]
fn an_overlapping_placement_is_refused_naming_both_blocks() {
    let text = "[base]\nwidth = 2.0\nheight = 0.1\n\
        [[blocks]]\nname = \"plinth\"\nwidth = 0.6\nheight = 0.4\non = \"base\"\n\
        [[blocks]]\nname = \"statue\"\nwidth = 0.2\nheight = 0.8\nx = 0.35\non = \"base\"\n\
        [contact]\nmu = 0.5\n";
    let e = Scene::from_toml(text).unwrap_err().to_string();
    assert!(
        e.contains("block 1 (plinth) and block 2 (statue) overlap by 5.000e-2"),
        "{e}"
    );
    assert!(!e.contains('\n'));
    // Unnamed, by number.
    let unnamed = text
        .replace("name = \"plinth\"\n", "")
        .replace("name = \"statue\"\n", "");
    let e = Scene::from_toml(&unnamed).unwrap_err().to_string();
    assert!(e.contains("block 1 and block 2 overlap by 5.000e-2"), "{e}");
}

/// `on` puts a block on the highest of the bodies it names, at its own x; a statue on its
/// plinth is a column of two; bad `on` values are one-line errors naming the entry.
#[test]
fn on_places_a_block_on_named_bodies() {
    let head = "[base]\nwidth = 2.0\nheight = 0.1\n\
        [[blocks]]\nname = \"plinth\"\nwidth = 0.6\nheight = 0.4\nx = 0.5\non = \"base\"\n";
    let statue =
        "[[blocks]]\nname = \"statue\"\nwidth = 0.2\nheight = 0.8\nx = 0.55\non = \"plinth\"\n";
    let tail = "[contact]\nmu = 0.5\n";
    let scene = Scene::from_toml(&format!("{head}{statue}{tail}")).unwrap();
    let q = scene.initial_coordinates();
    assert_eq!((q[0], q[1]), (0.5, 0.05 + 0.2));
    assert_eq!((q[3], q[4]), (0.55, 0.05 + 0.4 + 0.4));
    assert_eq!(
        scene.arrangement().seats(),
        [seat(Body::Base, 1), seat(Body::Block(1), 2)].as_slice()
    );
    let err = |entry: &str| {
        let e = Scene::from_toml(&format!("{head}{entry}{tail}"))
            .unwrap_err()
            .to_string();
        assert!(!e.contains('\n'), "{e}");
        e
    };
    let e = err(&statue.replace("on = \"plinth\"", "on = \"plinth\"\ny = 2.0"));
    assert!(e.contains("[[blocks]] entry 1 gives both y and on"), "{e}");
    let e = err(&statue.replace("on = \"plinth\"", "on = \"pedestal\""));
    assert!(
        e.contains("[[blocks]] entry 1 on: no body named \"pedestal\""),
        "{e}"
    );
    let e = err(&statue.replace("on = \"plinth\"", "on = \"statue\""));
    assert!(e.contains("listed before it"), "{e}");
    let e = err(&statue.replace("on = \"plinth\"", "on = \"floor\""));
    assert!(
        e.contains("[[blocks]] entry 1 on: \"floor\" is not a body"),
        "{e}"
    );
    let e = err(&statue.replace("on = \"plinth\"", "on = []"));
    assert!(e.contains("[[blocks]] entry 1 on: names no body"), "{e}");
}

/// Blocks lying on their sides on other lying blocks (examples/scenes/pile-at-rest.toml:
/// three stacked, and one across two) have no interface there (blocks 2, 3 and 6), but
/// they rest on those blocks through corner contacts: no warning that they fall (it
/// named blocks 2, 3 and 6), and they do not move.
#[test]
fn blocks_lying_across_others_rest_on_them() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/scenes/pile-at-rest.toml"
    );
    let scene = Scene::from_toml(&std::fs::read_to_string(path).unwrap()).unwrap();
    for k in [2, 3, 6] {
        assert!(scene.arrangement().seats_of(k).is_empty(), "block {k}");
    }
    assert!(scene.warnings().is_empty(), "{:?}", scene.warnings());
    let y0 = scene.initial_coordinates();
    let summary = run(&scene, 1.0, |_| {});
    for (k, pose) in summary.final_poses.iter().enumerate() {
        assert!(
            (pose.y - y0[3 * k + 1]).abs() < 1e-9,
            "block {}: {pose:?}",
            k + 1
        );
    }
}

/// A block given a height in the air rests on nothing: no interface, a warning that says
/// it falls, and no support event (it had none to lose).
#[test]
fn a_block_in_the_air_has_no_interface_and_falls() {
    let text = "[base]\nwidth = 2.0\nheight = 0.1\n\
        [[blocks]]\nwidth = 0.4\nheight = 0.2\n\
        [[blocks]]\nname = \"stone\"\nwidth = 0.2\nheight = 0.2\ny = 1.0\n\
        [contact]\nmu = 0.5\n[floor]\n";
    let scene = Scene::from_toml(text).unwrap();
    assert_eq!(
        scene.arrangement().seats(),
        [seat(Body::Base, 1)].as_slice()
    );
    let warnings: Vec<String> = scene.warnings().iter().map(ToString::to_string).collect();
    assert_eq!(
        warnings,
        ["block 2 (stone) rests on nothing at the start (no base or block under its bottom face, no floor): it falls"]
    );
    let y0 = scene.initial_coordinates()[4];
    let summary = run(&scene, 0.5, |_| {});
    assert!(
        summary.final_poses[1].y < y0 - 0.1,
        "{:?}",
        summary.final_poses
    );
    assert!(summary.events.is_empty(), "{:?}", summary.events);
}
