//! Decomposes one rotation into all twelve Euler-angle sets and checks each decomposition.
//!
//! Run with `cargo run -p rotations --example euler_decompositions`.

use rotations::{rotation_distance, AxisAngle, EulerSet, Vector3};

fn main() -> Result<(), rotations::RotationError> {
    // The holonomy (2.4.10) of the thesis: ψ = 62.7042° about s = −0.389418 A1 − 0.921061 A3.
    let target = AxisAngle::new(
        62.7042_f64.to_radians(),
        Vector3::new(-0.389_418, 0.0, -0.921_061),
    )?
    .to_rotation();
    println!("set      a1 [deg]     a2 [deg]     a3 [deg]   error [rad]");
    for set in EulerSet::ALL {
        let a = set.angles(&target);
        let error = rotation_distance(&set.rotation(a), &target);
        println!(
            "{set}  {:>11.6}  {:>11.6}  {:>11.6}   {error:.1e}",
            a[0].to_degrees(),
            a[1].to_degrees(),
            a[2].to_degrees()
        );
    }
    Ok(())
}
