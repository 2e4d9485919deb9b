//! `rollstack rotation` and `rollstack tour` end to end, checked against rotations built
//! independently with nalgebra (not with the rotations crate the command uses).

use nalgebra::{Matrix3, Rotation3, Unit, UnitQuaternion, Vector3};
use serde_json::Value;
use std::f64::consts::PI;

mod common;

use common::rollstack;

fn convert(from: &str, values: &str) -> Value {
    let out = rollstack(&["rotation", "--from", from, "--values", values, "--json"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON object")
}

fn matrix_of(json: &Value) -> Matrix3<f64> {
    let m = &json["matrix"];
    Matrix3::from_fn(|i, j| m[i][j].as_f64().unwrap())
}

fn vec3(v: &Value) -> [f64; 3] {
    [0, 1, 2].map(|i| v[i].as_f64().unwrap())
}

fn elementary(axis: usize, angle: f64) -> Rotation3<f64> {
    let e = [Vector3::x_axis(), Vector3::y_axis(), Vector3::z_axis()][axis - 1];
    Rotation3::from_axis_angle(&e, angle)
}

/// Every reported representation must describe `expected`.
fn check_all(json: &Value, expected: &Rotation3<f64>) {
    let tol = 1e-12;
    assert!((matrix_of(json) - expected.matrix()).amax() < tol);
    let q = &json["quaternion"];
    let uq = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(
        q[0].as_f64().unwrap(),
        q[1].as_f64().unwrap(),
        q[2].as_f64().unwrap(),
        q[3].as_f64().unwrap(),
    ));
    assert!(q[0].as_f64().unwrap() >= 0.0);
    assert!((uq.to_rotation_matrix().matrix() - expected.matrix()).amax() < tol);
    let [x, y, z] = vec3(&json["axis"]);
    let angle = json["angle"].as_f64().unwrap();
    assert!((0.0..=PI).contains(&angle));
    let aa = Rotation3::from_axis_angle(&Unit::new_normalize(Vector3::new(x, y, z)), angle);
    assert!((aa.matrix() - expected.matrix()).amax() < tol);
    let sets = json["euler"].as_object().unwrap();
    assert_eq!(sets.len(), 12);
    for (name, angles) in sets {
        let ax: Vec<usize> = name.split('-').map(|d| d.parse().unwrap()).collect();
        let a = vec3(angles);
        let r = elementary(ax[0], a[0]) * elementary(ax[1], a[1]) * elementary(ax[2], a[2]);
        assert!((r.matrix() - expected.matrix()).amax() < tol, "set {name}");
    }
}

#[test]
fn from_axis_angle() {
    let axis = Unit::new_normalize(Vector3::new(1.0, -2.0, 0.5));
    let json = convert("axis-angle", "1,-2,0.5,3pi/4");
    check_all(&json, &Rotation3::from_axis_angle(&axis, 0.75 * PI));
    let json = convert("axis-angle", "0,0,2,135deg");
    check_all(
        &json,
        &Rotation3::from_axis_angle(&Vector3::z_axis(), 0.75 * PI),
    );
}

#[test]
fn from_quaternion() {
    let q = UnitQuaternion::from_quaternion(nalgebra::Quaternion::new(0.3, -0.5, 0.1, 0.8));
    let json = convert("quaternion", "0.3,-0.5,0.1,0.8");
    check_all(&json, &q.to_rotation_matrix());
    // (2.2.4): the negated quaternion is the same rotation.
    let neg = convert("quaternion", "-0.3,0.5,-0.1,-0.8");
    assert_eq!(json["matrix"], neg["matrix"]);
}

#[test]
fn from_matrix() {
    let r = elementary(3, 0.4) * elementary(1, -1.2) * elementary(2, 2.0);
    let values: Vec<String> = (0..9)
        .map(|k| format!("{:.17}", r[(k / 3, k % 3)]))
        .collect();
    check_all(&convert("matrix", &values.join(",")), &r);
}

#[test]
fn from_every_euler_set() {
    for set in [
        "3-1-3", "3-2-3", "1-2-1", "1-3-1", "2-1-2", "2-3-2", "3-2-1", "3-1-2", "1-2-3", "1-3-2",
        "2-1-3", "2-3-1",
    ] {
        let ax: Vec<usize> = set.split('-').map(|d| d.parse().unwrap()).collect();
        let expected = elementary(ax[0], 0.5) * elementary(ax[1], -0.3) * elementary(ax[2], 2.0);
        let json = convert(&format!("euler:{set}"), "0.5,-0.3,2");
        check_all(&json, &expected);
    }
}

#[test]
fn singular_euler_angles_are_finite_and_flagged() {
    // A rotation about E3 is at ϑ = 0 of the 3-1-3 set.
    let json = convert("axis-angle", "0,0,1,0.9");
    check_all(&json, &elementary(3, 0.9));
    let singular: Vec<&str> = json["euler_singular"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_str().unwrap())
        .collect();
    assert!(singular.contains(&"3-1-3") && singular.contains(&"3-2-3"));
    assert_eq!(vec3(&json["euler"]["3-1-3"]), [0.0, 0.0, 0.9]);
}

#[test]
fn bad_input_is_one_clear_line() {
    let cases: &[&[&str]] = &[
        &["rotation", "--from", "euler:3-3-1", "--values", "1,2,3"],
        &["rotation", "--from", "euler:4-1-2", "--values", "1,2,3"],
        &["rotation", "--from", "rodrigues", "--values", "1,2,3"],
        &["rotation", "--from", "quaternion", "--values", "1,0,0"],
        &["rotation", "--from", "quaternion", "--values", "0,0,0,0"],
        &["rotation", "--from", "axis-angle", "--values", "0,0,0,1"],
        &["rotation", "--from", "axis-angle", "--values", "0,0,1,NaN"],
        &[
            "rotation",
            "--from",
            "matrix",
            "--values",
            "1,0,0,0,1,0,0,0,-1",
        ],
        &[
            "rotation",
            "--from",
            "matrix",
            "--values",
            "1,0,0,0,1,0,0,0,nan",
        ],
        &["rotation", "--from", "euler:3-1-3", "--values", "1,2,inf"],
        &["tour", "--out", "unused", "--only", "nonsense"],
    ];
    for args in cases {
        let out = rollstack(args);
        assert_eq!(out.status.code(), Some(1), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{err}");
        assert!(!err.contains("panicked"));
        assert!(out.stdout.is_empty());
    }
}

#[test]
fn tour_writes_the_rotation_section() {
    let dir = common::temp_dir("tour-rotations");
    let out = rollstack(&[
        "tour",
        "--out",
        dir.to_str().unwrap(),
        "--only",
        "rotations",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let html = std::fs::read_to_string(dir.join("index.html")).unwrap();
    assert!(html.contains("rotations/holonomy_2_4_10/rotated_basis.png"));
    let png = std::fs::read(dir.join("rotations/holonomy_2_4_10/rotated_basis.png")).unwrap();
    assert_eq!(&png[1..4], b"PNG");
    let csv =
        std::fs::read_to_string(dir.join("rotations/holonomy_2_4_10/euler_angles.csv")).unwrap();
    assert_eq!(csv.lines().count(), 13);
    std::fs::remove_dir_all(dir).unwrap();
}

#[test]
fn a_closed_stdout_is_not_a_panic() {
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_rollstack"))
        .args(["rotation", "--from", "axis-angle", "--values", "0,0,1,1"])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // Close the read end before the child writes.
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
}
