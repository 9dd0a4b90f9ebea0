//! # kanestop-codegen
//!
//! The build-time generator of kanestop: it expands the planar Kane quantities of a
//! restraining chain (Huston's form of Kane's method, Liu et al., Eqs. 1–27) into flat,
//! specialised Rust kernels.
//!
//! The generator is an ordinary library with a small, explicit input model,
//! [`topology::Topology`]: the body kinds in chain order and the counts per stage. The same
//! type describes the chain to the runtime, so the generator and the runtime can never
//! disagree about which body is which.

pub mod topology;

pub use topology::{BodyKind, Topology, TopologyError};
