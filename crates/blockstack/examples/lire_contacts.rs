//! The Leaning Tower of Lire (§4.3) as the contact geometry sees it: the harmonic
//! overhangs (ERRATA 16), each interface's gap cases and support, and what changes when the
//! top block is pushed off its support.
//!
//! Run with `cargo run -p blockstack --example lire_contacts`.

use blockstack::scenarios::{lire, maximum_overhang, Perturbation};
use blockstack::BlockError;

fn main() -> Result<(), BlockError> {
    println!(
        "maximum overhang of 4 blocks of width 1: {:.6} (ERRATA 16: 25/24)",
        maximum_overhang(4, 1.0)
    );
    let scene = lire(4, Perturbation::None)?;
    let mut q = scene.initial_coordinates();
    let u = vec![0.0; q.len()];
    for (k, b) in q.chunks(3).enumerate() {
        println!(
            "block {}: x = {:.6}, y = {:.3}, theta = {}",
            k + 1,
            b[0],
            b[1],
            b[2]
        );
    }
    let report = |q: &[f64]| {
        let c = scene.contacts(0.0, q, &u);
        for (k, i) in c.interfaces.iter().enumerate() {
            println!(
                "  interface {k}/{}: {:?}, left {:?} g = {:+.3e}, right {:?} g = {:+.3e}",
                k + 1,
                i.support,
                i.left.case,
                i.left.row.value,
                i.right.case,
                i.right.row.value
            );
        }
    };
    println!("at rest:");
    report(&q);
    // Slide the top block right by half a width: it no longer rests on block 3.
    q[9] += 0.6;
    println!("top block slid 0.6 to the right:");
    report(&q);
    Ok(())
}
