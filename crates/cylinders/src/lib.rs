//! Inclined cylinders rolling on one rim point (Honein 2024, Ch. 3, App. D, E, F).
#![warn(missing_docs)]
