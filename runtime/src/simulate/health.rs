//! The checks every accepted interval must pass: a finite state, an energy balance (Eq. 63)
//! within `solver.max_energy_drift` of its initial value (relative to the largest kinetic
//! energy of the states already checked), and joint forces (Eq. 52) below
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

/// Below this fraction of |E_0| a kinetic energy is no scale for the balance's drift: E is a
/// sum of terms of size |E_0| (its potential part measured from the seabed) and rounds at
/// about 1e-15 |E_0|, which a scale of 1e-9 |E_0| reads as a drift of 1e-6.
pub const SCALE_FLOOR: f64 = 1e-9;

/// The scale K (J) of the energy drift of a state whose kinetic energy is `kinetic` (J), when
/// the largest kinetic energy of the states already checked is `kinetic_max` (J): that
/// largest, not the state's own, since energy a blow-up pumps into motion would raise K with
/// it and hide itself; from rest (`kinetic_max` = 0), the state's own, so that a blow-up from
/// rest has a drift of about 1. At least [`SCALE_FLOOR`] |E_0|.
pub fn drift_scale(kinetic_max: f64, kinetic: f64, energy0: f64) -> f64 {
    let k = if kinetic_max > 0.0 { kinetic_max } else { kinetic };
    k.max(SCALE_FLOOR * energy0.abs())
}

/// The relative drift |E − E_0|/K of the energy balance `balance` (J) from `energy0` (J), when
/// it is finite and at most `limit`. K = `scale` (J, [`drift_scale`]) is a kinetic energy
/// (E^K, the entrained water's included): the energy in play, which no datum sets, where
/// E_0's potential part is measured from the seabed (in case 1, E_0 = 32.2 MJ against
/// K = 2.25 MJ; docs/model-choices.md). With no scale at all (K = 0: nothing moves and
/// E_0 = 0) a finite balance passes with drift 0; a non-finite one is a runaway.
pub fn energy_drift(balance: f64, energy0: f64, scale: f64, limit: f64) -> Result<f64, FailureKind> {
    let change = (balance - energy0).abs();
    let drift = if scale > 0.0 || !change.is_finite() { change / scale } else { 0.0 };
    if !drift.is_finite() || drift > limit {
        Err(FailureKind::EnergyRunaway { drift, limit, scale })
    } else {
        Ok(drift)
    }
}

/// The energy balance's watch over a run: E_0, the scale K and the largest drift so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DriftWatch {
    /// The energy balance at t = 0, J.
    pub energy0: f64,
    /// K: the largest kinetic energy of the states that passed every check, J.
    pub kinetic_max: f64,
    /// The largest finite drift |E − E_0|/K checked, the failing one's included.
    pub max_drift: f64,
}

impl DriftWatch {
    /// The watch from the state at t = 0, its balance `energy0` and kinetic energy `kinetic0`, J.
    pub fn new(energy0: f64, kinetic0: f64) -> Self {
        Self { energy0, kinetic_max: kinetic0, max_drift: 0.0 }
    }

    /// Checks a state of balance `balance` and kinetic energy `kinetic` (J) against `limit`,
    /// then the state's `other` checks; K takes the state in only once it passed them all, so a
    /// blow-up never scales its own drift. The drift that failed is kept as the largest too,
    /// when finite (the failure carries a NaN or an infinity).
    pub fn check(
        &mut self,
        balance: f64,
        kinetic: f64,
        limit: f64,
        other: impl FnOnce() -> Result<(), FailureKind>,
    ) -> Result<(), FailureKind> {
        let scale = drift_scale(self.kinetic_max, kinetic, self.energy0);
        let checked = energy_drift(balance, self.energy0, scale, limit);
        if let Ok(drift) | Err(FailureKind::EnergyRunaway { drift, .. }) = checked {
            if drift.is_finite() && drift > self.max_drift {
                self.max_drift = drift;
            }
        }
        checked?;
        other()?;
        self.kinetic_max = self.kinetic_max.max(kinetic);
        Ok(())
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
        // With no scale at all, a finite change is no drift.
        assert_eq!(energy_drift(1e-10, 0.0, 0.0, 0.05), Ok(0.0));
    }

    #[test]
    fn a_state_raises_k_only_once_it_passed_every_check() {
        let spike = || Err(FailureKind::ForceSpike { joint: 3, force: 1e9, bound: 1e6, swinging: 0 });
        let mut w = DriftWatch::new(3.2e7, 2.0e6);
        // Within the limit, but failing another check: K stays, the drift is kept.
        assert!(matches!(w.check(3.2e7 + 1e3, 5.0e6, 0.005, spike), Err(FailureKind::ForceSpike { .. })));
        assert_eq!((w.kinetic_max, w.max_drift), (2.0e6, 1e3 / 2.0e6));
        // A runaway against K before it: K stays, the drift is the largest.
        assert!(matches!(w.check(3.2e7 + 4e4, 9.0e6, 0.005, || Ok(())), Err(FailureKind::EnergyRunaway { .. })));
        assert_eq!((w.kinetic_max, w.max_drift), (2.0e6, 0.02));
        // A state that passes all: K takes it in; a NaN fails and leaves the largest finite.
        assert_eq!(w.check(3.2e7, 3.0e6, 0.005, || Ok(())), Ok(()));
        assert_eq!(w.kinetic_max, 3.0e6);
        assert!(w.check(f64::NAN, 3.0e6, 0.005, || Ok(())).is_err());
        assert_eq!(w.max_drift, 0.02);
        // From rest, a blow-up's energy in motion is its own scale: a drift of about 1.
        let mut rest = DriftWatch::new(3.2e7, 0.0);
        assert!(rest.check(3.2e7 + 5.0e8, 5.0e8, 0.05, || Ok(())).is_err());
        assert_eq!(rest.kinetic_max, 0.0);
    }

    #[test]
    fn the_drift_scale_is_the_kinetic_energy_before_the_state_or_its_own_from_rest() {
        // Once anything moved, the largest before: a state's own energy does not scale it.
        assert_eq!(drift_scale(2.0e6, 9.0e9, 3.2e7), 2.0e6);
        // From rest, the state's own: a blow-up from rest drifts by about 1 and is caught.
        let blown = drift_scale(0.0, 5.0e8, 3.2e7);
        assert_eq!(blown, 5.0e8);
        assert!(energy_drift(3.2e7 + 5.0e8, 3.2e7, blown, 0.05).is_err());
        // A kinetic energy below rounding's reach is no scale: a rounding's change of E is
        // no drift against the floor, where it would be a runaway against 1e-20 J.
        let k = drift_scale(1e-20, 0.0, 3.2e7);
        assert_eq!(k, SCALE_FLOOR * 3.2e7);
        assert!(energy_drift(3.2e7 + 1e-8, 3.2e7, k, 0.005).unwrap() < 1e-6);
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
