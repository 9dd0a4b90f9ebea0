//! # kanestop-chain
//!
//! The model of a restraining chain that the generator (`kanestop-codegen`) and the runtime
//! (`kanestop-runtime`) share, as `prost-types` is shared by `prost` and `prost-build`: which
//! bodies the chain has, in Huston's order ([`BodyKind`], [`Topology`]), and the shape of a
//! generated kernel ([`Variant`]) with the parameters it folds to zero ([`StructuralZero`]),
//! and the load terms a scene uses ([`LoadSignature`]), which decide its generated load code.
//!
//! Only *structure* lives here: masses, lengths and forces are numbers the runtime supplies,
//! so one kernel serves every scene of the same shape. The crate depends on nothing of the
//! project's; both sides depend on it, and the runtime never on the generator
//! (docs/architecture.md).
//!
//! ```
//! use kanestop_chain::{BodyKind, Topology, Variant, Water};
//!
//! // The paper's case 1: 15 chain links, cable stages of 3, 12 and 13 elements.
//! let topology = Topology::new(15, vec![3, 12, 13]).unwrap();
//! assert_eq!(topology.body_count(), 46);
//! assert_eq!(topology.kinds()[44], BodyKind::Rod);
//! assert_eq!(Variant::new(46, Water::On).module(), "chain46_wet");
//! ```

#![warn(missing_docs)]

mod signature;
mod topology;
mod variant;

pub use signature::{LoadSignature, LoadTerm};
pub use topology::{BodyKind, Topology, TopologyError};
pub use variant::{ParamField, StructuralZero, Variant, Water};
