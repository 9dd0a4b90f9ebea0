//! The joint forces (Eq. 52) in Newton's form: the force on B_k from B_{k−1} balances the
//! inertia of the bodies outboard of the hinge (their added mass included, Eq. 46) less the
//! loads applied to them. It needs the body accelerations (Eq. 17) of a solve.
//!
//! A recursive solve has the same forces in its rows ([`crate::kernel::Kernel::joint_forces`]:
//! the articulated-body recursion's force through each hinge); this form serves the kernels
//! that keep none (the reference, the unrolled kernels) and is the oracle of the other.

use crate::chain::Chain;
use crate::kernel::{BodyAcceleration, BodyState, Load};

/// `out[k − 2]` = [F_x, F_z] (N), the force on B_k from B_{k−1}, k = 2 … N, from the body
/// states, accelerations and applied loads of one solve, summed from the ship inward.
pub fn from_accelerations(
    chain: &Chain,
    bodies: &[BodyState],
    acc: &[BodyAcceleration],
    loads: &[Load],
    out: &mut [[f64; 2]],
) {
    let n = chain.len();
    assert!(
        out.len() + 1 >= n && bodies.len() >= n && acc.len() >= n && loads.len() >= n,
        "the states, accelerations and loads of N = {n} bodies and N − 1 joints"
    );
    let mut sum = [0.0, 0.0];
    for k in (1..n).rev() {
        let (b, a, l, s) = (&chain.bodies[k], &acc[k], &loads[k], &bodies[k]);
        let (sin, cos) = (s.sin, s.cos);
        // The added mass acts across the body axis: on the acceleration's normal component.
        let a_n = a.ax * sin + a.az * cos;
        sum[0] += b.mass * a.ax + b.added_mass * a_n * sin - l.fx;
        sum[1] += b.mass * a.az + b.added_mass * a_n * cos - l.fz;
        out[k - 1] = sum;
    }
}

/// |F|, the tension a joint carries (N); no overflow below 1e150 N.
pub fn magnitude(f: [f64; 2]) -> f64 {
    (f[0] * f[0] + f[1] * f[1]).sqrt()
}
