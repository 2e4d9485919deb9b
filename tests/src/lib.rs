//! Cross-crate acceptance tests of rollstack against the thesis; the tests live in `tests/tests/`.
#![warn(missing_docs)]
