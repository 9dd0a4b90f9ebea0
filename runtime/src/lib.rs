//! # kanestop-runtime
//!
//! Everything between a scene file and a report, in the order data flows:
//!
//! scene ([`scene`], [`paper`]) → topology and model ([`model`], [`chain`], [`catenary`], [`geometry`])
//! → kernel ([`kernel`]: the [`reference`](mod@reference) formulation, or generated code) with the
//! applied loads ([`forces`]) → right-hand side ([`dynamics`], its [`stability`] limit) → integrator
//! ([`integrate`]) → results ([`simulate`], [`energy`]) → reports ([`eval`]).
//!
//! Equation numbers refer to Liu, Hearn, Chen, Jiang & Wu, "Analysis of Dynamic Response of
//! a Restraining System for a Powerless Advancing Ship Based on the Kane Method".

#![warn(missing_docs)]

pub mod catenary;
pub mod chain;
pub mod contact;
pub mod design;
pub mod dynamics;
pub mod energy;
pub mod eval;
pub mod forces;
pub mod fusion;
pub mod generated;
pub mod geometry;
pub mod integrate;
pub mod joints;
pub mod kernel;
pub mod model;
pub mod overrides;
pub mod paper;
pub mod reference;
pub mod scene;
pub mod simulate;
pub mod stability;
