//! Holonomy of a sphere rolling without slipping on a plane (Honein 2024, Ch. 2, App. B, C).
#![warn(missing_docs)]
