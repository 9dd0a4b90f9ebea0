//! The numeric description of the chain: one [`Body`] per rigid body B_1 … B_N with its
//! mass, central inertia (Eq. 18), centroid r_k and joint point q_k (Eq. 13).
//!
//! Frames follow the paper (Section 2.3.1): x along the body toward the ship, z up for the
//! boxes and perpendicular to x for the rods, y = z × x into the page. Every vector stored
//! here is planar (x, z): the y components are zero by construction.

use kanestop_chain::BodyKind;

/// Geometry of a body, used by the force models and the inertia of Eq. 18.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shape {
    /// A cuboid: length L (x), width w (y), height h (z), in m.
    Box {
        /// L, along x, m.
        length: f64,
        /// w, along y, m.
        width: f64,
        /// h, along z, m.
        height: f64,
    },
    /// A homogeneous cylinder: length L and radius R, in m.
    Rod {
        /// L, along x, m.
        length: f64,
        /// R, m.
        radius: f64,
    },
}

/// One rigid body B_k.
#[derive(Clone, Debug, PartialEq)]
pub struct Body {
    /// What the body is.
    pub kind: BodyKind,
    /// m_k, kg.
    pub mass: f64,
    /// Central principal moments of inertia (I_11, I_22, I_33) in body axes, kg·m² (Eq. 18).
    pub inertia: [f64; 3],
    /// r_k: the centroid C_k measured from the body origin o_k, body axes (x, z), m.
    pub centroid: [f64; 2],
    /// q_k: the joint Q_k with the inner body B_{k-1}, in B_{k-1}'s axes (x, z), m.
    /// For B_1 this is the anchor origin o_1 in the inertial frame at t = 0.
    pub joint: [f64; 2],
    /// Geometry for the force models.
    pub shape: Shape,
    /// Added mass for accelerations normal to the body's x axis, kg (Eq. 46:
    /// m_a = C_M ρ π D² L / 4 for a submerged rod; 0 in air or vacuum). It enters a_lp as the
    /// translational inertia m_a n nᵀ, n the body's normal, so it is never lagged.
    pub added_mass: f64,
    /// Added moment of inertia about the centroid's y axis, kg·m² (Eq. 46: m_a L² / 12).
    pub added_inertia: f64,
}

impl Body {
    /// A homogeneous rod of length `length` (m), radius `radius` (m) and mass per metre
    /// `mass_per_length` (kg/m), hinged at its inner end (o_k at the joint, r_k = (L/2, 0)).
    /// `joint` is Q_k in the inner body's axes.
    pub fn rod(kind: BodyKind, length: f64, radius: f64, mass_per_length: f64, joint: [f64; 2]) -> Self {
        let mass = mass_per_length * length;
        Body {
            kind,
            mass,
            // Eq. 18, k = 2 … N-1.
            inertia: [mass * radius * radius / 2.0, mass * length * length / 12.0, mass * length * length / 12.0],
            centroid: [length / 2.0, 0.0],
            joint,
            shape: Shape::Rod { length, radius },
            added_mass: 0.0,
            added_inertia: 0.0,
        }
    }

    /// Length of the body along its x axis, m.
    pub fn length(&self) -> f64 {
        match self.shape {
            Shape::Box { length, .. } | Shape::Rod { length, .. } => length,
        }
    }
}

/// Added mass of a submerged rod for accelerations normal to its axis, kg (Eq. 46):
/// m_a = C_M ρ π D² L / 4, for water density `rho` (kg/m³), added-mass coefficient `c_m`,
/// diameter `d` (m) and length `len` (m).
pub fn added_mass(rho: f64, c_m: f64, d: f64, len: f64) -> f64 {
    c_m * rho * std::f64::consts::PI * d * d * len / 4.0
}

/// Inertia of a cuboid of mass m about a point a distance `d_s` above or below its centre
/// on the z axis (Eq. 18, k = 1 with d_s = 0 and k = N), kg·m².
pub fn box_inertia(mass: f64, length: f64, width: f64, height: f64, d_s: f64) -> [f64; 3] {
    [
        mass / 12.0 * (width * width + height * height + 12.0 * d_s * d_s),
        mass / 12.0 * (length * length + height * height + 12.0 * d_s * d_s),
        mass / 12.0 * (length * length + width * width),
    ]
}

/// The chain B_1 … B_N. B_1 is always the anchor, which can only translate along x.
#[derive(Clone, Debug, PartialEq)]
pub struct Chain {
    /// B_1 (anchor) … B_N (ship), in order along the line.
    pub bodies: Vec<Body>,
}

impl Chain {
    /// N, the number of bodies.
    pub fn len(&self) -> usize {
        self.bodies.len()
    }

    /// Always false for a valid chain (N ≥ 2); provided for clippy's sake.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }

    /// Whether any body has added mass (Eq. 46): the kernels' water switch.
    pub fn has_added_mass(&self) -> bool {
        self.bodies.iter().any(|b| b.added_mass != 0.0)
    }
}
