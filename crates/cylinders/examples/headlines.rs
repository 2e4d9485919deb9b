//! Headline numbers of Chapter 3: support forces, one holonomy, Frobenius ranks.
//!
//! Run with `cargo run -p cylinders --example headlines`.

use cylinders::frobenius::frobenius_test;
use cylinders::holonomy::{figure_3_12, CirclePath, Direction, Figure310, PathCase};
use cylinders::kinematics::Cylinder;
use cylinders::pair::{CylinderPair, PairConstraints, PairSystem, SingleCylinder};
use cylinders::statics::{FrictionLimit, SupportProblem};
use rotations::rotation_distance;

fn main() -> Result<(), cylinders::CylinderError> {
    // §3.3 with r/h = 0.1, μ = 0.2 (Figure 3.3) at ϑ = 30°.
    let problem = SupportProblem::new(0.1, 0.2)?;
    let theta = 30f64.to_radians();
    for limit in [
        FrictionLimit::Plus,
        FrictionLimit::Smooth,
        FrictionLimit::Minus,
    ] {
        println!(
            "N/mg ({limit:?}) at 30°: {:?}",
            problem.normal_force(theta, limit)?
        );
    }
    let min = problem.minimum_force(theta)?;
    println!("minimum force at 30°: {min:?}");

    // Figure 3.10 (radians, ERRATA 8).
    let fig = Figure310::new(PathCase::I);
    let err = rotation_distance(
        &fig.path.product(fig.theta, 0.0),
        &fig.path.closed_form(fig.theta, 0.0),
    );
    println!(
        "Figure 3.10: Δφ = {:.6} rad, product vs closed form {err:.1e}",
        fig.path.delta_phi()
    );
    let (cyl, theta12, ell) = figure_3_12();
    let hol =
        CirclePath::new(ell, PathCase::I, Direction::CounterClockwise)?.holonomy(&cyl, theta12)?;
    println!(
        "Figure 3.12: ℓ = {ell:.6} r, k = {:.6} r, Δφ = {:.6} rad",
        hol.k, hol.delta_phi
    );

    // Frobenius (App. D, F; ERRATA 13).
    let single = SingleCylinder {
        cylinder: Cylinder::gas_cylinder(),
    };
    let report = frobenius_test(&single, &[0.1, 0.2, 0.7, 0.4, 0.5, 0.3])?;
    println!(
        "single: rank {} max|aSb| {:?}",
        report.rank, report.max_abs_asb
    );
    let pair = CylinderPair::identical(Cylinder::gas_cylinder());
    for (name, q) in [
        ("touching", pair.touching_configuration(0.4, 0.3, 0.5)?),
        ("generic", pair.generic_configuration(0.4, 0.3, 0.5)?),
    ] {
        for constraints in [PairConstraints::Seven, PairConstraints::Nine] {
            let report = frobenius_test(&PairSystem { pair, constraints }, &q)?;
            println!(
                "pair {constraints:?} ({name}): rank {} σ_min {:.4} max|aSb| {:?}",
                report.rank,
                report.smallest_nonzero_singular_value(),
                report
                    .max_abs_asb
                    .iter()
                    .map(|v| format!("{v:.2e}"))
                    .collect::<Vec<_>>()
            );
        }
    }
    Ok(())
}
