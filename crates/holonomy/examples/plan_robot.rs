//! Plan a reorientation for a spherical robot: every rectangle that turns it by 3π/2
//! about 0.1 A1 + √0.98 A2 + 0.1 A3 ((2.4.12)), the shortest one, and an Euler plan.
//!
//! `cargo run -p holonomy --example plan_robot`

use holonomy::roll::{roll, CentrePath, Integrator};
use holonomy::{euler_plan_for_rotation, plan_rectangles, shortest, HolonomyError};
use rotations::{rotation_distance, AxisAngle, EulerSet, Vector3};
use std::f64::consts::PI;

fn main() -> Result<(), HolonomyError> {
    let target = AxisAngle::new(1.5 * PI, Vector3::new(0.1, 0.98_f64.sqrt(), 0.1))?.to_rotation();
    let plans = plan_rectangles(&target)?;
    println!(
        "{} rectangles (ϑ, φ1, φ2, direction, path length / R, error):",
        plans.len()
    );
    for p in &plans {
        let r = p.rectangle;
        println!(
            "  {:.5} {:.5} {:.5} {:>3} {:8.4} {:.1e}",
            r.theta,
            r.phi1,
            r.phi2,
            r.direction.as_str(),
            r.path_length(),
            p.error
        );
    }
    if let Some(best) = shortest(&plans) {
        let path = CentrePath::rectangle(&best.rectangle, 1.0)?;
        let traj = roll(&path, 1.0, Integrator::Rk4, 2000)?;
        let err = rotation_distance(&traj.final_orientation().to_rotation_matrix(), &target);
        println!(
            "shortest: {:?}; rolled with RK4 (2000 steps): error {err:.1e} rad",
            best.rectangle
        );
    }
    let euler = euler_plan_for_rotation(EulerSet::from_name("3-2-1")?, &target)?;
    println!("3-2-1 three-rectangle plan: error {:.1e} rad", euler.error);
    for p in &euler.rectangles {
        println!("  {:?}, heading {:.4}", p.rectangle, p.heading);
    }
    Ok(())
}
