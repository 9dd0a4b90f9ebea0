//! The checks every accepted interval must pass: a finite state, an energy balance (Eq. 63)
//! within `solver.max_energy_drift` of its initial value (relative to the largest kinetic
//! energy of the states already checked), and joint forces (Eq. 52) below
//! [`SPIKE_FACTOR`] times the line's largest break load. The model has no breaking, so a
//! force that large is numerical, not physical. Under RK4's fixed step, also tensions that
//! chatter from step to step ([`ChatterWatch`]): a mode the step no longer resolves.

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

/// A tension is rough at a step when its second difference over the last three steps,
/// |T_n − 2T_{n−1} + T_{n−2}|, exceeds this fraction of the largest of the three (or of
/// [`CHATTER_FLOOR`] × the line's smaller break load, whichever is larger). A tension the
/// step resolves changes little from one step to the next: on the paper's 19 cases and the
/// stress scenes at their own steps (RK4, dt = 2 ms, per step) the largest such ratio is 0.38
/// (at an anchor switch) and 0.67 once on k_z × 100, 0.005 in 99.9 % of the steps; RK4 a
/// little inside the limit of a mode that stiffened after t = 0 reaches 2 (an oscillation
/// with a period of a few steps).
pub const CHATTER_RATIO: f64 = 0.5;

/// Below this fraction of the line's smaller break load a change of tension is no roughness:
/// it matters to no design check (a slack element's few newtons).
pub const CHATTER_FLOOR: f64 = 0.01;

/// The window of steps the rough ones are counted in.
pub const CHATTER_WINDOW: u32 = 50;

/// A run whose tensions are rough at this many of the last [`CHATTER_WINDOW`] steps chatters.
/// An isolated rough step (an anchor switch, a slack element snapping taut) is physics the
/// step follows; a run of them is the step at the edge of a mode it no longer resolves, its
/// tensions and peaks noise. Measured per step: at most 1 of 50 on the paper's cases and the
/// stress scenes; 19–22 of 50 on k_z × 1e4 at dt = 0.8 and 1 ms (limit at t = 0: 1.69 ms),
/// whose peak tension came out at 691 and 1 933 kN against 433 kN at 0.5 ms and under DP5.
pub const CHATTER_STEPS: u32 = 10;

/// Watches RK4's joint tensions step by step for chatter ([`CHATTER_STEPS`] rough steps of
/// the last [`CHATTER_WINDOW`]). It takes the states after each step, not the one at t = 0:
/// the first second difference is at the third step.
#[derive(Clone, Debug)]
pub struct ChatterWatch {
    /// The tensions of the two steps before the last checked, and of the last (N); empty
    /// until there were such steps (the first two have no second difference).
    before: Vec<f64>,
    last: Vec<f64>,
    /// Bit i: whether the i-th latest step was rough, for the last [`CHATTER_WINDOW`] steps.
    rough: u64,
    /// The smallest change of tension counted, N.
    floor: f64,
    /// Steps checked, and the first of them that was rough (its count then).
    steps: u64,
    first_rough: Option<u64>,
}

const _: () = assert!(CHATTER_WINDOW < 64, "the window is a u64's low bits");

impl ChatterWatch {
    /// A watch for a line whose smaller break load (chain or cable) is `break_load`, N.
    pub fn new(break_load: f64) -> Self {
        let floor = CHATTER_FLOOR * break_load;
        ChatterWatch { before: Vec::new(), last: Vec::new(), rough: 0, floor, steps: 0, first_rough: None }
    }

    /// The watch for `model`'s line.
    pub fn for_model(model: &Model) -> Self {
        Self::new(model.scene.chain.break_load.min(model.scene.cable.break_load))
    }

    /// Takes the tensions |F^H_k| (`tensions[k − 2]`, N) of the next step: a chatter names
    /// the joint rough at this step whose second difference is the largest against its scale.
    pub fn check(&mut self, tensions: &[f64]) -> Result<(), FailureKind> {
        let mut worst: Option<(usize, f64)> = None;
        if self.before.len() == tensions.len() && self.last.len() == tensions.len() {
            for (i, ((&t, &t1), &t2)) in tensions.iter().zip(&self.last).zip(&self.before).enumerate() {
                let scale = t.abs().max(t1.abs()).max(t2.abs()).max(self.floor);
                let ratio = (t - 2.0 * t1 + t2).abs() / scale;
                if ratio > CHATTER_RATIO && !matches!(worst, Some((_, r)) if r >= ratio) {
                    worst = Some((i, ratio));
                }
            }
        }
        std::mem::swap(&mut self.before, &mut self.last);
        self.last.clear();
        self.last.extend_from_slice(tensions);
        self.rough = ((self.rough << 1) | u64::from(worst.is_some())) & ((1u64 << CHATTER_WINDOW) - 1);
        self.steps += 1;
        if worst.is_some() && self.first_rough.is_none() {
            self.first_rough = Some(self.steps);
        }
        let rough = self.rough.count_ones();
        match worst {
            Some((i, ratio)) if rough >= CHATTER_STEPS => Err(FailureKind::TensionChatter {
                joint: i + 2,
                ratio,
                rough,
                window: CHATTER_WINDOW,
                first_rough: self.steps - self.first_rough.unwrap_or(self.steps),
            }),
            _ => Ok(()),
        }
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

    #[test]
    fn smooth_or_once_rough_tensions_pass_and_a_chatter_names_its_joint() {
        // Three joints; the line's smaller break load 1e6 N (floor 1e4 N).
        let mut w = ChatterWatch::new(1e6);
        // A smooth rise, then one jump (an anchor switch) and back to smooth: no chatter,
        // however long.
        for i in 0..200 {
            let jump = if i >= 100 { 3e5 } else { 0.0 };
            assert_eq!(w.check(&[1e5 + 1e3 * i as f64 + jump, 2e5, 5e4]), Ok(()), "step {i}");
        }
        // Tiny tensions alternating (a slack element's newtons) stay under the floor.
        let mut slack = ChatterWatch::new(1e6);
        for i in 0..200 {
            assert_eq!(slack.check(&[1e5, if i % 2 == 0 { 10.0 } else { 2000.0 }]), Ok(()), "step {i}");
        }
        // Joint 3 (index 1) alternating between 1e5 and 3e5 N: rough from the third step on
        // (i = 2), a chatter once 10 of the last 50 steps were rough (i = 11), naming joint 3
        // and the run's first rough step, 9 steps back.
        let mut c = ChatterWatch::new(1e6);
        let mut failed = None;
        for i in 0..60 {
            let t = if i % 2 == 0 { 1e5 } else { 3e5 };
            if let Err(e) = c.check(&[2e5, t, 2e5 + 1e3 * i as f64]) {
                failed = Some((i, e));
                break;
            }
        }
        let Some((step, FailureKind::TensionChatter { joint, ratio, rough, window, first_rough })) = failed else {
            panic!("expected a chatter, got {failed:?}")
        };
        assert_eq!((step, joint, rough, window, first_rough), (11, 3, CHATTER_STEPS, CHATTER_WINDOW, 9));
        // |1e5 − 6e5 + 1e5| / 3e5 (or the other phase: |3e5 − 2e5 + 3e5| / 3e5).
        assert!((ratio - 4.0 / 3.0).abs() < 1e-12, "{ratio}");
        // Rough steps spread thinner than 10 in 50 pass: a spike every 30 steps roughens the
        // three steps whose second difference holds it, 6 of any 50.
        let mut sparse = ChatterWatch::new(1e6);
        for i in 0..600 {
            let t = if i % 30 == 0 { 4e5 } else { 1e5 };
            assert_eq!(sparse.check(&[t]), Ok(()), "step {i}");
        }
    }

    #[test]
    fn a_rough_step_counts_for_exactly_the_window() {
        // A lone spike (4e5 N in 1e5 N) roughens exactly three steps: its own and the next
        // two. Spikes at steps 10, 20 and 30 give 9 rough steps; a fourth spike chatters
        // while step 10 is among the last 50 (step 59: 49 back) and not a step later.
        let first_chatter = |spikes: &[usize]| -> Option<(usize, FailureKind)> {
            let mut w = ChatterWatch::new(1e6);
            (0..100).find_map(|i| {
                let t = if spikes.contains(&i) { 4e5 } else { 1e5 };
                w.check(&[t]).err().map(|e| (i, e))
            })
        };
        let Some((59, FailureKind::TensionChatter { rough: 10, first_rough: 49, .. })) =
            first_chatter(&[10, 20, 30, 59])
        else {
            panic!("{:?}", first_chatter(&[10, 20, 30, 59]))
        };
        assert_eq!(first_chatter(&[10, 20, 30, 60]), None, "step 10 has left the window");
        // The run's first rough step is named even when it left the window long ago.
        let Some((89, FailureKind::TensionChatter { first_rough: 84, .. })) = first_chatter(&[5, 50, 60, 70, 89])
        else {
            panic!("{:?}", first_chatter(&[5, 50, 60, 70, 89]))
        };
    }
}
