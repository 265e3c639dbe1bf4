//! `ellipsoid-core`: a rigid, non-homogeneous ellipsoid on a horizontal plane.
//!
//! SI units throughout (m, kg, s, rad). The physics reference is `docs/physics.md`
//! (shipped as `docs/physics.md`); integrators live in [`integrate`].

// `!(x > 0.0)` is how this crate rejects NaN along with non-positive values.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

pub mod body;
pub mod columns;
pub mod effects;
pub mod error;
pub mod geometry;
pub mod impact;
pub mod integrate;
pub mod invariants;
pub mod kinematics;
pub mod model;
pub mod reference;
pub mod scenario;
pub mod simulate;
pub mod state;
pub mod steady;
