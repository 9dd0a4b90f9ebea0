//! The loads a kernel can compute in its own code: a scene's load signature and the numbers
//! its generated load code reads (issue 14; docs/codegen.md, "Loads fused into the kernel").
//!
//! The force modules (`forces`) stay the oracle and never name generated code; `Dynamics`
//! fills this from them ([`crate::dynamics::Dynamics::new`]) and offers it to the kernel
//! ([`crate::kernel::Kernel::fuse_loads`]).

use kanestop_chain::LoadSignature;
use kanestop_generated::{Element, LoadParams};

/// A scene's loads as the generated load code takes them.
#[derive(Clone, Debug)]
pub struct FusedLoads {
    /// Which terms the scene has.
    pub signature: LoadSignature,
    /// The scene's numbers.
    pub params: LoadParams,
    /// Every body's length, radius, whether it is a line element and the products of its
    /// numbers the load code reads ([`Element::new`]), B_1 first.
    pub elements: Vec<Element>,
}
