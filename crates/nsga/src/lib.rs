//! Nonsmooth generalized-α time stepping with frictional contact (Capobianco et al. 2021).
#![warn(missing_docs)]
