//! The generic reference formulation (paper, Eqs. 1–27).
//!
//! [`general`] is Huston's machinery for an open chain of bodies with six generalised
//! speeds each; [`planar`] uses it for the restraining system, whose only non-zero speeds
//! are the relative rotations about y and the anchor's surge. It never depends on
//! generated code: it is what generated code is checked against.

pub mod general;
pub mod planar;

pub use planar::ReferenceKernel;
