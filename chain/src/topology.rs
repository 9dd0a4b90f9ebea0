//! Which bodies the chain has, in Huston's order.
//!
//! Body B_1 is the gravity anchor, then the chain links, the cable elements stage by stage,
//! the auxiliary rod B_{N-1} and the ship B_N (paper, Section 2.3.1). Only the *structure*
//! lives here; masses, lengths and forces are numbers the runtime supplies, so one kernel
//! serves every scene with the same structure.

use std::fmt;

/// What a body of the chain is. The kind decides its inertia form (Eq. 18) and which
/// forces can act on it (Section 3.2).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum BodyKind {
    /// B_1: a cuboid that can only translate along the seabed (assumption 5).
    Anchor,
    /// A studless chain link modelled as a homogeneous rod.
    ChainLink,
    /// A restraining-cable element of the given stage (0-based).
    Cable {
        /// The stage, 0-based from the chain toward the ship.
        stage: usize,
    },
    /// B_{N-1}: the auxiliary rod that replaces the net, above the water.
    Rod,
    /// B_N: the ship, a cuboid hinged to the rod.
    Ship,
}

impl BodyKind {
    /// True for the bodies modelled as slender homogeneous rods (Eq. 18, middle case).
    pub fn is_rod_like(self) -> bool {
        matches!(self, BodyKind::ChainLink | BodyKind::Cable { .. } | BodyKind::Rod)
    }
}

impl fmt::Display for BodyKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            BodyKind::Anchor => write!(f, "anchor"),
            BodyKind::ChainLink => write!(f, "chain link"),
            BodyKind::Cable { stage } => write!(f, "cable stage {}", stage + 1),
            BodyKind::Rod => write!(f, "auxiliary rod"),
            BodyKind::Ship => write!(f, "ship"),
        }
    }
}

/// The structure of a restraining chain: anchor, `chain_links` links, the cable stages,
/// the auxiliary rod and the ship.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub struct Topology {
    /// Number of chain links (paper: 15).
    pub chain_links: usize,
    /// Number of elements in each cable stage, from the chain toward the ship
    /// (paper, case 1: 3, 12, 13).
    pub cable_stages: Vec<usize>,
}

/// A topology that cannot describe a chain.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TopologyError {
    /// No cable stage, or a stage with no element.
    #[error("the cable needs at least one stage, each with at least one element")]
    EmptyCable,
}

impl Topology {
    /// A topology, checked: every cable stage must hold at least one element.
    pub fn new(chain_links: usize, cable_stages: Vec<usize>) -> Result<Self, TopologyError> {
        if cable_stages.is_empty() || cable_stages.contains(&0) {
            return Err(TopologyError::EmptyCable);
        }
        Ok(Topology { chain_links, cable_stages })
    }

    /// N, the number of bodies (anchor + links + cable elements + rod + ship).
    pub fn body_count(&self) -> usize {
        1 + self.chain_links + self.cable_elements() + 2
    }

    /// Total number of cable elements over all stages.
    pub fn cable_elements(&self) -> usize {
        self.cable_stages.iter().sum()
    }

    /// The kind of every body, B_1 first.
    pub fn kinds(&self) -> Vec<BodyKind> {
        let mut kinds = Vec::with_capacity(self.body_count());
        kinds.push(BodyKind::Anchor);
        kinds.extend(std::iter::repeat_n(BodyKind::ChainLink, self.chain_links));
        for (stage, &count) in self.cable_stages.iter().enumerate() {
            kinds.extend(std::iter::repeat_n(BodyKind::Cable { stage }, count));
        }
        kinds.push(BodyKind::Rod);
        kinds.push(BodyKind::Ship);
        kinds
    }

    /// Number of generalised speeds with the anchor free: N-1 relative rotations about y
    /// plus the anchor surge (Eq. 27). With the anchor stuck the last one is dropped.
    pub fn speed_count(&self) -> usize {
        self.body_count()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn paper_case_one_has_46_bodies_in_paper_order() {
        let t = Topology::new(15, vec![3, 12, 13]).unwrap();
        assert_eq!(t.body_count(), 46);
        let kinds = t.kinds();
        assert_eq!(kinds[0], BodyKind::Anchor);
        assert_eq!(kinds[1], BodyKind::ChainLink);
        assert_eq!(kinds[15], BodyKind::ChainLink);
        assert_eq!(kinds[16], BodyKind::Cable { stage: 0 });
        assert_eq!(kinds[19], BodyKind::Cable { stage: 1 });
        assert_eq!(kinds[31], BodyKind::Cable { stage: 2 });
        assert_eq!(kinds[44], BodyKind::Rod);
        assert_eq!(kinds[45], BodyKind::Ship);
    }

    #[test]
    fn empty_stage_is_rejected() {
        assert_eq!(Topology::new(15, vec![3, 0]), Err(TopologyError::EmptyCable));
        assert_eq!(Topology::new(15, vec![]), Err(TopologyError::EmptyCable));
    }
}
