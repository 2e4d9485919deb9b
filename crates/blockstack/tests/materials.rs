//! Materials per interface ([`blockstack::materials`]): μ, e_N, e_F of the `[contact]`
//! table overridden by `[contact.base]`, `[contact.blocks]`, `[contact.floor]` and
//! `[[contact.pair]]`, seen in the laws the stepper gets and in what the blocks do.

use blockstack::overlap::Body;
use blockstack::{simulate, RunOptions, Scene};

/// A column of `blocks` wide, low blocks (w = 0.4, h = 0.2: they slide long before they
/// could rock) on a base shaken as x = A sin(4t) with a peak acceleration of 0.3 g, for
/// two periods, with the `[contact]` table `contact` (and any table after it). Block 1
/// is named "bottom".
fn column(blocks: usize, contact: &str) -> String {
    let mut text = String::from(
        "[base]\nwidth = 1.0\nheight = 0.1\nmotion = \"harmonic\"\namplitude = 0.01875\nomega = 4.0\n\
         [[blocks]]\nwidth = 0.4\nheight = 0.2\nname = \"bottom\"\n",
    );
    if blocks > 1 {
        text += &format!(
            "[[blocks]]\nwidth = 0.4\nheight = 0.2\ncount = {}\n",
            blocks - 1
        );
    }
    text + "[solver]\nsteps_per_period = 100\nperiods = 2\n" + contact
}

/// How far each interface slips after the first half period: the range of x_k − x_{k−1}
/// of the block centres (x₀ the base's). The base starts at its peak speed under blocks
/// at rest, so every interface slips a little at first; that start is left out.
fn slips(text: &str) -> Vec<f64> {
    let scene = Scene::from_toml(text).unwrap();
    let half_period = std::f64::consts::PI / 4.0;
    let mut range = vec![(f64::INFINITY, f64::NEG_INFINITY); scene.n_blocks()];
    let summary = simulate(&scene, &RunOptions::default(), |r| {
        if r.t < half_period {
            return;
        }
        let mut below = r.base.x;
        for (k, p) in r.poses.iter().enumerate() {
            let d = p.x - below;
            range[k] = (range[k].0.min(d), range[k].1.max(d));
            below = p.x;
        }
    })
    .unwrap();
    assert!(summary.error.is_none(), "{:?}", summary.error);
    range.iter().map(|(lo, hi)| hi - lo).collect()
}

/// Slips of more than 1e-3 (of a block 0.4 wide): sliding (measured 0.0375 for μ = 0.05
/// on the column); less than 1e-4: sticking (measured 1.6e-5 on the base, the same with
/// and without a block above: stick holds the slip speed, and the relative position
/// drifts by that much over the run).
const SLIDES: f64 = 1e-3;
const STICKS: f64 = 1e-4;

#[test]
fn a_block_slides_on_a_slippery_base_whatever_the_blocks_mu() {
    let base_low = slips(&column(
        1,
        "[contact]\nmu = 0.8\n[contact.base]\nmu = 0.1\n",
    ));
    assert!(base_low[0] > SLIDES, "{base_low:?}");
    // μ of the block–block interfaces does not reach a block alone on the base.
    let blocks_low = slips(&column(
        1,
        "[contact]\nmu = 0.8\n[contact.blocks]\nmu = 0.1\n",
    ));
    assert!(blocks_low[0] < STICKS, "{blocks_low:?}");
    let plain = slips(&column(1, "[contact]\nmu = 0.8\n"));
    assert_eq!(blocks_low, plain, "bit-identical");
}

#[test]
fn the_interface_with_the_low_mu_is_the_one_that_slips() {
    let base_low = slips(&column(
        2,
        "[contact]\nmu = 0.8\n[contact.base]\nmu = 0.05\n",
    ));
    assert!(base_low[0] > SLIDES && base_low[1] < STICKS, "{base_low:?}");
    let blocks_low = slips(&column(
        2,
        "[contact]\nmu = 0.8\n[contact.blocks]\nmu = 0.05\n",
    ));
    assert!(
        blocks_low[0] < STICKS && blocks_low[1] > SLIDES,
        "{blocks_low:?}"
    );
}

#[test]
fn a_pair_override_wins_over_its_kind() {
    let pair = "[[contact.pair]]\nbodies = [\"base\", \"bottom\"]\nmu = 0.8\n";
    let text = column(
        2,
        &format!("[contact]\nmu = 0.05\n[contact.base]\nmu = 0.05\n{pair}"),
    );
    let s = slips(&text);
    assert!(s[0] < STICKS && s[1] > SLIDES, "{s:?}");
}

#[test]
fn each_kind_reaches_its_own_contacts() {
    let text = column(
        3,
        "[contact]\nmu = 0.5\ne_n = 0.1\n[contact.base]\nmu = 0.2\n[contact.blocks]\ne_n = 0.3\ne_f = 0.4\n\
         [contact.floor]\nmu = 0.7\ne_n = 0.6\n[floor]\n",
    );
    let scene = Scene::from_toml(&text).unwrap();
    let laws: Vec<(f64, f64)> = scene
        .friction_laws()
        .iter()
        .map(|l| (l.mu, l.e_f))
        .collect();
    // Interfaces base/1, 1/2, 2/3, then the floor laws of blocks 1, 2, 3.
    let floor = (0.7, 0.0);
    assert_eq!(
        laws,
        [(0.2, 0.0), (0.5, 0.4), (0.5, 0.4), floor, floor, floor]
    );
    let e_n = scene.normal_restitutions();
    assert_eq!(e_n[..6], [0.1, 0.1, 0.3, 0.3, 0.3, 0.3]);
    assert!(e_n[6..].iter().all(|&e| e == 0.6) && e_n.len() == 6 + 12);
}

#[test]
fn names_and_pairs_are_checked_with_one_line_naming_the_key() {
    let err = |contact: &str| {
        let e = Scene::from_toml(&column(2, contact))
            .unwrap_err()
            .to_string();
        assert!(!e.contains('\n'), "{e}");
        e
    };
    let pair = |bodies: &str| {
        format!("[contact]\nmu = 0.5\n[[contact.pair]]\nbodies = {bodies}\nmu = 0.1\n")
    };
    let e = err(&pair("[\"base\", \"capital\"]"));
    assert!(
        e.contains("contact.pair.0 bodies: no body named \"capital\"")
            && e.contains("base, floor, bottom"),
        "{e}"
    );
    assert!(err(&pair("[\"base\", \"floor\"]")).contains("never touch"));
    let e = err(&pair("[\"base\", \"bottom\"]\nmuu = 0.1"));
    assert!(e.contains("unknown field") && e.contains("muu"), "{e}");
    let e = err(&pair("[\"base\"]"));
    assert!(e.contains("bodies"), "{e}");
    let e = err("[contact]\nmu = 0.5\n[[contact.pair]]\nmu = 0.1\n");
    assert!(e.contains("missing field") && e.contains("bodies"), "{e}");
    assert!(err(&pair("[\"bottom\", \"bottom\"]")).contains("itself"));
    let e = err("[contact]\nmu = 0.5\n[contact.floor]\ne_n = 1.5\n");
    assert!(e.contains("contact.floor.e_n"), "{e}");
    let e = err("[contact]\nmu = 0.5\n[contact.walls]\nmu = 0.1\n");
    assert!(e.contains("unknown field") && e.contains("walls"), "{e}");
    // A name is one block's.
    let named_group = column(1, "[contact]\nmu = 0.5\n")
        .replace("name = \"bottom\"", "name = \"bottom\"\ncount = 2");
    let e = Scene::from_toml(&named_group).unwrap_err().to_string();
    assert!(
        e.contains("[[blocks]] entry 0 name") && e.contains("count = 2"),
        "{e}"
    );
    let twice = column(1, "[contact]\nmu = 0.5\n")
        + "[[blocks]]\nwidth = 0.4\nheight = 0.2\nname = \"bottom\"\n";
    let e = Scene::from_toml(&twice).unwrap_err().to_string();
    assert!(e.contains("already the name"), "{e}");
    let floor = column(1, "[contact]\nmu = 0.5\n").replace("\"bottom\"", "\"floor\"");
    assert!(Scene::from_toml(&floor)
        .unwrap_err()
        .to_string()
        .contains("taken"));
}

/// The example of docs/scenes.md ("Materials per interface"), on a base: it loads with the
/// materials the page says, and the page's error messages are the loader's.
#[test]
fn the_example_of_the_scenes_page_is_what_it_says() {
    const DOC: &str = include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/scenes.md"));
    let from = DOC.find("**Materials per interface.**").unwrap();
    let start = DOC[from..].find("```toml\n").unwrap() + from + 8;
    let example = &DOC[start..start + DOC[start..].find("```").unwrap()];
    let text = format!("[base]\nwidth = 1.0\nheight = 0.1\n{example}");
    let scene = Scene::from_toml(&text).unwrap();
    let (base, plinth, statue) = (Body::Base, Body::Block(1), Body::Block(2));
    assert_eq!(scene.contact_between(base, plinth).mu, 0.1);
    let glued = scene.contact_between(statue, plinth);
    assert_eq!((glued.mu, glued.e_n), (5.0, 0.0));
    let e = Scene::from_toml(&text.replace("\"statue\"]", "\"capital\"]"))
        .unwrap_err()
        .to_string();
    assert!(DOC.contains(&format!("error: {e}\n")), "{e}");
    let e = Scene::from_toml(&text.replace("mu = 0.1", "mu = -0.1"))
        .unwrap_err()
        .to_string();
    assert!(DOC.contains(&format!("error: {e}\n")), "{e}");
}
