//! The reports of `holonomy::studies` serialize to the JSON of `rollstack sphere ...
//! --json` (docs/cli.md): these keys, in this order, with these value types.

use holonomy::studies::examples::{rectangle_2_4_10, target_2_4_12};
use holonomy::studies::plan::{euler_plan_report, plan_report, PlanReport};
use holonomy::studies::report::{holonomy_report, HolonomyReport};
use holonomy::studies::roll::{roll_report, ClosedPath, PathShape, RollReport};
use holonomy::{euler_plan, Direction, Integrator, Rectangle};
use rotations::EulerSet;
use serde_json::Value;

fn keys(v: &Value) -> Vec<&str> {
    v.as_object().unwrap().keys().map(String::as_str).collect()
}

#[test]
fn holonomy_report_json() {
    let rep = holonomy_report(&rectangle_2_4_10());
    let text = serde_json::to_string(&rep).unwrap();
    let v: Value = serde_json::from_str(&text).unwrap();
    // serde_json keeps insertion order only with its preserve_order feature; compare sets.
    let mut k = keys(&v);
    k.sort_unstable();
    assert_eq!(
        k,
        [
            "angle",
            "axis",
            "closed_form_error",
            "components_error",
            "e3_final",
            "matrix",
            "no_holonomy",
            "path_length",
            "quaternion",
            "quaternion_closed_form"
        ]
    );
    assert!(text.starts_with("{\"angle\":") && text.ends_with("\"no_holonomy\":null}"));
    // Reads back (to the last bit only with serde_json's float_roundtrip feature).
    let back: HolonomyReport = serde_json::from_str(&text).unwrap();
    assert!((back.angle - rep.angle).abs() < 1e-15 && back.no_holonomy.is_none());
    // A no-holonomy family is written by its name.
    let flat = Rectangle::new(1.0, 0.0, std::f64::consts::TAU, Direction::Ccw).unwrap();
    let text = serde_json::to_string(&holonomy_report(&flat)).unwrap();
    assert!(
        text.ends_with("\"no_holonomy\":\"phi2_multiple_of_two_pi\"}"),
        "{text}"
    );
}

#[test]
fn plan_reports_json() {
    let rep = plan_report(&target_2_4_12().unwrap()).unwrap();
    let text = serde_json::to_string(&rep).unwrap();
    assert!(text.starts_with("{\"rectangles\":[{\"theta\":"));
    assert!(text.contains("\"direction\":\"ccw\""));
    let v: Value = serde_json::from_str(&text).unwrap();
    let mut k = keys(&v["rectangles"][0]);
    k.sort_unstable();
    assert_eq!(
        k,
        [
            "direction",
            "error",
            "heading",
            "path_length",
            "phi1",
            "phi1_free",
            "phi2",
            "theta",
            "waypoints"
        ]
    );
    let back: PlanReport = serde_json::from_str(&text).unwrap();
    assert_eq!(back.rectangles.len(), rep.rectangles.len());
    assert_eq!(back.shortest, rep.shortest);

    let set = EulerSet::from_name("3-1-3").unwrap();
    let e = euler_plan_report(&euler_plan(set, [0.3, 0.5, 0.7]).unwrap());
    let v = serde_json::to_value(&e).unwrap();
    let mut k = keys(&v);
    k.sort_unstable();
    assert_eq!(k, ["angles", "error", "rectangles", "set", "target_matrix"]);
    assert_eq!(v["set"], "3-1-3");
}

#[test]
fn roll_report_json() {
    let closed = ClosedPath::new(&PathShape::Rectangle(rectangle_2_4_10())).unwrap();
    let (rep, _) = roll_report(&closed, Integrator::Rk4, 64).unwrap();
    let text = serde_json::to_string(&rep).unwrap();
    assert!(text.starts_with("{\"angle\":"));
    assert!(text.contains(",\"integrator\":\"rk4\",\"steps\":64,\"path_length\":"));
    assert!(text.contains(",\"wall_time_s\":"));
    let back: RollReport = serde_json::from_str(&text).unwrap();
    assert_eq!((back.integrator, back.steps), (Integrator::Rk4, 64));
}
