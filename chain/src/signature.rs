//! The load terms a scene uses: what changes the generated load code (issue 14).

/// Which applied loads a scene has, beyond the weight every body carries (Eq. 40).
///
/// A term a signature does not have is not in the code generated for it. The switches are
/// normalised so that each set of terms has one signature: the current is only seen in
/// water, and the line's sliding friction only on a seabed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LoadSignature {
    /// Water: buoyancy (Eqs. 36, 42), Morison drag on the line (Eqs. 43–47), the anchor's
    /// drag (Eq. 39) and the ship's hydrostatics and resistance (Eqs. 53–62).
    pub water: bool,
    /// The seabed as an elastic foundation under the line (Eq. 41).
    pub seabed: bool,
    /// A current (Eq. 38) of non-zero surface speed.
    pub current: bool,
    /// The grounded line's sliding friction on the seabed.
    pub line_friction: bool,
}

/// A term of the load code, as reports name it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum LoadTerm {
    /// −m g through every centroid (Eq. 40).
    Weight,
    /// The seabed's reaction on the line (Eq. 41).
    Seabed,
    /// The grounded line's sliding friction.
    LineFriction,
    /// Buoyancy of the line and the anchor (Eqs. 36, 42).
    Buoyancy,
    /// The current profile (Eq. 38), read by the drag terms.
    Current,
    /// Morison drag on the line (Eqs. 43–47) and the added mass's power.
    LineDrag,
    /// The anchor's current drag (Eq. 39).
    AnchorDrag,
    /// The ship's heave and pitch hydrostatics (Eqs. 53–58).
    Hydrostatics,
    /// The ship's hull resistance (Eqs. 59–62).
    HullResistance,
}

impl LoadTerm {
    /// Every term, in report order.
    pub const ALL: [LoadTerm; 9] = [
        LoadTerm::Weight,
        LoadTerm::Seabed,
        LoadTerm::LineFriction,
        LoadTerm::Buoyancy,
        LoadTerm::Current,
        LoadTerm::LineDrag,
        LoadTerm::AnchorDrag,
        LoadTerm::Hydrostatics,
        LoadTerm::HullResistance,
    ];

    /// The term's name in reports (`weight`, `seabed`, …).
    pub fn name(self) -> &'static str {
        match self {
            LoadTerm::Weight => "weight",
            LoadTerm::Seabed => "seabed",
            LoadTerm::LineFriction => "line_friction",
            LoadTerm::Buoyancy => "buoyancy",
            LoadTerm::Current => "current",
            LoadTerm::LineDrag => "line_drag",
            LoadTerm::AnchorDrag => "anchor_drag",
            LoadTerm::Hydrostatics => "hydrostatics",
            LoadTerm::HullResistance => "hull_resistance",
        }
    }
}

impl LoadSignature {
    /// The signature of these switches, normalised: `current` counts only with `water`,
    /// `line_friction` only with `seabed`.
    pub fn new(water: bool, seabed: bool, current: bool, line_friction: bool) -> Self {
        LoadSignature { water, seabed, current: current && water, line_friction: line_friction && seabed }
    }

    /// Weight alone: a chain hanging in vacuum.
    pub fn weight_only() -> Self {
        LoadSignature::new(false, false, false, false)
    }

    /// Every distinct signature, dry ones first, in a fixed order (nine in all).
    pub fn all() -> Vec<Self> {
        let mut out = Vec::new();
        for water in [false, true] {
            for current in [false, true] {
                for seabed in [false, true] {
                    for friction in [false, true] {
                        out.push(LoadSignature::new(water, seabed, current, friction));
                    }
                }
            }
        }
        out.sort();
        out.dedup();
        out
    }

    /// Whether `term` is in this signature's load code.
    pub fn has(&self, term: LoadTerm) -> bool {
        match term {
            LoadTerm::Weight => true,
            LoadTerm::Seabed => self.seabed,
            LoadTerm::LineFriction => self.line_friction,
            LoadTerm::Current => self.current,
            LoadTerm::Buoyancy | LoadTerm::LineDrag | LoadTerm::AnchorDrag => self.water,
            LoadTerm::Hydrostatics | LoadTerm::HullResistance => self.water,
        }
    }

    /// The terms this signature has, in report order.
    pub fn terms(&self) -> Vec<LoadTerm> {
        LoadTerm::ALL.into_iter().filter(|&t| self.has(t)).collect()
    }

    /// The name of the generated code: `dry` or `wet`, then `_seabed`, `_friction`,
    /// `_current` for the switches that are on (`wet_seabed_friction_current`).
    pub fn name(&self) -> String {
        let mut s = String::from(if self.water { "wet" } else { "dry" });
        for (on, part) in [(self.seabed, "_seabed"), (self.line_friction, "_friction"), (self.current, "_current")] {
            if on {
                s += part;
            }
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn signatures_are_normalised_and_named_once() {
        let all = LoadSignature::all();
        assert_eq!(all.len(), 9);
        let mut names: Vec<String> = all.iter().map(LoadSignature::name).collect();
        names.sort();
        names.dedup();
        assert_eq!(names.len(), 9);
        assert_eq!(LoadSignature::new(false, false, true, true), LoadSignature::weight_only());
        assert_eq!(LoadSignature::new(true, true, true, true).name(), "wet_seabed_friction_current");
        assert_eq!(LoadSignature::weight_only().terms(), vec![LoadTerm::Weight]);
        assert!(!LoadSignature::new(true, false, false, false).has(LoadTerm::Seabed));
    }
}
