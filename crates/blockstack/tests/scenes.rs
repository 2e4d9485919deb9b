//! The shipped scene files parse, validate and equal the scenario constructors.

use blockstack::scenarios::{
    lire, lire_on_floor, shaking_column, sliding_column, Perturbation, Shaking, Sliding,
};
use blockstack::{BaseMotion, Scene};

fn load(name: &str) -> Scene {
    let path = format!("{}/scenes/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(&path).unwrap();
    Scene::from_toml(&text).unwrap_or_else(|e| panic!("{path}: {e}"))
}

fn same_start(a: &Scene, b: &Scene) {
    let (qa, qb) = (a.initial_coordinates(), b.initial_coordinates());
    assert_eq!(qa.len(), qb.len());
    for (x, y) in qa.iter().zip(&qb) {
        assert!((x - y).abs() < 1e-15, "{x} vs {y}");
    }
    assert_eq!(a.contact, b.contact);
    assert_eq!(a.solver.dt, b.solver.dt);
    assert_eq!(a.solver.t_end, b.solver.t_end);
    assert_eq!(a.base().motion, b.base().motion);
    assert_eq!(a.floor(), b.floor());
    assert_eq!(a.mass_diagonal(), b.mass_diagonal());
}

#[test]
fn lire_file_is_the_maximum_overhang_tower() {
    same_start(&load("lire.toml"), &lire(4, Perturbation::None).unwrap());
}

#[test]
fn lire_file_with_its_floor_uncommented_is_the_landing_scene() {
    let path = format!("{}/scenes/lire.toml", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.contains("\n# [floor]"));
    let scene = Scene::from_toml(&text.replace("\n# [floor]", "\n[floor]")).unwrap();
    same_start(&scene, &lire_on_floor(4, Perturbation::None).unwrap());
}

#[test]
fn shaking_file_is_the_section_4_4_column() {
    let s = load("shaking.toml");
    same_start(
        &s,
        &shaking_column(&Shaking {
            omega: 4.0,
            ..Shaking::default()
        })
        .unwrap(),
    );
    assert_eq!(
        s.base().motion,
        BaseMotion::Harmonic {
            amplitude: 0.2,
            omega: 4.0
        }
    );
}

#[test]
fn slide_file_is_the_section_4_5_column() {
    same_start(
        &load("slide.toml"),
        &sliding_column(&Sliding::default()).unwrap(),
    );
}
