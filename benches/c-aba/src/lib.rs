//! The comparator that issue 14 names for its weight-alone goal: a hand-written planar
//! articulated-body algorithm in C (`aba.c`, Featherstone's Table 7.1 in planar spatial
//! algebra, generic 3 × 3 products, the C library's `sin` and `cos`), for the chain of
//! kanestop's model under its weight alone: the anchor sliding freely along x, the rods and
//! the ship on revolute joints. For benchmarks only (`benches/kernels.rs` times it beside the
//! generated right-hand side, `tests/c_aba.rs` checks it solves the same problem); nothing in
//! the tool depends on it.

use std::ffi::c_double;

/// One body as `aba.c` reads it (its `aba_body`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Mass, kg.
    pub mass: f64,
    /// Moment of inertia about the centroid for rotation about y, kg·m².
    pub inertia: f64,
    /// The centroid from the body's joint in its axes (x, z), m.
    pub centroid: [f64; 2],
    /// The body's joint in the parent's axes (x, z), m; the anchor's in the world's at s = 0.
    pub joint: [f64; 2],
}

/// Doubles of work per body (`ABA_WORK_PER_BODY` of `aba.h`).
const WORK_PER_BODY: usize = 35;

extern "C" {
    fn aba_accelerations(
        n: usize,
        bodies: *const Body,
        g: c_double,
        q: *const c_double,
        u: *const c_double,
        qdd: *mut c_double,
        work: *mut c_double,
    );
}

/// A chain and the C algorithm's work memory.
#[derive(Clone, Debug)]
pub struct Aba {
    bodies: Vec<Body>,
    gravity: f64,
    work: Vec<f64>,
}

impl Aba {
    /// The chain `bodies` (the anchor first, the ship last; at least two) under gravity
    /// `gravity`, m/s².
    pub fn new(bodies: Vec<Body>, gravity: f64) -> Self {
        assert!(bodies.len() >= 2, "a chain of at least an anchor and one hinged body");
        let work = vec![0.0; bodies.len() * WORK_PER_BODY];
        Aba { bodies, gravity, work }
    }

    /// The generalised accelerations in kanestop's order (the joint angles β_1 … β_{N−1},
    /// then the anchor's surge s) at the state `q`, `u` of that order.
    pub fn accelerations(&mut self, q: &[f64], u: &[f64], qdd: &mut [f64]) {
        let n = self.bodies.len();
        assert!(q.len() == n && u.len() == n && qdd.len() == n, "q, u and qdd hold N = {n} entries each");
        // SAFETY: every pointer covers the n entries (n · WORK_PER_BODY for the work) that
        // aba.c reads or writes, checked above and in `new`; the buffers do not overlap.
        unsafe {
            aba_accelerations(
                n,
                self.bodies.as_ptr(),
                self.gravity,
                q.as_ptr(),
                u.as_ptr(),
                qdd.as_mut_ptr(),
                self.work.as_mut_ptr(),
            )
        }
    }
}
