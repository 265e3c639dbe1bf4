//! The output columns, declared once in the core ([`ellipsoid_core::columns`]).
pub use ellipsoid_core::columns::*;
