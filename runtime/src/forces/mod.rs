//! Applied loads on each body (Section 3.2), one small module per force.
//!
//! These modules are the readable statement of the physics and the oracle of the generated
//! load code (`generated/src/loads.rs`, emitted by `codegen/src/loads.rs` with the same
//! operations, per load signature; `tests/fused_loads.rs` checks them equal). The reference
//! kernel, the assembled path and `eval` call [`Forces::loads`] with the body states they
//! computed and project the result with the partial velocities (Eq. 23); the generated
//! kernel's solve runs the generated copy and hands back the power ([`LoadModel::fused`]),
//! keeping the loads for whoever asks (`Kernel::last_loads`). Each load is the resultant at the body's
//! centroid (force in N, moment about y in N·m). Added mass (Eq. 46) is not a load: it is
//! part of each body's inertia ([`crate::chain::Body::added_mass`]) and so of a_lp.
//!
//! Alongside the loads, [`Forces::power`] records the power of each category of force, so
//! the run can integrate their work with the state and check the energy balance of
//! Eqs. 63–69 to integration accuracy.

pub mod anchor;
pub mod current;
pub mod gravity;
pub mod morison;
pub mod seabed;
pub mod ship;

use kanestop_chain::{BodyKind, LoadSignature};

use crate::chain::{Chain, Shape};
use crate::kernel::{BodyState, Load, LoadModel};
use crate::model::Model;
use anchor::AnchorForces;
use current::Current;
use ship::ShipHydro;

/// The categories of non-gravitational work in the energy balance (Eq. 63), each
/// integrated with the state: buoyancy (Eq. 42), the seabed's reaction on the line
/// (Eq. 41), the anchor's sliding friction (Eq. 37), the grounded line's sliding friction,
/// the current drag on the anchor (Eq. 39), Morison drag on the line (Eqs. 43–47), the
/// ship's hull resistance, the ship's hydrostatics and the added mass's rotational part.
pub const WORK_TERMS: [&str; 9] = [
    "buoyancy",
    "seabed",
    "anchor_friction",
    "line_friction",
    "anchor_drag",
    "line_drag",
    "hull_resistance",
    "hydrostatic",
    "added_mass",
];

/// Index of each term in [`WORK_TERMS`] and [`Power`].
pub mod term {
    /// Buoyancy of the line and the anchor.
    pub const BUOYANCY: usize = 0;
    /// The seabed's normal reaction on the line.
    pub const SEABED: usize = 1;
    /// The anchor's sliding friction.
    pub const ANCHOR_FRICTION: usize = 2;
    /// The grounded line's sliding friction.
    pub const LINE_FRICTION: usize = 3;
    /// Current drag on the anchor.
    pub const ANCHOR_DRAG: usize = 4;
    /// Morison drag on the chain and cable.
    pub const LINE_DRAG: usize = 5;
    /// The ship's hull resistance.
    pub const HULL_RESISTANCE: usize = 6;
    /// The ship's heave and pitch hydrostatics.
    pub const HYDROSTATIC: usize = 7;
    /// The added-mass force's rotational part.
    pub const ADDED_MASS: usize = 8;
}

/// The work terms as reports name them (CSV channels, `run --json`, Python), each with the
/// terms of [`WORK_TERMS`] it sums: the six of before the split (issue 16; `friction` the
/// anchor's and the line's, `drag` the anchor's, the line's and the hull's), then the split
/// parts.
pub const REPORTED_WORK_PARTS: [(&str, &[usize]); 11] = [
    ("buoyancy", &[term::BUOYANCY]),
    ("seabed", &[term::SEABED]),
    ("friction", &[term::ANCHOR_FRICTION, term::LINE_FRICTION]),
    ("drag", &[term::ANCHOR_DRAG, term::LINE_DRAG, term::HULL_RESISTANCE]),
    ("hydrostatic", &[term::HYDROSTATIC]),
    ("added_mass", &[term::ADDED_MASS]),
    ("anchor_friction", &[term::ANCHOR_FRICTION]),
    ("line_friction", &[term::LINE_FRICTION]),
    ("anchor_drag", &[term::ANCHOR_DRAG]),
    ("line_drag", &[term::LINE_DRAG]),
    ("hull_resistance", &[term::HULL_RESISTANCE]),
];

/// The names of [`REPORTED_WORK_PARTS`], in order.
pub const REPORTED_WORK: [&str; REPORTED_WORK_PARTS.len()] = {
    let mut names = [""; REPORTED_WORK_PARTS.len()];
    let mut i = 0;
    while i < names.len() {
        names[i] = REPORTED_WORK_PARTS[i].0;
        i += 1;
    }
    names
};

/// The work of each name of [`REPORTED_WORK`], J, from the work of each term `work` (J).
pub fn reported_work(work: &Power) -> [(&'static str, f64); REPORTED_WORK.len()] {
    REPORTED_WORK_PARTS.map(|(name, parts)| (name, parts.iter().map(|&i| work[i]).sum()))
}

/// Power of each category of [`WORK_TERMS`], W.
pub type Power = [f64; WORK_TERMS.len()];

/// Per-body data the force models need.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Element {
    pub(crate) kind: BodyKind,
    pub(crate) length: f64,
    pub(crate) radius: f64,
    mass: f64,
    added_mass: f64,
}

/// All loads of a model.
#[derive(Clone, Debug)]
pub struct Forces {
    pub(crate) g: f64,
    pub(crate) rho: f64,
    pub(crate) water: bool,
    pub(crate) seabed: bool,
    pub(crate) k_z: f64,
    pub(crate) line_friction: f64,
    pub(crate) c_d: f64,
    pub(crate) c_f: f64,
    pub(crate) seabed_z: f64,
    pub(crate) elements: Vec<Element>,
    pub(crate) current: Current,
    /// The anchor's drag and friction.
    pub anchor: AnchorForces,
    pub(crate) ship: ShipHydro,
    power: Power,
}

impl Forces {
    /// The loads of a model, as its scene's switches select.
    pub fn new(model: &Model) -> Self {
        let s = &model.scene;
        let e = &s.environment;
        let mut f = Forces::gravity_only(&model.chain, e.gravity);
        f.rho = e.water_density;
        f.water = e.water;
        f.seabed = e.seabed;
        f.k_z = e.seabed_stiffness;
        f.line_friction = e.line_friction;
        f.c_d = s.hydrodynamics.normal_drag_coefficient;
        f.c_f = s.hydrodynamics.tangential_drag_coefficient;
        f.seabed_z = model.seabed_z;
        f.current = Current {
            surface_speed: if e.water { e.current_surface_speed } else { 0.0 },
            exponent: e.current_exponent,
            depth: model.water_depth(),
            seabed_z: model.seabed_z,
        };
        f.anchor = AnchorForces {
            volume: s.anchor.length * s.anchor.width * s.anchor.height,
            frontal_area: s.anchor.width * s.anchor.height,
            drag_coefficient: s.hydrodynamics.anchor_drag_coefficient,
            friction_coefficient: if e.seabed { e.seabed_friction } else { 0.0 },
        };
        f.ship = ShipHydro::new(
            s.ship.mass,
            s.ship.length,
            s.ship.beam,
            s.ship.hull_roughness,
            e.water_density,
            e.gravity,
            e.kinematic_viscosity,
        );
        f
    }

    /// Weight alone, gravity `g` in m/s²: a chain hanging in vacuum.
    pub fn gravity_only(chain: &Chain, g: f64) -> Self {
        let elements = chain
            .bodies
            .iter()
            .map(|b| Element {
                kind: b.kind,
                length: b.length(),
                radius: match b.shape {
                    Shape::Rod { radius, .. } => radius,
                    Shape::Box { .. } => 0.0,
                },
                mass: b.mass,
                added_mass: b.added_mass,
            })
            .collect();
        Forces {
            g,
            rho: 0.0,
            water: false,
            seabed: false,
            k_z: 0.0,
            line_friction: 0.0,
            c_d: 0.0,
            c_f: 0.0,
            seabed_z: 0.0,
            elements,
            current: Current { surface_speed: 0.0, exponent: 1.0 / 7.0, depth: 1.0, seabed_z: 0.0 },
            anchor: AnchorForces { volume: 0.0, frontal_area: 0.0, drag_coefficient: 0.0, friction_coefficient: 0.0 },
            ship: ShipHydro::new(1.0, 1.0, 1.0, 0.0, 1.0, g, 1.0),
            power: [0.0; WORK_TERMS.len()],
        }
    }

    /// The load terms these loads have ([`LoadSignature`]): the switches that change the
    /// generated load code. Weight alone when water and seabed are off (a chain hanging in
    /// vacuum: no buoyancy, drag, foundation or hydrostatics; the anchor's friction needs
    /// the seabed).
    pub fn signature(&self) -> LoadSignature {
        LoadSignature::new(self.water, self.seabed, self.current.surface_speed != 0.0, self.line_friction > 0.0)
    }

    /// Power of each work term at the last [`LoadModel::loads`] call, W.
    pub fn power(&self) -> Power {
        self.power
    }

    /// What the loads include, for reports.
    pub fn description(&self) -> String {
        let mut parts = vec!["gravity"];
        if self.water {
            parts.extend([
                "buoyancy",
                "Morison drag and added mass",
                "anchor water drag",
                "ship hydrostatics and resistance",
            ]);
        }
        if self.current.surface_speed != 0.0 {
            parts.push("current");
        }
        if self.seabed {
            parts.extend(["seabed foundation", "anchor stick–slip friction"]);
            if self.line_friction > 0.0 {
                parts.push("line friction on the seabed");
            }
        }
        parts.join(", ")
    }
}

/// Adds force `(fx, fz)` applied at `arm` from the centroid to `load`, and returns its power
/// for the body's state.
fn apply(load: &mut Load, s: &BodyState, arm: [f64; 2], fx: f64, fz: f64) -> f64 {
    // Moment about y of r × F: r_z F_x − r_x F_z.
    let my = arm[1] * fx - arm[0] * fz;
    load.fx += fx;
    load.fz += fz;
    load.my += my;
    fx * s.vx + fz * s.vz + my * s.omega
}

impl LoadModel for Forces {
    fn loads(&mut self, bodies: &[BodyState], loads: &mut [Load]) {
        let mut power = [0.0; WORK_TERMS.len()];
        let n = bodies.len();
        for (k, ((load, s), e)) in loads.iter_mut().zip(bodies).zip(&self.elements).enumerate() {
            *load = Load { fx: 0.0, fz: -e.mass * self.g, my: 0.0 };
            match e.kind {
                BodyKind::Anchor => {
                    let current = self.current.at(s.z);
                    if self.water {
                        power[term::BUOYANCY] +=
                            apply(load, s, [0.0, 0.0], 0.0, self.rho * self.anchor.volume * self.g);
                        power[term::ANCHOR_DRAG] +=
                            apply(load, s, [0.0, 0.0], self.anchor.drag(self.rho, current, s.vx), 0.0);
                    }
                }
                BodyKind::ChainLink | BodyKind::Cable { .. } => {
                    self.element_loads(s, e, load, &mut power);
                }
                BodyKind::Rod => {} // above the water: weight only (Section 3.2.2)
                BodyKind::Ship => {
                    if self.water && k == n - 1 {
                        power[term::HYDROSTATIC] += apply(load, s, [0.0, 0.0], 0.0, self.ship.vertical_force(s.z));
                        let my = self.ship.pitch_moment(s.theta);
                        load.my += my;
                        power[term::HYDROSTATIC] += my * s.omega;
                        let v_rel = s.vx - self.current.at(0.0);
                        power[term::HULL_RESISTANCE] += apply(load, s, [0.0, 0.0], self.ship.resistance(v_rel), 0.0);
                    }
                }
            }
        }
        self.power = power;
    }

    fn fused(&mut self, power: &[f64]) {
        self.power.copy_from_slice(power);
    }
}

impl Forces {
    /// Buoyancy (Eq. 42), seabed reaction (Eq. 41) and Morison drag (Eqs. 43–47) on a chain
    /// link or cable element.
    fn element_loads(&self, s: &BodyState, e: &Element, load: &mut Load, power: &mut Power) {
        let (sin, cos) = (s.sin, s.cos);
        let ex = [cos, -sin]; // body x axis
        let ez = [sin, cos]; // body z axis (normal)
        let half = 0.5 * e.length;
        let (za, zb) = (s.z - half * ex[1], s.z + half * ex[1]);
        let at = |xi: f64| [xi * ex[0], xi * ex[1]];

        // Seabed foundation, Eq. 41, at the centroid of the embedded volume, with the
        // element's sliding friction there.
        let mut embedded = 0.0;
        if self.seabed {
            let (v, s_bar) = seabed::embedded_volume(e.radius, e.length, za - self.seabed_z, zb - self.seabed_z);
            if v > 0.0 {
                embedded = v;
                let (arm, reaction) = (at(s_bar - half), self.k_z * v);
                power[term::SEABED] += apply(load, s, arm, 0.0, reaction);
                if self.line_friction > 0.0 {
                    // Velocity of the contact point along x: v_x − ξ ω sin θ.
                    let slip = s.vx - (s_bar - half) * s.omega * sin;
                    let friction = seabed::sliding_friction(self.line_friction, reaction, slip);
                    power[term::LINE_FRICTION] += apply(load, s, arm, friction, 0.0);
                }
            }
        }
        if !self.water {
            return;
        }
        // Submerged length: the part of the axis below the still-water plane.
        let (lo, hi) = (za.min(zb), za.max(zb));
        let fraction = if hi <= 0.0 {
            1.0
        } else if lo >= 0.0 {
            0.0
        } else {
            -lo / (hi - lo)
        };
        if fraction == 0.0 {
            return;
        }
        // Centre of the submerged part, as an axial offset from the centroid.
        let wet_centre = if fraction == 1.0 {
            0.0
        } else {
            let low_end = if za < zb { -half } else { half };
            low_end - low_end.signum() * fraction * half
        };
        // Buoyancy, Eq. 42: ρ (V − V^S) g on the submerged volume.
        let volume = std::f64::consts::PI * e.radius * e.radius * e.length * fraction;
        let buoyancy = self.rho * self.g * (volume - embedded).max(0.0);
        power[term::BUOYANCY] += apply(load, s, at(wet_centre), 0.0, buoyancy);

        // Morison drag, Eqs. 43–47, on the submerged fraction.
        let rel = [self.current.at(s.z) - s.vx, -s.vz]; // water relative to the body
        let v_t = rel[0] * ex[0] + rel[1] * ex[1];
        let u_n = rel[0] * ez[0] + rel[1] * ez[1];
        let d = 2.0 * e.radius;
        let (f_n, m_n) = morison::normal_drag(self.rho, self.c_d, d, e.length, u_n, s.omega);
        let f_t = morison::tangential_drag(self.rho, self.c_f, d, e.length, v_t);
        let (f_n, m_n, f_t) = (f_n * fraction, m_n * fraction, f_t * fraction);
        load.fx += f_n * ez[0] + f_t * ex[0];
        load.fz += f_n * ez[1] + f_t * ex[1];
        load.my += m_n;
        power[term::LINE_DRAG] +=
            (f_n * ez[0] + f_t * ex[0]) * s.vx + (f_n * ez[1] + f_t * ex[1]) * s.vz + m_n * s.omega;

        // The added-mass force −m_a (a·n) n does work −d(½ m_a v_n²)/dt + m_a ω v_t v_n: the
        // first part is kinetic energy of the entrained water, the second is tracked here.
        let (bt, bn) = (s.vx * ex[0] + s.vz * ex[1], s.vx * ez[0] + s.vz * ez[1]);
        power[term::ADDED_MASS] += e.added_mass * s.omega * bt * bn;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chain::Body;
    use std::f64::consts::{FRAC_PI_2, PI};

    /// Forces on one vertical cable element of length 2 m and radius 0.05 m in water, with
    /// its centroid at height `z` (the still-water plane is z = 0), at rest.
    fn vertical_element_loads(z: f64) -> (Load, Power) {
        let body = Body::rod(BodyKind::Cable { stage: 0 }, 2.0, 0.05, 10.0, [0.0, 0.0]);
        let mut f = Forces::gravity_only(&Chain { bodies: vec![body] }, 9.81);
        f.water = true;
        f.rho = 1025.0;
        f.seabed_z = -100.0;
        let (sin, cos) = (-FRAC_PI_2).sin_cos();
        let state = BodyState { x: 0.0, z, theta: -FRAC_PI_2, cos, sin, vx: 0.0, vz: 0.0, omega: 0.0 };
        let mut loads = [Load::default()];
        f.loads(&[state], &mut loads);
        (loads[0], f.power())
    }

    #[test]
    fn the_description_names_every_term_the_loads_include() {
        let body = Body::rod(BodyKind::Cable { stage: 0 }, 2.0, 0.05, 10.0, [0.0, 0.0]);
        let mut f = Forces::gravity_only(&Chain { bodies: vec![body] }, 9.81);
        assert_eq!(f.description(), "gravity");
        f.seabed = true;
        assert!(!f.description().contains("line friction"), "{}", f.description());
        f.line_friction = 0.5;
        assert!(f.description().ends_with("anchor stick–slip friction, line friction on the seabed"));
    }

    #[test]
    fn every_term_is_reported_under_its_own_name_and_the_sums_are_of_their_parts() {
        for (i, term) in WORK_TERMS.iter().enumerate() {
            assert!(REPORTED_WORK_PARTS.contains(&(*term, &[i][..])), "{term} is not reported alone");
        }
        let work: Power = std::array::from_fn(|i| (1 << i) as f64);
        let reported = reported_work(&work);
        assert_eq!(reported.map(|(n, _)| n), REPORTED_WORK);
        let by_name = |n: &str| reported.iter().find(|(m, _)| *m == n).unwrap().1;
        assert_eq!(by_name("friction"), by_name("anchor_friction") + by_name("line_friction"));
        assert_eq!(by_name("drag"), by_name("anchor_drag") + by_name("line_drag") + by_name("hull_resistance"));
    }

    #[test]
    fn buoyancy_of_a_half_submerged_element() {
        let weight = 20.0 * 9.81;
        let volume = PI * 0.05 * 0.05 * 2.0;
        // Fully submerged: ρ V g; half submerged (centroid on the surface): ρ V g / 2;
        // in air: none (Eq. 42 on the submerged volume).
        let (full, _) = vertical_element_loads(-5.0);
        let (half, _) = vertical_element_loads(0.0);
        let (dry, _) = vertical_element_loads(5.0);
        assert!((full.fz - (1025.0 * volume * 9.81 - weight)).abs() < 1e-9);
        assert!((half.fz - (1025.0 * volume * 9.81 / 2.0 - weight)).abs() < 1e-9, "{}", half.fz);
        assert!((dry.fz + weight).abs() < 1e-12);
        // A vertical element's buoyancy acts along its axis: no moment, no horizontal force.
        assert!(half.fx.abs() < 1e-12 && half.my.abs() < 1e-9);
    }
}
