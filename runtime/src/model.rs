//! From a checked scene to what the solver needs: the topology, the numeric chain, the
//! initial state and the environment (Section 3.1).
//!
//! Layout choices the paper leaves open are made here, once, for every scene; they are
//! listed in `docs/model-choices.md`.

use std::f64::consts::FRAC_PI_2;

use kanestop_chain::{BodyKind, Topology, TopologyError};

use crate::catenary::{lay_elements, Catenary, CatenaryError};
use crate::chain::{added_mass, box_inertia, Body, Chain, Shape};
use crate::kernel::AnchorDof;
use crate::scene::Scene;

/// Everything a run starts from.
#[derive(Clone, Debug)]
pub struct Model {
    /// The checked scene the model was built from.
    pub scene: Scene,
    /// How many bodies of each kind, in order (anchor, links, cable stages, rod, ship).
    pub topology: Topology,
    /// The numeric bodies B_1 … B_N (masses, inertias of Eq. 18, added masses of Eq. 46).
    pub chain: Chain,
    /// Generalised coordinates at t = 0 (see [`crate::kernel`] for the convention).
    pub q0: Vec<f64>,
    /// Generalised speeds at t = 0.
    pub u0: Vec<f64>,
    /// The anchor's degree of freedom at t = 0.
    pub anchor: AnchorDof,
    /// Height of the seabed in the inertial frame (−d), m.
    pub seabed_z: f64,
    /// The catenary the cable was laid on.
    pub catenary: Catenary,
    /// Its lower end o in the inertial frame, m.
    pub catenary_origin: [f64; 2],
}

/// A scene whose geometry admits no initial configuration.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ModelError {
    /// The cable stages describe no chain.
    #[error("cable.stages: {0}")]
    Topology(TopologyError),
    /// The cable cannot be laid on the catenary of Eqs. 30–34.
    #[error("initial configuration: {0}")]
    InitialConfiguration(CatenaryError),
}

impl From<CatenaryError> for ModelError {
    fn from(e: CatenaryError) -> Self {
        ModelError::InitialConfiguration(e)
    }
}

impl Model {
    /// Builds the model of a checked scene: the bodies, the cable laid on its catenary
    /// (Eqs. 30–35) and the initial state.
    ///
    /// ```
    /// use kanestop_runtime::{model::Model, paper::DEFAULT_SCENE, scene::Scene};
    ///
    /// let scene = Scene::from_toml(DEFAULT_SCENE, "case01.toml").unwrap();
    /// let model = Model::new(&scene).unwrap();
    /// // Anchor, 15 chain links, 28 cable elements, rod and ship.
    /// assert_eq!(model.body_count(), 46);
    /// assert_eq!(model.q0.len(), 46);
    /// assert!(model.cable_end_error() < 1e-9);
    /// ```
    pub fn new(scene: &Scene) -> Result<Model, ModelError> {
        let topology = Topology::new(scene.chain.elements, scene.cable.stages.iter().map(|s| s.elements).collect())
            .map_err(ModelError::Topology)?;
        let n = topology.body_count();
        let line = LaidLine::new(scene)?;
        let theta = initial_angles(scene, &line.points, n);

        // The ship's water-plane centre is the inertial origin o_0 (Section 2.3.1).
        let top = line.points.last().expect("a laid line has at least one element");
        let hinge = [top[0], line.line_height + top[1] + scene.rod.length];
        let ship_centre = [hinge[0] - scene.ship.hinge_x, hinge[1] - scene.ship.hinge_z];
        let seabed_z = -ship_centre[1];

        let chain = bodies(scene, &line, ship_centre, n);
        let (q0, u0) = initial_state(scene, &theta);
        // The anchor starts at rest, held by static friction (released by the run when the
        // pull exceeds μN); on a frictionless or absent seabed it slides freely.
        let env = &scene.environment;
        let anchor = if env.seabed && env.seabed_friction > 0.0 { AnchorDof::Stuck } else { AnchorDof::Free };

        let catenary_origin = [-ship_centre[0], line.line_height - ship_centre[1]];
        Ok(Model {
            scene: scene.clone(),
            topology,
            chain,
            q0,
            u0,
            anchor,
            seabed_z,
            catenary: line.catenary,
            catenary_origin,
        })
    }

    /// N.
    pub fn body_count(&self) -> usize {
        self.chain.len()
    }

    /// Distance between the laid cable's top joint and (x_L, h_L) above the catenary's lower
    /// end o, m, by forward kinematics of q_0 (Eq. 13): how exactly the rigid elements end
    /// where Eqs. 30–34 say (zero to round-off).
    pub fn cable_end_error(&self) -> f64 {
        let joints = self.initial_joints();
        let top = joints[self.body_count() - 2]; // o_{N−1}: the rod stands on the cable top
        let o = self.catenary_origin;
        let target = [o[0] + self.catenary.horizontal, o[1] + self.catenary.vertical];
        (top[0] - target[0]).hypot(top[1] - target[1])
    }

    /// Body origins o_k at t = 0 in the inertial frame (Eq. 13 with r_k = 0), B_1 first.
    pub fn initial_joints(&self) -> Vec<[f64; 2]> {
        let mut theta: f64 = 0.0;
        let mut o = self.chain.bodies[0].joint;
        let mut out = vec![o];
        for k in 1..self.body_count() {
            let q = self.chain.bodies[k].joint;
            let (s, c) = theta.sin_cos();
            o = [o[0] + q[0] * c + q[1] * s, o[1] - q[0] * s + q[1] * c];
            theta += self.q0[k - 1];
            out.push(o);
        }
        out
    }

    /// Length of the laid cable elements that lie on the seabed at t = 0 (both ends at the
    /// height of the catenary's lower end o, to 1e-9 m), m: the grounded part of the line as
    /// the rigid elements lay it, which differs from the catenary's grounded length
    /// ([`Catenary::grounded_length`]) by less than two elements: the one the catenary
    /// touches down in, and the one the laying lifts to meet (x_L, h_L).
    pub fn grounded_cable_length(&self) -> f64 {
        let joints = self.initial_joints();
        let floor = self.catenary_origin[1] + 1e-9;
        (0..self.body_count() - 1)
            .filter(|&k| matches!(self.chain.bodies[k].kind, kanestop_chain::BodyKind::Cable { .. }))
            .filter(|&k| joints[k][1] <= floor && joints[k + 1][1] <= floor)
            .map(|k| self.chain.bodies[k].length())
            .sum()
    }

    /// The laid line's tensions at rest, N: its horizontal tension T_h = w_c a (Eq. 31) and its
    /// top tension T_t = w_c (a + h_L), of the catenary its elements are laid on.
    pub fn initial_tensions(&self) -> (f64, f64) {
        let w = self.scene.cable_weight_per_length();
        (w * self.catenary.a, w * (self.catenary.a + self.catenary.vertical))
    }

    /// Water depth d, m.
    pub fn water_depth(&self) -> f64 {
        -self.seabed_z
    }

    /// Load limits of a body of `kind` as a member of the line: a chain link's Table 1 proof
    /// and break loads; the cable's break load for the cable and the rod; none for the
    /// anchor and the ship.
    pub fn member_limits(&self, kind: BodyKind) -> LoadLimits {
        let s = &self.scene;
        match kind {
            BodyKind::ChainLink => LoadLimits { proof: Some(s.chain.proof_load), breaking: Some(s.chain.break_load) },
            BodyKind::Cable { .. } | BodyKind::Rod => LoadLimits { proof: None, breaking: Some(s.cable.break_load) },
            BodyKind::Anchor | BodyKind::Ship => LoadLimits::default(),
        }
    }

    /// Load limits of the joint k (2 … N) between B_{k−1} and B_k: the weaker of the two
    /// bodies' [`Model::member_limits`] (at the chain–cable joint, the chain's proof load and
    /// the cable's break load, which may be below it).
    pub fn joint_limits(&self, k: usize) -> LoadLimits {
        let limits = |kind: BodyKind| self.member_limits(kind);
        let (a, b) = (limits(self.chain.bodies[k - 2].kind), limits(self.chain.bodies[k - 1].kind));
        let min = |x: Option<f64>, y: Option<f64>| match (x, y) {
            (Some(x), Some(y)) => Some(x.min(y)),
            (x, None) => x,
            (None, y) => y,
        };
        LoadLimits { proof: min(a.proof, b.proof), breaking: min(a.breaking, b.breaking) }
    }
}

/// The line laid on its catenary in the local frame (seabed at z = 0, the catenary's lower
/// end o at (0, z_cable)), with the heights at which the chain and the cable rest.
struct LaidLine {
    /// The catenary the cable was laid on (Eqs. 30–34).
    catenary: Catenary,
    /// Joint points of the cable elements, from the chain's end to the rod's foot, m.
    points: Vec<[f64; 2]>,
    /// Height of the chain's centreline above the seabed, m.
    chain_height: f64,
    /// Height of the cable's centreline above the seabed, m.
    line_height: f64,
    /// The anchor's origin o_1, m.
    anchor_origin: [f64; 2],
}

impl LaidLine {
    fn new(scene: &Scene) -> Result<LaidLine, CatenaryError> {
        // Element lengths along the line.
        let cable_lengths = scene.cable_element_lengths();
        let (catenary, cable_points) =
            lay_elements(&cable_lengths, scene.horizontal_projection()?, scene.initial.vertical_projection)?;

        // Chain links and grounded cable lie level at their static embedment height (weight
        // less buoyancy = foundation reaction, Eqs. 41, 42). The chain leaves the anchor's
        // forward face at its height; the first cable element, thin and light, bridges the
        // few centimetres from the chain's height down to its own (its raised end just rests).
        let env = &scene.environment;
        let rest = |radius: f64, mpl: f64| env.resting_height(radius, mpl);
        let cable_height = rest(scene.cable.radius, scene.cable.mass_per_length);
        let chain_height =
            if scene.chain.elements > 0 { rest(scene.chain.radius, scene.chain.mass_per_length) } else { cable_height };
        let line_height = cable_height;
        let step = chain_height - cable_height;
        let mut points = cable_points;
        // The first element keeps its length from its upper joint (grounded or not) to the
        // chain's height.
        let first_len = cable_lengths[0];
        let rise = points[1][1] - step;
        if first_len <= rise.abs() {
            // The scene check refuses this first (cable.stages[0].element_length).
            return Err(CatenaryError::FirstElementTooShort { length: first_len, rise: rise.abs() });
        }
        points[0] = [points[1][0] - (first_len * first_len - rise * rise).sqrt(), step];
        let chain_length = scene.chain.elements as f64 * scene.chain.element_length;
        let anchor_origin = [points[0][0] - chain_length - scene.anchor.length, 0.0];
        Ok(LaidLine { catenary, points, chain_height, line_height, anchor_origin })
    }
}

/// Absolute angles θ_k of the N bodies at t = 0 (Eq. 35 with atan2 along the laid cable);
/// the anchor and chain are level, the rod stands vertical, the ship is level.
fn initial_angles(scene: &Scene, cable_points: &[[f64; 2]], n: usize) -> Vec<f64> {
    let mut theta = vec![0.0; n];
    let first_cable = 1 + scene.chain.elements;
    for (j, w) in cable_points.windows(2).enumerate() {
        theta[first_cable + j] = -(w[1][1] - w[0][1]).atan2(w[1][0] - w[0][0]);
    }
    theta[n - 2] = -FRAC_PI_2; // the rod stands vertical on the cable top
    theta[n - 1] = 0.0; // the ship is level
    theta
}

/// The bodies B_1 … B_N: the anchor box, the chain links, the cable elements stage by
/// stage, the rod and the ship box (Eq. 18), with the added masses of Eq. 46.
fn bodies(scene: &Scene, line: &LaidLine, ship_centre: [f64; 2], n: usize) -> Chain {
    let mut bodies = Vec::with_capacity(n);
    let a = &scene.anchor;
    bodies.push(Body {
        kind: BodyKind::Anchor,
        mass: a.mass,
        inertia: box_inertia(a.mass, a.length, a.width, a.height, 0.0),
        centroid: [a.length / 2.0, a.height / 2.0],
        joint: [line.anchor_origin[0] - ship_centre[0], line.anchor_origin[1] - ship_centre[1]],
        shape: Shape::Box { length: a.length, width: a.width, height: a.height },
        added_mass: 0.0,
        added_inertia: 0.0,
    });
    let mut inner_joint = [a.length, line.chain_height];
    let mut push_rod = |bodies: &mut Vec<Body>, kind, length: f64, radius, mpl| {
        bodies.push(Body::rod(kind, length, radius, mpl, inner_joint));
        inner_joint = [length, 0.0];
    };
    let ch = &scene.chain;
    for _ in 0..ch.elements {
        push_rod(&mut bodies, BodyKind::ChainLink, ch.element_length, ch.radius, ch.mass_per_length);
    }
    for (stage, s) in scene.cable.stages.iter().enumerate() {
        for _ in 0..s.elements {
            push_rod(
                &mut bodies,
                BodyKind::Cable { stage },
                s.element_length,
                scene.cable.radius,
                scene.cable.mass_per_length,
            );
        }
    }
    push_rod(&mut bodies, BodyKind::Rod, scene.rod.length, scene.rod.radius, scene.rod.mass_per_length);
    let s = &scene.ship;
    // Eq. 18, k = N: d_s is the height of the box's centre above the water plane.
    let d_s = s.depth / 2.0 - scene.ship_draught();
    bodies.push(Body {
        kind: BodyKind::Ship,
        mass: s.mass,
        inertia: box_inertia(s.mass, s.length, s.beam, s.depth, d_s),
        centroid: [-s.hinge_x, -s.hinge_z],
        joint: inner_joint,
        shape: Shape::Box { length: s.length, width: s.beam, height: s.depth },
        added_mass: 0.0,
        added_inertia: 0.0,
    });
    if scene.environment.water {
        add_water_inertia(scene, &mut bodies);
    }
    Chain { bodies }
}

/// Added mass and added moment of inertia of the submerged chain links and cable elements
/// (Eq. 46); the rod is in air and the ship has none (docs/model-choices.md).
fn add_water_inertia(scene: &Scene, bodies: &mut [Body]) {
    let rho = scene.environment.water_density;
    let c_m = scene.hydrodynamics.added_mass_coefficient;
    for b in bodies.iter_mut().filter(|b| matches!(b.kind, BodyKind::ChainLink | BodyKind::Cable { .. })) {
        if let Shape::Rod { length, radius } = b.shape {
            b.added_mass = added_mass(rho, c_m, 2.0 * radius, length);
            b.added_inertia = b.added_mass * length * length / 12.0;
        }
    }
}

/// q_0 = (β_2 … β_N, s_1) from the absolute angles, and u_0: the cable and chain at rest,
/// the rod turning so that its top moves with the ship, the ship not rotating
/// (assumption 2).
fn initial_state(scene: &Scene, theta: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let n = theta.len();
    let mut q0 = vec![0.0; n];
    for k in 1..n {
        q0[k - 1] = theta[k] - theta[k - 1];
    }
    let mut u0 = vec![0.0; n];
    let rod = n - 2;
    // Rod top velocity x-component = −L θ̇ sin θ = V.
    let rod_rate = -scene.initial.ship_speed / (scene.rod.length * theta[rod].sin());
    u0[rod - 1] = rod_rate;
    u0[n - 2] = -rod_rate;
    (q0, u0)
}

/// The load limits of a joint, N.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LoadLimits {
    /// Proof load (chain joints only), N.
    pub proof: Option<f64>,
    /// Break load, N.
    pub breaking: Option<f64>,
}
