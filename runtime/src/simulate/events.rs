//! Event location: the switching functions of the run's two kinds of event and the
//! bisection that finds where one first holds inside a step, to round-off.
//!
//! - the anchor's stick–slip switch (discussion after Eq. 26 and Eq. 37): held until the
//!   holding force exceeds μN (`releases`), then sliding with friction −μN until its
//!   velocity returns to zero (`reversed`);
//! - the ship stopping: the first zero of its surge velocity (`ship_stopped`).

use super::observe::Observation;
use crate::integrate::{Integrator, OdeSystem, StepError};

/// Bisection stops when the bracket is below this fraction of the step.
const RELATIVE_BRACKET: f64 = 1e-12;

/// Bisection halvings at most (2⁻⁶⁰ ≈ 1e-18: the bracket test ends it first).
const MAX_HALVINGS: usize = 60;

/// Static friction is exceeded: |H| > μN (Eq. 37 and the discussion after Eq. 26).
pub(crate) fn releases(obs: &Observation, mu: f64) -> bool {
    obs.reaction.holding.abs() > mu * obs.reaction.normal.max(0.0)
}

/// The sliding anchor's velocity has come to rest or reversed against `direction` (±1).
pub(crate) fn reversed(obs: &Observation, direction: f64) -> bool {
    obs.anchor_vx() * direction <= 0.0
}

/// The ship's surge velocity has reached zero.
pub(crate) fn ship_stopped(obs: &Observation) -> bool {
    obs.ship_vx() <= 0.0
}

/// Integrates from (t, y0) over h: one fixed step, or error-controlled sub-steps of an
/// adaptive method. A method's cached derivatives are keyed by (t, y), so a bisection
/// restarting from y0 reuses them.
pub(crate) fn advance<S: OdeSystem>(
    integrator: &mut dyn Integrator,
    system: &mut S,
    t: f64,
    y0: &[f64],
    h: f64,
) -> Result<Vec<f64>, StepError> {
    let mut y = y0.to_vec();
    integrator.step(system, t, &mut y, h)?;
    Ok(y)
}

/// A located event: its offset from the step's start (s), the state there and what was
/// observed of it.
pub(crate) type Located<T> = (f64, Vec<f64>, T);

/// Bisects (0, h] for the first sub-step at which `g` (of what `observe` makes of a state)
/// holds; (h, y(t + h), ·) when it holds nowhere inside.
///
/// A method with a continuous extension (DP5, SDIRK4) integrates [t, t + h] once and is
/// probed on its interpolants, to their accuracy (one observation per probe); RK4
/// re-integrates from (t, y0) to each probe, so the event falls on a step of its own.
pub(crate) fn locate<S: OdeSystem, T, E: From<StepError>>(
    integrator: &mut dyn Integrator,
    system: &mut S,
    (t, y0, h): (f64, &[f64], f64),
    mut observe: impl FnMut(&mut S, &[f64]) -> Result<T, E>,
    g: impl Fn(&T) -> bool,
) -> Result<Located<T>, E> {
    let y_end = advance(integrator, system, t, y0, h)?;
    let mut y = y_end.clone();
    let dense = integrator.dense_state(t + h, &mut y);
    let (mut lo, mut hi) = (0.0, h);
    let mut best = None;
    for _ in 0..MAX_HALVINGS {
        let mid = 0.5 * (lo + hi);
        if !(dense && integrator.dense_state(t + mid, &mut y)) {
            y = advance(integrator, system, t, y0, mid)?;
        }
        let obs = observe(system, &y)?;
        if g(&obs) {
            hi = mid;
            best = Some((mid, y.clone(), obs));
        } else {
            lo = mid;
        }
        if hi - lo <= RELATIVE_BRACKET * h.max(1e-300) {
            break;
        }
    }
    match best {
        Some(b) => Ok(b),
        None => {
            let obs = observe(system, &y_end)?;
            Ok((h, y_end, obs))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::energy::Energy;
    use crate::integrate::{Adaptive, Dp5, RhsError, Rk4, Sdirk4};
    use crate::kernel::{AnchorReaction, BodyState};

    /// A projectile: x' = v, v' = −1 from x = 0, v = 1, so x = t − t²/2, zero at t = 2.
    /// Its solution is a quadratic, which RK4, DP5's interpolant and SDIRK4's cubic Hermite
    /// reproduce exactly: the located zero is exact to round-off.
    struct Projectile;
    impl OdeSystem for Projectile {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
            dy[0] = y[1];
            dy[1] = -1.0;
            Ok(())
        }
    }

    /// An oscillator: x'' = −x from x = 1, v = 0, so x = cos t, zero at π/2.
    struct Oscillator;
    impl OdeSystem for Oscillator {
        fn dim(&self) -> usize {
            2
        }
        fn rhs(&mut self, _t: f64, y: &[f64], dy: &mut [f64]) -> Result<(), RhsError> {
            dy[0] = y[1];
            dy[1] = -y[0];
            Ok(())
        }
    }

    /// The first time in [t0, t0 + h] where x ≤ 0, from the state at t0.
    fn zero_of_x(integrator: &mut dyn Integrator, system: &mut impl OdeSystem, t0: f64, y0: &[f64], h: f64) -> f64 {
        let observe = |_: &mut _, y: &[f64]| Ok::<f64, StepError>(y[0]);
        let (dt, y, x) = locate(integrator, system, (t0, y0, h), observe, |x| *x <= 0.0).expect("located");
        assert_eq!(x, y[0]);
        t0 + dt
    }

    fn projectile_at(t: f64) -> [f64; 2] {
        [t - 0.5 * t * t, 1.0 - t]
    }

    #[test]
    fn rk4_locates_the_zero_of_a_quadratic_to_round_off() {
        let t = zero_of_x(&mut Rk4::new(2), &mut Projectile, 1.9, &projectile_at(1.9), 0.25);
        assert!((t - 2.0).abs() < 1e-12, "{t}");
    }

    #[test]
    fn dense_output_locates_the_zero_of_a_quadratic_to_round_off() {
        let dp5 = Dp5::new(2, 1e-8, 1e-10).expect("tolerances");
        let t = zero_of_x(&mut Adaptive::new(dp5), &mut Projectile, 1.9, &projectile_at(1.9), 0.25);
        assert!((t - 2.0).abs() < 1e-12, "DP5 {t}");
        let sdirk = Sdirk4::new(2, 1e-8, 1e-10).expect("tolerances");
        let t = zero_of_x(&mut Adaptive::new(sdirk), &mut Projectile, 1.9, &projectile_at(1.9), 0.25);
        assert!((t - 2.0).abs() < 1e-10, "SDIRK4 {t}");
    }

    #[test]
    fn the_zero_of_a_cosine_is_found_to_the_methods_accuracy() {
        let half_pi = std::f64::consts::FRAC_PI_2;
        let y0 = [1.5f64.cos(), -1.5f64.sin()];
        let t = zero_of_x(&mut Rk4::new(2), &mut Oscillator, 1.5, &y0, 0.1);
        // RK4's error over one step of ≤ 0.1 is below 0.1⁵/120 ≈ 1e-7.
        assert!((t - half_pi).abs() < 1e-7, "RK4 {t}");
        let dp5 = Dp5::new(2, 1e-11, 1e-13).expect("tolerances");
        let t = zero_of_x(&mut Adaptive::new(dp5), &mut Oscillator, 1.5, &y0, 0.1);
        assert!((t - half_pi).abs() < 1e-9, "DP5 {t}");
    }

    #[test]
    fn no_event_inside_the_step_returns_its_end() {
        let observe = |_: &mut _, y: &[f64]| Ok::<f64, StepError>(y[0]);
        let (dt, y, _) =
            locate(&mut Rk4::new(2), &mut Projectile, (0.0, &[0.0, 1.0], 0.5), observe, |x| *x <= 0.0).unwrap();
        assert_eq!(dt, 0.5);
        assert!((y[0] - 0.375).abs() < 1e-15, "{y:?}");
    }

    fn observation(anchor_vx: f64, ship_vx: f64, reaction: AnchorReaction) -> Observation {
        let body = |vx| BodyState { vx, ..BodyState::default() };
        Observation {
            bodies: vec![body(anchor_vx), body(0.0), body(ship_vx)],
            tensions: vec![0.0; 2],
            reaction,
            energy: Energy::default(),
        }
    }

    #[test]
    fn the_switching_functions() {
        let pull = |holding, normal| observation(0.0, 1.0, AnchorReaction { holding, normal });
        // μN = 0.5 × 100 N: 60 N releases, 40 N (either sign) holds, a lifting N holds nothing.
        assert!(releases(&pull(60.0, 100.0), 0.5) && releases(&pull(-60.0, 100.0), 0.5));
        assert!(!releases(&pull(40.0, 100.0), 0.5) && !releases(&pull(-40.0, 100.0), 0.5));
        assert!(releases(&pull(1e-9, -5.0), 0.5));
        let moving = |vx| observation(vx, 1.0, AnchorReaction::default());
        assert!(!reversed(&moving(0.2), 1.0) && reversed(&moving(0.0), 1.0) && reversed(&moving(-0.1), 1.0));
        assert!(reversed(&moving(0.2), -1.0) && !reversed(&moving(-0.2), -1.0));
        let ship = |vx| observation(0.0, vx, AnchorReaction::default());
        assert!(!ship_stopped(&ship(0.1)) && ship_stopped(&ship(0.0)) && ship_stopped(&ship(-1e-12)));
    }
}
