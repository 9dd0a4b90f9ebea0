//! The checks every accepted interval must pass: a finite state, an energy balance (Eq. 63)
//! within `solver.max_energy_drift` of its initial value (relative to the largest kinetic
//! energy so far), and joint forces (Eq. 52) below
//! [`SPIKE_FACTOR`] times the line's largest break load. The model has no breaking, so a
//! force that large is numerical, not physical.

use super::failure::FailureKind;
use crate::model::Model;

/// A joint force above this multiple of the largest break load in the line (chain or
/// cable) is a numerical spike: the line would have parted many times over.
pub const SPIKE_FACTOR: f64 = 10.0;

/// Every component of the state y = (q, u, W) is finite.
pub fn finite(y: &[f64]) -> Result<(), FailureKind> {
    if y.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(FailureKind::NonFiniteState)
    }
}

/// The relative drift |E − E_0|/K of the energy balance `balance` (J) from `energy0` (J), when
/// it is finite and at most `limit`. K = `scale` (J) is the largest kinetic energy before the
/// interval checked (E^K, the entrained water's included): the energy in play, which no datum
/// sets, where E_0's potential part is measured from the seabed (in case 1, E_0 = 32.2 MJ
/// against K = 2.25 MJ; docs/model-choices.md). Not the interval's own: energy a blow-up
/// pumps into motion would raise K with it and hide itself. While nothing has moved (K = 0)
/// there is nothing to measure against: a finite balance passes with drift 0.
pub fn energy_drift(balance: f64, energy0: f64, scale: f64, limit: f64) -> Result<f64, FailureKind> {
    let change = (balance - energy0).abs();
    let drift = if scale > 0.0 || !change.is_finite() { change / scale } else { 0.0 };
    if !drift.is_finite() || drift > limit {
        Err(FailureKind::EnergyRunaway { drift, limit, scale })
    } else {
        Ok(drift)
    }
}

/// The force bound of [`no_spike`] for `model`'s line: [`SPIKE_FACTOR`] × the larger of the
/// chain's and the cable's break loads, N.
pub fn spike_bound(model: &Model) -> f64 {
    SPIKE_FACTOR * model.scene.chain.break_load.max(model.scene.cable.break_load)
}

/// The largest joint force |F^H_k| (`tensions[k − 2]`, N) is at most `bound` (N). A spike
/// names its joint; the swinging body is filled in by [`super::Failure::at`].
pub fn no_spike(tensions: &[f64], bound: f64) -> Result<(), FailureKind> {
    let (i, force) = tensions.iter().enumerate().fold((0, 0.0), |best, (i, &t)| if t > best.1 { (i, t) } else { best });
    if force > bound {
        Err(FailureKind::ForceSpike { joint: i + 2, force, bound, swinging: 0 })
    } else {
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_finite_state_passes_and_a_nan_or_infinity_trips() {
        assert_eq!(finite(&[0.0, -1.5, 1e300]), Ok(()));
        assert_eq!(finite(&[0.0, f64::NAN]), Err(FailureKind::NonFiniteState));
        assert_eq!(finite(&[f64::NEG_INFINITY]), Err(FailureKind::NonFiniteState));
    }

    #[test]
    fn energy_within_the_limit_passes_and_a_runaway_trips() {
        // Relative to the kinetic energy, not to E_0: 4 J of 100 J kinetic, E_0 = 1000 J.
        let drift = energy_drift(1004.0, 1000.0, 100.0, 0.05).expect("4 % is within 5 %");
        assert!((drift - 0.04).abs() < 1e-15, "{drift}");
        // A loss counts as much as a gain.
        assert!(energy_drift(996.0, 1000.0, 100.0, 0.05).is_ok());
        match energy_drift(1006.0, 1000.0, 100.0, 0.05) {
            Err(FailureKind::EnergyRunaway { drift, limit, scale }) => {
                assert!((drift - 0.06).abs() < 1e-15 && limit == 0.05 && scale == 100.0, "{drift} {limit}")
            }
            other => panic!("expected a runaway, got {other:?}"),
        }
        // A non-finite balance is a runaway whatever the limit and the scale.
        for scale in [1.0, 0.0] {
            let nan = energy_drift(f64::NAN, 100.0, scale, f64::INFINITY);
            assert!(matches!(nan, Err(FailureKind::EnergyRunaway { .. })), "K = {scale}");
        }
        // Before anything moves there is no scale: a rounding's change of E is no drift.
        assert_eq!(energy_drift(1000.0 + 1e-10, 1000.0, 0.0, 0.05), Ok(0.0));
    }

    #[test]
    fn forces_below_the_bound_pass_and_a_spike_names_its_joint() {
        let tensions = [10.0, 30.0, 20.0];
        assert_eq!(no_spike(&tensions, 30.0), Ok(()));
        // The largest force is at index 1: joint k = 3.
        assert_eq!(
            no_spike(&tensions, 25.0),
            Err(FailureKind::ForceSpike { joint: 3, force: 30.0, bound: 25.0, swinging: 0 })
        );
    }
}
