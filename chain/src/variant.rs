//! The shape of a generated kernel and the parameters it folds to zero.

use std::fmt;

/// Whether the water's added mass (Eq. 46) enters a_lp.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Water {
    /// No added-mass terms: A_k = m_k 1.
    Off,
    /// Added mass m_a,k n_k n_kᵀ on every rod-like body (B_2 … B_{N−1}).
    On,
}

impl Water {
    /// `dry` or `wet`, as in the kernels' module names.
    pub fn suffix(self) -> &'static str {
        match self {
            Water::Off => "dry",
            Water::On => "wet",
        }
    }
}

/// One kernel shape: N bodies (anchor, N − 3 links or cable elements, rod, ship) and the
/// water switch. Masses, lengths and inertias are runtime parameters.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Variant {
    /// N, the number of bodies (≥ 3).
    pub bodies: usize,
    /// Whether the added mass enters a_lp.
    pub water: Water,
}

/// A body parameter that a kernel may fold to zero.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ParamField {
    /// r_k,z: the centroid's height in body axes, zero on a rod-like body.
    CentroidZ,
    /// q_k,z: the joint's height in the inner body's axes, zero from B_3 on.
    JointZ,
    /// m_a,k: the added mass (Eq. 46), zero off the rod-like bodies or with the water off.
    AddedMass,
}

impl fmt::Display for ParamField {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            ParamField::CentroidZ => "centroid[1]",
            ParamField::JointZ => "joint[1]",
            ParamField::AddedMass => "added_mass",
        })
    }
}

/// A parameter folded to zero in a kernel: body `body` (0-based, B_{body+1}), `field`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct StructuralZero {
    /// 0-based body index.
    pub body: usize,
    /// Which parameter.
    pub field: ParamField,
}

impl Variant {
    /// The shape with `bodies` bodies; `None` below 3 (an anchor, a rod and a ship).
    pub fn try_new(bodies: usize, water: Water) -> Option<Self> {
        (bodies >= 3).then_some(Variant { bodies, water })
    }

    /// The shape with `bodies` bodies.
    ///
    /// # Panics
    /// When `bodies < 3`; [`Variant::try_new`] returns `None` instead.
    pub fn new(bodies: usize, water: Water) -> Self {
        Self::try_new(bodies, water).expect("a chain has at least an anchor, one rod and a ship")
    }

    /// Module name, e.g. `chain46_dry`.
    pub fn module(&self) -> String {
        format!("chain{}_{}", self.bodies, self.water.suffix())
    }

    /// True for the bodies modelled as slender rods (B_2 … B_{N−1}, 0-based 1 … N−2).
    pub fn is_rod_like(&self, body: usize) -> bool {
        body > 0 && body + 1 < self.bodies
    }

    /// Whether a kernel of this shape folds `field` of body `body` (0-based) to zero.
    pub fn folds(&self, body: usize, field: ParamField) -> bool {
        match field {
            ParamField::CentroidZ => self.is_rod_like(body),
            ParamField::JointZ => body >= 2,
            ParamField::AddedMass => !(self.is_rod_like(body) && self.water == Water::On),
        }
    }

    /// Every parameter a kernel of this shape folds to zero, body by body: what a chain must
    /// satisfy to use it.
    pub fn structural_zeros(&self) -> impl Iterator<Item = StructuralZero> + '_ {
        (0..self.bodies).flat_map(move |body| {
            [ParamField::CentroidZ, ParamField::JointZ, ParamField::AddedMass]
                .into_iter()
                .filter(move |&field| self.folds(body, field))
                .map(move |field| StructuralZero { body, field })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zeros_of_a_small_wet_chain() {
        // B_1 anchor, B_2 … B_4 rod-like, B_5 ship.
        let v = Variant::new(5, Water::On);
        let zeros: Vec<(usize, String)> = v.structural_zeros().map(|z| (z.body, z.field.to_string())).collect();
        let expected = [
            (0, "added_mass"),
            (1, "centroid[1]"),
            (2, "centroid[1]"),
            (2, "joint[1]"),
            (3, "centroid[1]"),
            (3, "joint[1]"),
            (4, "joint[1]"),
            (4, "added_mass"),
        ];
        assert_eq!(zeros, expected.map(|(k, f)| (k, f.to_string())));
    }

    #[test]
    fn dry_chains_fold_every_added_mass() {
        let v = Variant::new(4, Water::Off);
        assert!((0..4).all(|k| v.folds(k, ParamField::AddedMass)));
        assert!(!Variant::new(4, Water::On).folds(1, ParamField::AddedMass));
    }

    #[test]
    fn fewer_than_three_bodies_is_no_shape() {
        assert_eq!(Variant::try_new(2, Water::Off), None);
        assert_eq!(Variant::try_new(3, Water::Off).map(|v| v.module()), Some("chain3_dry".to_string()));
    }
}
