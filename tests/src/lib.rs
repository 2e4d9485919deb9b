//! Cross-crate acceptance tests of rollstack against the thesis; the tests live in
//! `tests/tests/`. They use the crates as a user would, through their public APIs:
//!
//! ```
//! use rotations::EulerSet;
//!
//! // App. A: a 3-1-3 rotation by (ψ, ϑ, φ) turns E3 into e3 = sin ϑ sin ψ E1 − … .
//! let r = EulerSet::from_name("3-1-3").unwrap().rotation([0.3, 0.9, -1.4]);
//! let e3 = r * nalgebra::Vector3::z();
//! assert!((e3.z - 0.9_f64.cos()).abs() < 1e-15);
//! ```
#![warn(missing_docs)]
