//! A 2D stack of rigid blocks on a driven base (Honein 2024, Ch. 4, App. G, H, I).
#![warn(missing_docs)]
