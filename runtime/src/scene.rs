//! Scenes: the TOML description of one simulation, parsed with serde and checked.
//!
//! Every field is required (no silent defaults) and unknown keys are rejected. Units are
//! SI and stated on each field. [`Scene::from_toml`] returns either a scene whose every
//! value is finite and in range, or a [`SceneError`] that names the file, the field, the
//! value and the valid range.

use std::fmt;
use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::catenary::{self, CatenaryError};
use crate::geometry::segment_area;
use crate::overrides::{self, OverrideError};

/// The most bodies N a scene may have: the start-up stability analysis and the reference
/// kernel hold dense matrices of about [`bytes_for_bodies`]`(N)` (≈ 1.7 GB at 4000) and cost
/// O(N³); larger scenes are refused before anything is allocated.
pub const MAX_BODIES: usize = 4000;

/// The most steps (`solver.end_time / solver.dt`) a scene may ask for: 1e7, about 6 min of
/// RK4 at N = 46 (36 µs per step on the project's machine) and an hour at N = 500; smaller
/// steps are refused with the estimate.
pub const MAX_STEPS: f64 = 1e7;

/// The longest step a scene may ask for (`solver.dt`), s.
pub const MAX_DT: f64 = 1.0;

/// Wall time per body and right-hand-side evaluation of the generated kernels, measured for
/// case 1 (0.354 s for 40 243 evaluations at N = 46), s: the basis of the time estimates.
pub const SECONDS_PER_BODY_EVALUATION: f64 = 1.9e-7;

/// Bytes of the dense matrices a run of N bodies holds at start-up: the reference kernel's
/// N × N mass matrix and the stability analysis's (2N)² Jacobian with its eigen-decomposition
/// or Arnoldi basis (at most three copies in all), 8 bytes each.
pub fn bytes_for_bodies(n: usize) -> f64 {
    let n = n as f64;
    8.0 * (n * n + 3.0 * (2.0 * n) * (2.0 * n))
}

/// One simulation: the bodies, their initial layout, the environment and the solver.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// `[meta]`: name, description, the paper's stopping time.
    pub meta: Meta,
    /// `[environment]`: gravity, water, current, seabed switches and constants.
    pub environment: Environment,
    /// `[hydrodynamics]`: the drag and added-mass coefficients of Eqs. 43–47.
    pub hydrodynamics: Hydrodynamics,
    /// `[anchor]`: the gravity anchor B_1.
    pub anchor: Anchor,
    /// `[chain]`: the anchor chain's links.
    pub chain: ChainSpec,
    /// `[cable]`: the cable and its stages.
    pub cable: Cable,
    /// `[rod]`: the rod between the cable top and the ship.
    pub rod: Rod,
    /// `[ship]`: the ship B_N.
    pub ship: Ship,
    /// `[initial]`: the laid catenary and the ship's speed at t = 0.
    pub initial: Initial,
    /// `[solver]`: integrator, step and tolerances, end time, output and stop rules.
    pub solver: Solver,
    /// `[checks]` (optional): design checks the run's results are held to (docs/sweeps.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checks: Option<crate::design::DesignChecks>,
}

/// What the scene is.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Meta {
    /// Short name used in reports and file names: one line, without control characters.
    pub name: String,
    /// One line for humans, without control characters.
    pub description: String,
    /// The stopping time the paper reports for this scene (Table 3), s, as the paper's scene
    /// files state it, in (0, 1e15]; absent for other scenes. Reports take Table 3's time from the
    /// paper's cases themselves, for a scene that is one of them (see above).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paper_stopping_time: Option<f64>,
}

/// Gravity, water, seabed and current (Section 3.2, Eqs. 38, 41).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Environment {
    /// g, m/s², in (0, 100].
    pub gravity: f64,
    /// Water on: buoyancy, drag and added mass act, and the ship floats (its hydrostatics and
    /// resistance, Eqs. 53–62). Off: the line hangs in vacuum and nothing holds the ship up,
    /// which falls freely onto the line: a test of the mechanics, not a ship afloat.
    pub water: bool,
    /// ρ, sea-water density, kg/m³, in [900, 1300] (`WATER_DENSITY`: fresh water is 1000, sea
    /// water about 1025, the densest brines about 1240; 1.025, a density in t/m³, was refused
    /// as a ship too heavy to float).
    pub water_density: f64,
    /// ϑ, kinematic viscosity of sea water, m²/s.
    pub kinematic_viscosity: f64,
    /// Seabed on: foundation reaction (Eq. 41) and anchor friction act. Off, the anchor
    /// still only surges at its seabed height (the model gives it no heave or pitch, Eq. 1):
    /// the line hangs from it and sinks below that height where nothing holds it up.
    pub seabed: bool,
    /// k_z, normal counter-force coefficient of the seabed foundation, N/m³ (Eq. 41). With
    /// water and seabed on, must exceed ρ g + (m' − ρ π R²) g/(π R²) for the chain and the
    /// cable (m', R their `mass_per_length` and `radius`): softer, the foundation cannot carry
    /// them and they would sink whole.
    pub seabed_stiffness: f64,
    /// μ, anchor–seabed sliding friction coefficient, dimensionless (Eq. 37), in [0, 2].
    pub seabed_friction: f64,
    /// μ_l, friction coefficient between chain or cable elements and the seabed, acting on
    /// the foundation reaction of Eq. 41, dimensionless, in [0, 2]. The paper's links slide
    /// without friction (assumption 4): 0 in its cases.
    pub line_friction: f64,
    /// U_ST, current speed at the free surface along +x, m/s (Eq. 38), in [-10, 10] m/s
    /// (negative: toward −x).
    pub current_surface_speed: f64,
    /// Exponent of the current profile U = U_ST (h/d)^exponent, dimensionless (Eq. 38: 1/7),
    /// in (0, 1].
    pub current_exponent: f64,
}

impl Environment {
    /// Height of a level rod's centreline above the seabed at rest, m: the depth δ at which
    /// the foundation carries the submerged weight, (k_z − ρ g) A(δ) = (m' − ρ π R²) g
    /// (Eqs. 41, 42), for a rod of `radius` (m) and `mass_per_length` (kg/m). Without a
    /// seabed (or lighter than water) the rod is placed touching the seabed plane (+R); on a
    /// foundation too soft to carry it, fully buried (−R).
    pub fn resting_height(&self, radius: f64, mass_per_length: f64) -> f64 {
        let rho = if self.water { self.water_density } else { 0.0 };
        let area = std::f64::consts::PI * radius * radius;
        let load = (mass_per_length - rho * area) * self.gravity;
        if !self.seabed || load <= 0.0 {
            return radius;
        }
        let target = load / (self.seabed_stiffness - rho * self.gravity);
        if target >= area {
            return -radius; // the foundation is too soft to carry it: fully buried
        }
        let (mut lo, mut hi) = (0.0, 2.0 * radius);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if segment_area(radius, mid) < target {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        radius - 0.5 * (lo + hi)
    }
}

/// Hydrodynamic coefficients (Eqs. 39, 44–47).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Hydrodynamics {
    /// C_M, added-mass coefficient of the rods, dimensionless, in [0, 100] (the paper's 1.0).
    pub added_mass_coefficient: f64,
    /// C_D, normal drag coefficient of the rods, dimensionless, in [0, 100] (the paper's 1.21).
    pub normal_drag_coefficient: f64,
    /// C_F, tangential drag coefficient of the rods, dimensionless, in [0, 100] (the paper's 0.062).
    pub tangential_drag_coefficient: f64,
    /// C_1^D, drag coefficient of the anchor, dimensionless, in [0, 100] (Eq. 39; the paper's 1.05).
    pub anchor_drag_coefficient: f64,
}

/// The gravity anchor B_1, a cuboid on the seabed.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Anchor {
    /// m_1, kg. With water on, must exceed ρ L_1 w_1 h_1 (the anchor sinks: N > 0 in Eq. 37).
    pub mass: f64,
    /// L_1, along x, m.
    pub length: f64,
    /// w_1, across the line, m.
    pub width: f64,
    /// h_1, m. Must be below the water depth d = h_L + δ_c + `rod.length` − `ship.hinge_z`
    /// (δ_c the cable's resting height, see `vertical_projection`).
    pub height: f64,
}

/// The anchor chain: identical links from the anchor toward the cable.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChainSpec {
    /// Number of links (may be 0). With the cable's elements, at most `MAX_BODIES` = 4000
    /// bodies in all (N = links + cable elements + 3), refused with the memory estimate.
    pub elements: usize,
    /// Length of one link element, m.
    pub element_length: f64,
    /// R_CE, equivalent radius of the 2D element, m (Table 1).
    pub radius: f64,
    /// Mass per metre of the 2D element, kg/m. With water on, must exceed ρ π R_CE² (the chain
    /// sinks).
    pub mass_per_length: f64,
    /// Proof load, N (Table 1: one chain's, checked against the 2D element's tension, which
    /// is the two chains': conservative by 2, as the paper checks; docs/model-choices.md). At
    /// most `break_load`.
    pub proof_load: f64,
    /// Break load, N (Table 1: one chain's, as for `proof_load`). At least the weight in air
    /// of `MIN_BREAKING_LENGTH` = 100 m of the chain (mass_per_length × 9.80665 m/s² × 100 m):
    /// a steel chain breaks under kilometres of its own length (case 1: 2.7 km), so a break
    /// load below that is one in kN, not N (it ran, and failed as a numerical spike).
    pub break_load: f64,
}

/// The restraining cable, in stages of equal elements.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Cable {
    /// R_RE, equivalent radius, m.
    pub radius: f64,
    /// m_RU-based mass per metre of the 2D element, kg/m. With water on, must exceed ρ π R_RE²
    /// (the cable sinks: w_c > 0 in Eqs. 30–31).
    pub mass_per_length: f64,
    /// Break load, N (the paper's 2520 kN, checked against the 2D element's tension, which is
    /// the cable's two ends': conservative by 2, as for the chain's loads). At least the weight
    /// in air of `MIN_BREAKING_LENGTH` = 100 m of the cable, as for the chain's (case 1: 18.6 km).
    pub break_load: f64,
    /// The stages from the chain toward the ship (`[[cable.stages]]` tables; at least one:
    /// an absent list is reported by the range check, not the parser; at least 2 elements
    /// in all, since one rigid element cannot lie on the seabed and reach (x_L, h_L)).
    #[serde(default)]
    pub stages: Vec<CableStage>,
}

/// One cable stage.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CableStage {
    /// Number of elements (≥ 1; at least 2 over all stages). See `chain.elements` for the
    /// limit on bodies.
    pub elements: usize,
    /// Length of one element, m.
    pub element_length: f64,
}

/// The auxiliary rod B_{N-1} between cable and ship, above the water (weight only).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Rod {
    /// L_{N-1}, m. At most `ship.hinge_z`: the rod stands on the cable top up to the hinge and
    /// is in air (Section 3.2.2).
    pub length: f64,
    /// Radius, m.
    pub radius: f64,
    /// Mass per metre, kg/m.
    pub mass_per_length: f64,
}

/// The ship B_N, a cuboid whose centroid is the centre of its water plane (assumption 8).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ship {
    /// m_N, kg. Must float: the draught T = m_N/(ρ L_N w_N) below `depth` and, with water
    /// on, below the water depth d (see `anchor.height`); with water on, also at least
    /// `MIN_DRAUGHT_FRACTION` = 0.01 of `depth` (an empty steel barge floats on about a
    /// tenth of its depth: 500, a mass in tonnes, floated case 1's ship on 1 mm).
    pub mass: f64,
    /// L_N, m.
    pub length: f64,
    /// w_N (beam), m.
    pub beam: f64,
    /// h_N (depth, keel to deck), m.
    pub depth: f64,
    /// k_s, hull roughness height, m (Eq. 61).
    pub hull_roughness: f64,
    /// d_x: the rod hinge's position forward of the water-plane centre, m (negative: aft), on
    /// the hull: in [−L_N/2, L_N/2] (L_N the ship's `length`).
    pub hinge_x: f64,
    /// d_z: the rod hinge's height above the water plane, m, in [-1000, 1000] m. At least
    /// `rod.length`; sets the water depth with h_L (see `ship.mass`, `anchor.height`).
    pub hinge_z: f64,
}

/// The initial configuration (Section 3.1, Eqs. 30–35).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Initial {
    /// x_L, horizontal projection of the whole cable, m. The paper's way to lay the line
    /// (Table 2); give this, `horizontal_tension` or `top_tension`, one of them. Joined with the cable's length
    /// L_c and `vertical_projection` h_L: the line must lay as the paper lays it (Section 3.1),
    /// grounded from o, then the catenary of Eqs. 30–34 up to (x_L, h_L), so
    /// L_c − h_L < x_L ≤ a asinh(L_c/a) with a = (L_c² − h_L²)/(2 h_L) (below: no tension,
    /// the cable would hang vertically; above: nothing on the seabed, the cable would leave o
    /// with a slope and lift the chain; for case 1, (146, 151.842056] m); the rigid elements
    /// may raise the lower end (case 1: by less than 1e-5 m), found by laying them. The laid
    /// elements end at (x_L, h_L) to 1e-9 m, or the scene is refused with the range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub horizontal_projection: Option<f64>,
    /// T_h, the horizontal tension of the cable's catenary at rest, N. Instead of
    /// `horizontal_projection`, the line laid by its tension: T_h = w_c a (Eq. 31), w_c the
    /// cable's weight per metre in water (in air without water), a that of the catenary the
    /// rigid elements are laid on; x_L is the one that lays them so (docs/model-choices.md).
    /// Not the top tension (T_h + w_c h_L, what a mooring engineer's pretension usually
    /// means: `top_tension`). Setting it (a sweep's
    /// path, the Python package, a file that `extends` another) replaces x_L or the top tension. Held fixed, it keeps the suspended part's shape while a sweep changes the cable's
    /// length (x_L follows it), and keeps the line laid while a sweep changes h_L; a fixed
    /// x_L has a window of a few metres (see `horizontal_projection`). Must be in the range
    /// of the laid lines, from nearly 0 (the rigid elements cannot follow a sharper corner at
    /// the touchdown) to T_max, where no cable is left on the seabed; the scene is refused
    /// with the range (case 1: [1.006e-5, 226 722] N; its x_L = 148 m has T_h = 148.0 N, the
    /// paper's line hanging nearly vertically from its touchdown).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub horizontal_tension: Option<f64>,
    /// T_t, the pretension: the cable's tension at its top at rest, N. Instead of x_L or T_h,
    /// the line laid by its top tension, T_t = T_h + w_c h_L (the catenary's tension grows by
    /// w_c per metre of rise, Eqs. 30–34), so T_h = T_t − w_c h_L and the line is laid as by
    /// `horizontal_tension`. Setting it replaces x_L or T_h. Must be in the range of the laid
    /// lines, the T_h range raised by w_c h_L, from just above the suspended cable's weight
    /// w_c h_L (a slack line hanging from its touchdown) to where no cable is left on the
    /// seabed (case 1: [708.875, 227 431] N; its x_L = 148 m has T_t = 856.8 N). Like T_h, a
    /// parameter of the laid shape, not a tension the model holds at t = 0: the paper starts
    /// the auxiliary rod vertical (Section 2.1), and a taut line's rod swings at the start,
    /// the line nearly slack until the ship takes it up (docs/model-choices.md).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub top_tension: Option<f64>,
    /// h_L, vertical projection of the cable (seabed line to cable top), m. Must be below the
    /// cable's length L_c; with x_L, see `horizontal_projection`. Sets the water depth
    /// d = h_L + δ_c + `rod.length` − `ship.hinge_z`, where δ_c is the laid cable's resting
    /// height above the seabed (its centreline where the foundation carries its submerged
    /// weight, Eqs. 41, 42: the cable's radius R less its embedment of a few mm, 21.8 mm in
    /// case 1; from +R on a hard seabed to −R, buried, on a soft one).
    pub vertical_projection: f64,
    /// The ship's initial surge speed, m/s, in [0, 20] m/s. A ship at rest (0) has stopped at
    /// t = 0: its stopping time is 0, and `solver.stop_when_ship_stops` ends its run there
    /// (stopping distance 0).
    pub ship_speed: f64,
}

/// How `[initial]` lays the line: by its horizontal projection, its horizontal tension or its
/// top tension.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Layout {
    /// x_L, m.
    Projection(f64),
    /// T_h, N.
    Tension(f64),
    /// T_t, N.
    TopTension(f64),
}

impl Initial {
    /// The layout the scene gives, `None` when it gives none or more than one (a scene error).
    pub fn layout(&self) -> Option<Layout> {
        match self.layouts_given()[..] {
            [(field, v)] => Some(match field {
                "initial.horizontal_projection" => Layout::Projection(v),
                "initial.horizontal_tension" => Layout::Tension(v),
                _ => Layout::TopTension(v),
            }),
            _ => None,
        }
    }

    /// The fields of the layouts the scene gives, with their values, in the order of
    /// [`Layout`].
    fn layouts_given(&self) -> Vec<(&'static str, f64)> {
        [
            ("initial.horizontal_projection", self.horizontal_projection),
            ("initial.horizontal_tension", self.horizontal_tension),
            ("initial.top_tension", self.top_tension),
        ]
        .into_iter()
        .filter_map(|(field, v)| Some((field, v?)))
        .collect()
    }
}

/// Time integration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Solver {
    /// The method.
    pub integrator: Method,
    /// Time step of `rk4`, s. For the adaptive methods, the observation interval: events and
    /// stability checks are evaluated every `dt`, and the method takes its own
    /// error-controlled steps (never longer) in between, after each of which the peak
    /// tensions are looked at. In (0, 1] s, and at least `end_time` / 1e7: more steps are
    /// refused with the time estimate (`MAX_STEPS`).
    pub dt: f64,
    /// Relative tolerance of the adaptive methods (`dp5`, `sdirk4`), dimensionless, in
    /// [1e-14, 0.1].
    pub rtol: f64,
    /// Absolute tolerance of the adaptive methods, in the state's units (rad, m, rad/s, m/s, J),
    /// in [1e-16, 1] (`MIN_ATOL`: below it a component at zero, such as a work term at the
    /// start, is asked for an error the steps cannot meet, and the step collapses; case 1 runs
    /// at rtol 1e-14 with atol 1e-16 under both methods, and collapsed at t = 0 with 1e-300).
    pub atol: f64,
    /// Simulated time after which the run ends in any case, s, in (0, ∞), and at most
    /// `dt` × 1e7 (`MAX_STEPS`: 20 000 s at the paper's 2 ms). The run ends at the last
    /// whole `dt` at or before it (0.501 s at 2 ms: 0.5 s; until 2026-12-07 the nearest,
    /// 0.502 s, past it).
    pub end_time: f64,
    /// Interval between recorded samples, s (rounded to a whole number of steps), at least
    /// `dt` and at most 1e15 s.
    pub output_interval: f64,
    /// End the run when the ship's surge speed first reaches zero (at t = 0 for a ship at rest
    /// at the start). With `false` the run goes on to `end_time`; its stopping time and
    /// distance are still those of that first zero, and the stopping checks judge them.
    pub stop_when_ship_stops: bool,
    /// Relative energy-balance drift |E − E_0|/K at which a run is stopped as unstable,
    /// dimensionless; K is the largest kinetic energy before the step checked (the entrained
    /// water's included), the energy in play (docs/model-choices.md; before 2026-12-06 it was
    /// E_0, whose potential energy is measured from the seabed). In [0.0001, 10]
    /// (`MIN_ENERGY_DRIFT`): a detector of blow-ups, not an accuracy target. The integration's
    /// own drift is below it on the paper's cases (RK4 at 2 ms: 8.5e-7 on case 1, and below it
    /// on the rough line `tests/paper_cases.rs` runs); set below it, a sound run was stopped
    /// as an instability (1e-9 stopped case 1 in its first second).
    pub max_energy_drift: f64,
}

/// Integration methods a scene can name.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Classic fourth-order Runge–Kutta with fixed step (the paper's method).
    Rk4,
    /// Dormand–Prince 5(4), adaptive (explicit).
    Dp5,
    /// L-stable SDIRK of order 4, adaptive, for stiff scenes (implicit).
    Sdirk4,
}

impl Method {
    /// Every method, in the order the docs list them.
    pub const ALL: [Method; 3] = [Method::Rk4, Method::Dp5, Method::Sdirk4];

    /// The name a scene, the command line and every output use: `rk4`, `dp5` or `sdirk4`.
    pub fn name(self) -> &'static str {
        match self {
            Method::Rk4 => "rk4",
            Method::Dp5 => "dp5",
            Method::Sdirk4 => "sdirk4",
        }
    }

    /// True for the error-controlled methods (`dp5`, `sdirk4`), whose `dt` is an observation
    /// interval.
    pub fn is_adaptive(self) -> bool {
        self != Method::Rk4
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A name that is not a [`Method`].
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0}: unknown method (valid: rk4, dp5, sdirk4)")]
pub struct UnknownMethod(pub String);

/// A method by its name; anything else is refused naming the three (`integrator = 0` was
/// "wanted string or table").
impl<'de> Deserialize<'de> for Method {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Name;
        impl serde::de::Visitor<'_> for Name {
            type Value = Method;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("a method's name: \"rk4\", \"dp5\" or \"sdirk4\"")
            }
            fn visit_str<E: serde::de::Error>(self, text: &str) -> Result<Method, E> {
                text.parse().map_err(E::custom)
            }
        }
        d.deserialize_str(Name)
    }
}

impl std::str::FromStr for Method {
    type Err = UnknownMethod;

    fn from_str(text: &str) -> Result<Self, UnknownMethod> {
        Method::ALL.into_iter().find(|m| m.name() == text.trim()).ok_or_else(|| UnknownMethod(text.to_string()))
    }
}

/// A scene that could not be read or is not valid.
#[derive(Debug)]
pub enum SceneError {
    /// The file could not be read.
    Io {
        /// The path as given.
        file: String,
        /// The file whose `extends` named it, for a base of a scene.
        extended_by: Option<String>,
        /// The I/O error.
        source: std::io::Error,
    },
    /// Not TOML, a missing or unknown key, or a value of the wrong type.
    Parse {
        /// The path as given.
        file: String,
        /// The TOML or serde message.
        message: String,
    },
    /// Values out of range: every problem found, each naming its field.
    Invalid {
        /// The path as given.
        file: String,
        /// Every out-of-range value, in field order.
        problems: Vec<Problem>,
    },
    /// An `extends` chain or a dotted-path override could not be applied.
    Override {
        /// The file (or the scene's name, with the overrides).
        file: String,
        /// What went wrong.
        error: OverrideError,
    },
}

/// One out-of-range value.
#[derive(Clone, Debug, PartialEq)]
pub struct Problem {
    /// Dotted path of the field, e.g. `anchor.mass`.
    pub field: String,
    /// The value as written.
    pub value: String,
    /// The valid range, with units.
    pub expected: String,
}

impl fmt::Display for Problem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} = {}: must be {}", self.field, self.value, self.expected)
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneError::Io { file, extended_by: None, source } => write!(f, "cannot read scene {file}: {source}"),
            SceneError::Io { file, extended_by: Some(by), source } => {
                write!(f, "cannot read scene {file}, the base that `extends` names in {by}: {source}")
            }
            SceneError::Parse { file, message } => {
                write!(f, "scene {file} is not valid: {}", plain_types(message.trim_end()))?;
                // A sweep spec's own fields: the file is a spec, given where a scene goes.
                let spec = ["base", "axis", "sampling", "uncertain", "set"];
                if spec.iter().any(|k| message.contains(&format!("unknown field `{k}`"))) {
                    write!(f, "\n(a sweep spec, not a scene: run it with `kanestop sweep {file}`)")?;
                }
                Ok(())
            }
            SceneError::Invalid { file, problems } => {
                write!(f, "scene {file} has {} invalid value(s):", problems.len())?;
                for p in problems {
                    write!(f, "\n  {p}")?;
                }
                Ok(())
            }
            SceneError::Override { file, error } => write!(f, "scene {file}: {error}"),
        }
    }
}

impl std::error::Error for SceneError {}

impl Scene {
    /// Reads and checks a scene file. A file with `extends = "base.toml"` is laid over its
    /// base (a path relative to it; chains allowed): its tables merge key by key into the
    /// base's, and an array (such as `cable.stages`) replaces the base's whole.
    ///
    /// ```
    /// use kanestop_runtime::scene::{Scene, SceneError};
    ///
    /// let dir = std::env::temp_dir().join(format!("kanestop-doc-{}", std::process::id()));
    /// std::fs::create_dir_all(&dir).unwrap();
    /// let path = dir.join("case01.toml");
    /// std::fs::write(&path, kanestop_runtime::paper::DEFAULT_SCENE).unwrap();
    /// let scene = Scene::load(&path)?;
    /// assert_eq!(scene.chain.elements, 15);
    /// assert!(matches!(Scene::load(&dir.join("missing.toml")), Err(SceneError::Io { .. })));
    /// # std::fs::remove_dir_all(&dir).unwrap();
    /// # Ok::<(), SceneError>(())
    /// ```
    pub fn load(path: &Path) -> Result<Scene, SceneError> {
        Scene::load_edited(path, &|_| {})
    }

    /// [`Scene::load`] with `edit` applied to the file's tables (its `extends` chain laid
    /// over each other) before the scene is checked, so that the edit may mend the file (a
    /// command line's `--dt` over a file whose own step is refused) and may read its values
    /// (`--dt` raises an output interval below it). Errors name the file `FILE (with
    /// command-line overrides)` where `edit` changed something ([`overrides::same`]); an edit
    /// that changes nothing is [`Scene::load`], whose errors point at the file's lines.
    pub fn load_edited(path: &Path, edit: &dyn Fn(&mut toml::Value)) -> Result<Scene, SceneError> {
        let file = path.display().to_string();
        let text =
            read_scene_file(path).map_err(|source| SceneError::Io { file: file.clone(), extended_by: None, source })?;
        let Ok(top) = text.parse::<toml::Table>() else {
            // Not TOML: the parse error, with its line.
            return Scene::from_toml(&text, &file);
        };
        let extends = top.contains_key("extends");
        let mut value = if extends { Scene::resolve_file(path, None)? } else { toml::Value::Table(top.clone()) };
        let before = value.clone();
        edit(&mut value);
        let mut scene = match (overrides::same(&value, &before), extends) {
            // A whole file as it is: parsed as text, so that errors point at its lines.
            (true, false) => return Scene::from_toml(&text, &file),
            (true, true) => Scene::from_value(value, &file)?,
            (false, _) => Scene::from_value(value, &format!("{file} (with command-line overrides)"))?,
        };
        if extends {
            scene.own_meta(path, &top);
        }
        Ok(scene)
    }

    /// [`Scene::from_toml`] of text named as a file at `path` (which need not exist): an
    /// `extends` is resolved from `path`'s folder, as [`Scene::load`] resolves a file's, and
    /// the text is laid over that chain of files (a file there of the text's own name is one
    /// of them, not the text).
    pub fn from_toml_at(text: &str, path: &Path) -> Result<Scene, SceneError> {
        let file = path.display().to_string();
        let mut top = match text.parse::<toml::Table>() {
            Ok(top) if top.contains_key("extends") => top,
            _ => return Scene::from_toml(text, &file),
        };
        let own = top.clone();
        let extends = top.remove("extends");
        let Some(base) = extends.as_ref().and_then(overrides::extends_target) else {
            return Err(SceneError::Override { file, error: OverrideError::ExtendsType });
        };
        let mut value = Scene::resolve_file(&path.parent().unwrap_or(Path::new("")).join(base), Some(path))?;
        overrides::merge(&mut value, toml::Value::Table(top));
        let mut scene = Scene::from_value(value, &file)?;
        scene.own_meta(path, &own);
        Ok(scene)
    }

    /// The tables of the scene file at `path` with its `extends` chain laid over each other;
    /// `named_by` is the file (or text) whose `extends` named `path`, if any.
    fn resolve_file(path: &Path, named_by: Option<&Path>) -> Result<toml::Value, SceneError> {
        fn io(p: &Path, by: Option<&Path>) -> impl FnOnce(std::io::Error) -> SceneError {
            let (file, extended_by) = (p.display().to_string(), by.map(|b| b.display().to_string()));
            move |source| SceneError::Io { file, extended_by, source }
        }
        let mut read = |p: &Path, by: Option<&Path>| read_scene_file(p).map_err(io(p, by));
        let mut parse = |p: &Path, text: &str| {
            text.parse::<toml::Table>()
                .map(toml::Value::Table)
                .map_err(|e| SceneError::Parse { file: p.display().to_string(), message: e.to_string() })
        };
        let wrap = |p: &Path, error| SceneError::Override { file: p.display().to_string(), error };
        overrides::resolve(path, named_by, &mut read, &mut parse, &wrap)
    }

    /// The `[meta]` of a scene that extends another, where the file does not set it: its name
    /// is the file's stem and its description says what it extends (the base's would describe
    /// another scene). Table 3's time is not decided here: reports take it from the paper's
    /// cases whenever a scene is one of them (`paper::stopping_time`).
    fn own_meta(&mut self, path: &Path, top: &toml::Table) {
        let sets = |key: &str| top.get("meta").and_then(toml::Value::as_table).is_some_and(|m| m.contains_key(key));
        if !sets("name") {
            self.meta.name =
                path.file_stem().map_or_else(|| self.meta.name.clone(), |s| s.to_string_lossy().into_owned());
        }
        if !sets("description") {
            let base = top.get("extends").and_then(toml::Value::as_str).unwrap_or_default();
            let file = path.file_name().map_or_else(String::new, |f| f.to_string_lossy().into_owned());
            self.meta.description = format!("{base} with the changes of {file}");
        }
    }

    /// Whether two scenes are the same physical case: equal but for `[meta]`, `[checks]` and
    /// `[solver]` (the environment, the bodies, the line and the initial state). The paper's
    /// Table 3 applies to a scene that is the same case as one of its 19
    /// (`paper::stopping_time`).
    pub fn same_case(&self, other: &Scene) -> bool {
        let strip =
            |s: &Scene| Scene { meta: Meta::default(), checks: None, solver: other.solver.clone(), ..s.clone() };
        strip(self) == strip(other)
    }

    /// Checks a scene given as a TOML value (a file's tables after `extends`, or a table
    /// built in code); `file` names it in errors.
    pub fn from_value(value: toml::Value, file: &str) -> Result<Scene, SceneError> {
        let scene: Scene =
            from_value_at(value).map_err(|message| SceneError::Parse { file: file.to_string(), message })?;
        scene.checked(file)
    }

    /// The scene as a TOML value, every field present.
    pub fn to_value(&self) -> toml::Value {
        toml::Value::try_from(self).expect("a scene is plain tables of numbers, strings and booleans")
    }

    /// The same scene with each (dotted path, value) set, checked as a whole file would be:
    /// `[("ship.mass", 1e6.into()), ("cable.stages[1].elements", 20.into())]`.
    pub fn with_overrides(&self, values: &[(&str, toml::Value)]) -> Result<Scene, SceneError> {
        let file = format!("{} (with overrides)", self.meta.name);
        let paths: Vec<&str> = values.iter().map(|(p, _)| *p).collect();
        if let Some((i, j)) = overrides::conflicting_alternatives(&paths) {
            let error = OverrideError::Alternatives { first: paths[i].to_string(), second: paths[j].to_string() };
            return Err(SceneError::Override { file, error });
        }
        let mut value = self.to_value();
        for (path, v) in values {
            overrides::set(&mut value, path, v.clone())
                .map_err(|error| SceneError::Override { file: file.clone(), error })?;
        }
        Scene::from_value(value, &file)
    }

    /// The scene when [`Scene::problems`] finds none, else every problem.
    fn checked(self, file: &str) -> Result<Scene, SceneError> {
        let problems = self.problems();
        if problems.is_empty() {
            Ok(self)
        } else {
            Err(SceneError::Invalid { file: file.to_string(), problems })
        }
    }

    /// Parses and checks scene text; `file` names it in errors.
    ///
    /// ```
    /// use kanestop_runtime::scene::{Scene, SceneError};
    ///
    /// // The embedded case 1 of Table 2.
    /// let scene = Scene::from_toml(kanestop_runtime::paper::DEFAULT_SCENE, "case01.toml")?;
    /// assert_eq!(scene.meta.name, "case01");
    /// // A value out of range is reported with its field.
    /// let bad = kanestop_runtime::paper::DEFAULT_SCENE.replace("[anchor]\nmass =", "[anchor]\nmass = -1.0 #");
    /// let err = Scene::from_toml(&bad, "bad.toml").unwrap_err();
    /// assert!(err.to_string().contains("anchor.mass"), "{err}");
    /// # Ok::<(), SceneError>(())
    /// ```
    pub fn from_toml(text: &str, file: &str) -> Result<Scene, SceneError> {
        let scene: Scene =
            toml::from_str(text).map_err(|e| SceneError::Parse { file: file.to_string(), message: e.to_string() })?;
        scene.checked(file)
    }

    /// The scene as TOML text.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a scene always serialises")
    }

    /// Total cable length L_c, m.
    pub fn cable_length(&self) -> f64 {
        self.cable.stages.iter().map(|s| s.elements as f64 * s.element_length).sum()
    }

    /// w_c, the cable's weight per metre where it lies, N/m (Eqs. 30, 31): in water less its
    /// buoyancy, (m'_c − ρ π R_c²) g, in air m'_c g.
    pub fn cable_weight_per_length(&self) -> f64 {
        let e = &self.environment;
        let rho = if e.water { e.water_density } else { 0.0 };
        (self.cable.mass_per_length - rho * std::f64::consts::PI * self.cable.radius.powi(2)) * e.gravity
    }

    /// x_L, m: `initial.horizontal_projection` as given, or the one that lays the line at
    /// `initial.horizontal_tension` (a = T_h / w_c, Eq. 31,
    /// [`catenary::horizontal_for_parameter`]) or at `initial.top_tension` (a = T_t / w_c −
    /// h_L). A scene that gives none or more than one (refused by its checks) has none:
    /// [`CatenaryError::NoLayout`].
    pub fn horizontal_projection(&self) -> Result<f64, CatenaryError> {
        let (w, h) = (self.cable_weight_per_length(), self.initial.vertical_projection);
        let a = match self.initial.layout() {
            Some(Layout::Projection(x)) => return Ok(x),
            Some(Layout::Tension(t)) => t / w,
            Some(Layout::TopTension(t)) => t / w - h,
            None => return Err(CatenaryError::NoLayout),
        };
        catenary::horizontal_for_parameter(&self.cable_element_lengths(), h, a)
    }

    /// The water depth d = h_L + δ_c + `rod.length` − `ship.hinge_z`, m: the seabed lies d
    /// below the water plane, the cable's top h_L above the laid line, which rests at the
    /// cable's resting height δ_c ([`Environment::resting_height`]); the rod stands on the
    /// cable top up to the ship's hinge, `hinge_z` above the water plane (the model's layout).
    pub fn water_depth(&self) -> f64 {
        let cable = &self.cable;
        let rest = self.environment.resting_height(cable.radius, cable.mass_per_length);
        rest + self.initial.vertical_projection + self.rod.length - self.ship.hinge_z
    }

    /// The ship's draught T = m_N / (ρ L_N w_N), m: the box floats level in still water.
    pub fn ship_draught(&self) -> f64 {
        self.ship.mass / (self.environment.water_density * self.ship.length * self.ship.beam)
    }

    /// Every out-of-range value, in file order.
    pub fn problems(&self) -> Vec<Problem> {
        let mut c = Checker::default();
        // Names and descriptions stand on one line of tables, CSV rows and plot titles.
        for (field, text) in [("meta.name", &self.meta.name), ("meta.description", &self.meta.description)] {
            if text.chars().any(char::is_control) {
                c.push(
                    field,
                    &format!("{text:?}"),
                    "one line of text, without line breaks, tabs or other control characters",
                );
            }
        }
        if let Some(t) = self.meta.paper_stopping_time {
            c.range("meta.paper_stopping_time", t, 0.0, MAX_MAGNITUDE, false, "s");
        }
        self.check_environment(&mut c);
        self.check_hydrodynamics(&mut c);
        self.check_anchor_and_chain(&mut c);
        self.check_cable(&mut c);
        self.check_size(&mut c);
        self.check_rod_and_ship(&mut c);
        let laid = self.check_initial(&mut c);
        self.check_solver(&mut c);
        self.check_checks(&mut c);
        if c.problems.is_empty() {
            self.check_joined(&mut c, laid);
        }
        c.problems
    }

    /// Rules between fields of different tables, checked when every value alone is valid;
    /// each is documented beside the fields it joins. `laid`: the x_L that lays the line.
    fn check_joined(&self, c: &mut Checker, laid: Option<f64>) {
        let ch = &self.chain;
        if ch.proof_load > ch.break_load {
            c.push(
                "chain.proof_load",
                &fmt_value(ch.proof_load),
                &format!("≤ chain.break_load = {} N", fmt_value(ch.break_load)),
            );
        }
        for (name, mpl, load) in
            [("chain", ch.mass_per_length, ch.break_load), ("cable", self.cable.mass_per_length, self.cable.break_load)]
        {
            let least = mpl * STANDARD_GRAVITY * MIN_BREAKING_LENGTH;
            if load < least {
                c.push(
                    &format!("{name}.break_load"),
                    &fmt_value(load),
                    &format!(
                        "≥ {least:.3e} N, the weight in air of {MIN_BREAKING_LENGTH} m of the {name} (a steel line \
                         breaks under kilometres of its own length; this one would break under {} m of it): a break \
                         load in N, not kN",
                        fmt_rounded(load / (mpl * STANDARD_GRAVITY), 1)
                    ),
                );
            }
        }
        self.check_depth(c);
        if self.environment.water {
            self.check_sinking(c);
        }
        if let Some(x) = laid {
            self.check_first_element(c, x);
        }
    }

    /// The first cable element bridges the chain's resting height and its upper joint on the
    /// laid line: it must be longer than that rise, taken with both radii as the bound of the
    /// resting heights (a link rests within its radius of the seabed plane).
    fn check_first_element(&self, c: &mut Checker, x: f64) {
        let lengths = self.cable_element_lengths();
        let h = self.initial.vertical_projection;
        let Ok((_, points)) = catenary::lay_elements(&lengths, x, h) else { return };
        let Some(joint) = points.get(1) else { return };
        let bound = joint[1].abs() + 2.0 * (self.chain.radius + self.cable.radius);
        if lengths[0] <= bound {
            c.push(
                "cable.stages[0].element_length",
                &fmt_value(lengths[0]),
                &format!(
                    "> {} m: the first cable element must span the rise from the chain's resting height \
                     to its upper joint ({} m above the seabed)",
                    fmt_rounded(bound, 6),
                    fmt_rounded(joint[1], 6)
                ),
            );
        }
    }

    /// The water depth d ([`Scene::water_depth`]) holds the anchor and the floating ship; the
    /// rod is above the water.
    fn check_depth(&self, c: &mut Checker) {
        let (rod, ship) = (&self.rod, &self.ship);
        if rod.length > ship.hinge_z + 1e-9 {
            let why = format!(
                "≤ ship.hinge_z = {} m: the rod stands on the cable top up to the hinge and is in air (Section 3.2.2), so its foot must not be under the water plane",
                fmt_value(ship.hinge_z)
            );
            c.push("rod.length", &fmt_value(rod.length), &why);
        }
        let depth = self.water_depth();
        if self.environment.water && depth <= 0.0 {
            // No water under the ship: the hinge's height is what is off (the paper's is
            // 1 m), not the anchor or the ship the depth would fail to hold.
            let room = depth + ship.hinge_z;
            let why = format!(
                "≤ {} m (h_L + the cable's resting height + rod.length), so that the water depth d = h_L + the \
                 cable's resting height + rod.length − ship.hinge_z is positive (it is {} m; or raise \
                 initial.vertical_projection)",
                fmt_rounded(room, 3),
                fmt_rounded(depth, 3)
            );
            c.push("ship.hinge_z", &fmt_value(ship.hinge_z), &why);
            return;
        }
        let needs = [
            ("anchor.height", self.anchor.height, "the anchor's top"),
            ("ship.mass", self.ship_draught(), "the ship's keel (draught)"),
        ];
        for (field, height, what) in needs {
            if self.environment.water && height >= depth {
                let value = if field == "ship.mass" { fmt_value(ship.mass) } else { fmt_value(height) };
                let why = format!(
                    "such that {what} ({} m) is below the water depth d = h_L + the cable's resting height + rod.length − ship.hinge_z = {} m (raise initial.vertical_projection)",
                    fmt_rounded(height, 3),
                    fmt_rounded(depth, 3)
                );
                c.push(field, &value, &why);
            }
        }
    }

    /// In water the anchor, the chain and the cable sink (w_c > 0 in Eqs. 30–31; N > 0 in
    /// Eq. 37), and on a seabed the foundation carries the links and the cable (Eqs. 41, 42).
    fn check_sinking(&self, c: &mut Checker) {
        let e = &self.environment;
        let rho = e.water_density;
        let a = &self.anchor;
        let displaced = rho * a.length * a.width * a.height;
        if a.mass <= displaced {
            c.push(
                "anchor.mass",
                &fmt_value(a.mass),
                &format!("> ρ L_1 w_1 h_1 = {} kg (the anchor would float)", fmt_value(displaced)),
            );
        }
        let lines = [
            ("chain", self.chain.radius, self.chain.mass_per_length, self.chain.elements > 0),
            ("cable", self.cable.radius, self.cable.mass_per_length, true),
        ];
        for (name, radius, mpl, _) in lines.into_iter().filter(|l| l.3) {
            let area = std::f64::consts::PI * radius * radius;
            if mpl <= rho * area {
                let why = format!(
                    "> ρ π R² = {} kg/m (the {name} would float: no catenary, Eqs. 30–31)",
                    fmt_rounded(rho * area, 3)
                );
                c.push(&format!("{name}.mass_per_length"), &fmt_value(mpl), &why);
            } else if e.seabed {
                let least = rho * e.gravity + (mpl - rho * area) * e.gravity / area;
                if e.seabed_stiffness <= least {
                    let why = format!("> ρ g + (m' − ρ π R²) g / (π R²) = {least:.4e} N/m³ for the {name} (softer, the foundation of Eq. 41 cannot carry it: it would sink whole)");
                    c.push("environment.seabed_stiffness", &fmt_value(e.seabed_stiffness), &why);
                }
            }
        }
    }

    /// `[environment]`: constants in their physical ranges.
    fn check_environment(&self, c: &mut Checker) {
        let e = &self.environment;
        c.range("environment.gravity", e.gravity, 0.0, 100.0, false, "m/s²");
        let (lo, hi) = WATER_DENSITY;
        c.range("environment.water_density", e.water_density, lo, hi, true, "kg/m³ (sea water about 1025)");
        c.positive("environment.kinematic_viscosity", e.kinematic_viscosity, "m²/s");
        c.positive("environment.seabed_stiffness", e.seabed_stiffness, "N/m³");
        c.range("environment.seabed_friction", e.seabed_friction, 0.0, 2.0, true, "(dimensionless)");
        c.range("environment.line_friction", e.line_friction, 0.0, 2.0, true, "(dimensionless)");
        c.range("environment.current_surface_speed", e.current_surface_speed, -10.0, 10.0, true, "m/s");
        c.range("environment.current_exponent", e.current_exponent, 0.0, 1.0, false, "(dimensionless)");
    }

    /// `[hydrodynamics]`: the coefficients of Eqs. 39 and 43–47, each in [0, [`MAX_HYDRO_COEFFICIENT`]].
    fn check_hydrodynamics(&self, c: &mut Checker) {
        let h = &self.hydrodynamics;
        let unit = "(dimensionless; published values for chain, wire rope and block anchors stay below 3)";
        for (field, v) in [
            ("hydrodynamics.added_mass_coefficient", h.added_mass_coefficient),
            ("hydrodynamics.normal_drag_coefficient", h.normal_drag_coefficient),
            ("hydrodynamics.tangential_drag_coefficient", h.tangential_drag_coefficient),
            ("hydrodynamics.anchor_drag_coefficient", h.anchor_drag_coefficient),
        ] {
            c.range(field, v, 0.0, MAX_HYDRO_COEFFICIENT, true, unit);
        }
    }

    /// `[anchor]` and `[chain]`: positive sizes, masses and loads.
    fn check_anchor_and_chain(&self, c: &mut Checker) {
        let a = &self.anchor;
        c.positive("anchor.mass", a.mass, "kg");
        c.positive("anchor.length", a.length, "m");
        c.positive("anchor.width", a.width, "m");
        c.positive("anchor.height", a.height, "m");
        let ch = &self.chain;
        c.positive("chain.element_length", ch.element_length, "m");
        c.positive("chain.radius", ch.radius, "m");
        c.positive("chain.mass_per_length", ch.mass_per_length, "kg/m");
        c.positive("chain.proof_load", ch.proof_load, "N");
        c.positive("chain.break_load", ch.break_load, "N");
    }

    /// `[cable]` and its stages: at least one stage, each with elements.
    fn check_cable(&self, c: &mut Checker) {
        let cb = &self.cable;
        c.positive("cable.radius", cb.radius, "m");
        c.positive("cable.mass_per_length", cb.mass_per_length, "kg/m");
        c.positive("cable.break_load", cb.break_load, "N");
        if cb.stages.is_empty() {
            c.push("cable.stages", "[]", "at least one [[cable.stages]] table (N ≥ 4 bodies)");
        }
        for (i, s) in cb.stages.iter().enumerate() {
            if s.elements == 0 {
                c.push(&format!("cable.stages[{i}].elements"), "0", "≥ 1 element");
            }
            c.positive(&format!("cable.stages[{i}].element_length"), s.element_length, "m");
        }
    }

    /// `[rod]` and `[ship]`; the ship must float with a draught below its depth (checked
    /// only when every value before is valid).
    fn check_rod_and_ship(&self, c: &mut Checker) {
        let e = &self.environment;
        let r = &self.rod;
        c.positive("rod.length", r.length, "m");
        c.positive("rod.radius", r.radius, "m");
        c.positive("rod.mass_per_length", r.mass_per_length, "kg/m");
        let s = &self.ship;
        c.positive("ship.mass", s.mass, "kg");
        c.positive("ship.length", s.length, "m");
        c.positive("ship.beam", s.beam, "m");
        c.positive("ship.depth", s.depth, "m");
        c.non_negative("ship.hull_roughness", s.hull_roughness, "m");
        if s.length.is_finite() && s.length > 0.0 {
            c.range("ship.hinge_x", s.hinge_x, -s.length / 2.0, s.length / 2.0, true, "m (on the hull)");
        }
        c.range("ship.hinge_z", s.hinge_z, -1e3, 1e3, true, "m");
        let least = MIN_DRAUGHT_FRACTION * s.depth;
        if c.problems.is_empty() && e.water && self.ship_draught() < least {
            c.push(
                "ship.mass",
                &fmt_value(s.mass),
                &format!(
                    "≥ {:.3e} kg, a draught of {MIN_DRAUGHT_FRACTION} × ship.depth = {} m (this mass floats the hull \
                     on {} m; an empty steel barge floats on about a tenth of its depth): a mass in kg, not t",
                    least * e.water_density * s.length * s.beam,
                    fmt_value(least),
                    fmt_rounded(self.ship_draught(), 4)
                ),
            );
        }
        if c.problems.is_empty() && self.ship_draught() >= s.depth {
            c.push(
                "ship.mass",
                &fmt_value(s.mass),
                &format!(
                    "< ρ·L·w·depth = {} kg, the water a hull of ship.depth = {} m displaces when wholly \
                     immersed: this mass would need a draught of {} m to float",
                    fmt_value(e.water_density * s.length * s.beam * s.depth),
                    fmt_value(s.depth),
                    fmt_rounded(self.ship_draught(), 3)
                ),
            );
        }
    }

    /// Bodies N = 1 (anchor) + chain links + cable elements + 2 (rod, ship).
    pub fn body_count(&self) -> usize {
        let cable: usize = self.cable.stages.iter().map(|s| s.elements).fold(0, usize::saturating_add);
        cable.saturating_add(self.chain.elements).saturating_add(3)
    }

    /// At most [`MAX_BODIES`], refused with the memory estimate before anything is allocated.
    fn check_size(&self, c: &mut Checker) {
        let n = self.body_count();
        if n > MAX_BODIES {
            // Counted without overflow (the sum of counts near usize::MAX saturated and read as N).
            let cable: u128 = self.cable.stages.iter().map(|s| s.elements as u128).sum();
            let exact = cable + self.chain.elements as u128 + 3;
            let why = format!(
                "with the cable stages at most {MAX_BODIES} bodies in all (N = {exact}: the dense matrices of the \
                 start-up stability analysis and the reference kernel would need about {:.3e} bytes)",
                bytes_for_bodies(usize::try_from(exact).unwrap_or(usize::MAX))
            );
            if self.chain.elements as u128 >= cable {
                c.push("chain.elements", &self.chain.elements.to_string(), &why);
            } else {
                c.push("cable.stages", &format!("{cable} elements"), &why);
            }
        }
    }

    /// `[initial]`: each value in range, then the line must lay as the paper lays it (checked
    /// when the cable and the initial values are valid): see [`Scene::check_geometry`]. The
    /// x_L that lays it, when it lays.
    fn check_initial(&self, c: &mut Checker) -> Option<f64> {
        let ini = &self.initial;
        match ini.layouts_given()[..] {
            [] => c.push(
                "initial.horizontal_projection",
                "(missing)",
                "given (x_L, m, as in Table 2), or initial.horizontal_tension (T_h, N) or initial.top_tension \
                 (T_t, N) instead",
            ),
            [(field, v)] => c.positive(field, v, unit(field).unwrap_or_default()),
            [(field, v), (other, _), ..] => c.push(
                field,
                &fmt_value(v),
                &format!("left out when {other} is given (the line is laid by one of them)"),
            ),
        }
        c.positive("initial.vertical_projection", ini.vertical_projection, "m");
        c.range("initial.ship_speed", ini.ship_speed, 0.0, 20.0, true, "m/s");
        let joined = |f: &Problem| {
            f.field.starts_with("cable.") || f.field.starts_with("initial.") || f.field == "chain.elements"
        };
        // A tension that is not a positive number is refused with the range of tensions that
        // lay, where the rest of the line lets it be computed ([`Scene::check_tension_layout`]).
        let tension = match ini.layout() {
            Some(Layout::Tension(_)) => Some("initial.horizontal_tension"),
            Some(Layout::TopTension(_)) => Some("initial.top_tension"),
            _ => None,
        };
        let bad_tension = c.problems.iter().position(|p| Some(p.field.as_str()) == tension);
        if c.problems.iter().enumerate().any(|(i, f)| joined(f) && Some(i) != bad_tension) {
            return None;
        }
        let x = self.check_geometry(c);
        if let Some(i) = bad_tension {
            if c.problems[i + 1..].iter().any(|p| Some(p.field.as_str()) == tension) {
                c.problems.remove(i);
            }
        }
        x
    }

    /// The initial line exists (Section 3.1, Eqs. 30–35): chain on the seabed, the cable
    /// grounded from o and then on the catenary up to (x_L, h_L), its rigid elements ending
    /// there to 1e-9 m. For a continuous cable of length L_c this holds for
    /// L_c − h_L < x_L ≤ a asinh(L_c/a) with a = (L_c² − h_L²)/(2 h_L) (below: no tension, the
    /// cable would hang vertically; above: nothing left on the seabed, the cable would leave o
    /// with a slope and lift the chain), and needs h_L < L_c; the rigid elements raise the lower
    /// end a little ([`catenary::laid_range`]). A single cable element cannot lie on the seabed
    /// and reach (x_L, h_L). Laid by T_h, the line must have a laid x_L for a = T_h / w_c
    /// ([`catenary::horizontal_for_parameter`]); a cable that does not sink (w_c ≤ 0) is left
    /// to the sinking check. The x_L that lays the line, when it lays.
    fn check_geometry(&self, c: &mut Checker) -> Option<f64> {
        let (h, lc) = (self.initial.vertical_projection, self.cable_length());
        let lengths = self.cable_element_lengths();
        if h >= lc {
            let why = format!(
                "< L_c = {} m, the cable length (it must reach h_L and lie partly on the seabed)",
                fmt_value(lc)
            );
            c.push("initial.vertical_projection", &fmt_value(h), &why);
            return None;
        }
        if lengths.len() == 1 {
            let why = "at least 2 cable elements in all: one rigid element cannot lie on the seabed at o and reach (x_L, h_L)";
            c.push("cable.stages", "1 element", why);
            return None;
        }
        let x = match self.initial.layout()? {
            Layout::Projection(x) => x,
            layout @ (Layout::Tension(t) | Layout::TopTension(t)) => return self.check_tension_layout(c, layout, t),
        };
        if catenary::lay_elements(&lengths, x, h).is_ok() {
            return Some(x);
        }
        let expected = match catenary::laid_range(&lengths, h) {
            Some((lo, hi)) => format!(
                "in [{}, {}] m for cable length L_c = {} m and h_L = {} m: the cable grounded from o, then the \
                 catenary of Eqs. 30–34 up to (x_L, h_L) (L_c − h_L < x_L ≤ a asinh(L_c/a), a = (L_c² − h_L²)/(2 h_L); \
                 the rigid elements raise the lower end){}",
                (lo * 1e6).ceil() / 1e6,
                (hi * 1e6).floor() / 1e6,
                fmt_value(lc),
                fmt_value(h),
                vertical_hint(&lengths, x),
            ) + "; or lay the line by its tension instead (initial.horizontal_tension or initial.top_tension, N), which holds as the cable's length and h_L change",
            None => format!(
                "a value for which the {} cable elements lay on the catenary of Eqs. 30–34 (none does for h_L = {} m)",
                lengths.len(),
                fmt_value(h)
            ),
        };
        c.push("initial.horizontal_projection", &fmt_value(x), &expected);
        None
    }

    /// A line laid by T_h or T_t (`layout`, the value `t`, N): the x_L that lays it, or its
    /// problem with the range of tensions that lay ([`Scene::check_geometry`]).
    fn check_tension_layout(&self, c: &mut Checker, layout: Layout, t: f64) -> Option<f64> {
        let (h, lc, w) = (self.initial.vertical_projection, self.cable_length(), self.cable_weight_per_length());
        // A cable that does not sink is left to the sinking check.
        if !(w > 0.0 && w.is_finite()) {
            return None;
        }
        // T_t = w_c (a + h_L), T_h = w_c a.
        let (field, name, lift) = match layout {
            Layout::TopTension(_) => ("initial.top_tension", "T_t = w_c (a + h_L) (Eqs. 31, 33)", w * h),
            _ => ("initial.horizontal_tension", "T_h = w_c a (Eq. 31)", 0.0),
        };
        let e = match self.horizontal_projection() {
            Ok(x) => return Some(x),
            Err(e) => e,
        };
        let range = match e {
            CatenaryError::NoLineWithParameter { range: Some((lo, hi)), .. } => {
                // Open below (a line touching down at a sharp corner), closed above; a lower
                // bound rounded up to 6 digits is itself a tension that lays, and shown so.
                let (lo, lo_in) = fmt_bound(lo * w + lift, true);
                format!(
                    "in {}{lo}, {}] N for cable length L_c = {} m, h_L = {} m and w_c = {} N/m",
                    if lo_in { "[" } else { "(" },
                    fmt_bound(hi * w + lift, false).0,
                    fmt_value(lc),
                    fmt_value(h),
                    fmt_rounded(w, 3)
                )
            }
            _ => format!(
                "a tension at which the {} cable elements lay (none does here)",
                self.cable_element_lengths().len()
            ),
        };
        let why = format!(
            "{range}: {name} of the catenary the elements are laid on; lower, the rigid \
             elements cannot follow the curve's corner at the touchdown; higher, no cable is left on the seabed"
        );
        c.push(field, &fmt_value(t), &why);
        None
    }

    /// The length of every cable element, from the chain toward the ship, m.
    pub fn cable_element_lengths(&self) -> Vec<f64> {
        self.cable.stages.iter().flat_map(|s| std::iter::repeat_n(s.element_length, s.elements)).collect()
    }

    /// `[solver]`: step, end time, output interval and tolerances, each in its own range
    /// ([`Solver::check_fixed`]), and those bounded by each other.
    fn check_solver(&self, c: &mut Checker) {
        let so = &self.solver;
        so.check_fixed(c, false);
        // A step out of its own range bounds nothing else (an interval in [1e300, 1e15]).
        if so.dt.is_finite() && so.dt > 0.0 && so.dt <= MAX_DT {
            let hint = format!("s (at least solver.dt = {} s: raise it, or take a smaller step)", fmt_value(so.dt));
            c.range("solver.output_interval", so.output_interval, so.dt, MAX_MAGNITUDE, true, &hint);
            // An end time ≤ 0 is refused by its own range alone.
            if so.end_time.is_finite() && so.end_time > 0.0 && so.end_time < so.dt {
                c.push("solver.end_time", &fmt_value(so.end_time), &format!("≥ solver.dt = {} s", fmt_value(so.dt)));
            }
        }
        let steps = so.end_time / so.dt;
        if so.dt > 0.0 && so.end_time > 0.0 && so.end_time.is_finite() && steps > MAX_STEPS {
            let end_bound = fmt_significant(so.dt * MAX_STEPS, 3);
            // Beyond the longest step (1 s) only a shorter end time helps: that is the field to name.
            if so.end_time / MAX_STEPS > MAX_DT {
                let why = format!(
                    "≤ solver.dt × {MAX_STEPS:e} = {end_bound} s: {steps:.3e} steps exceed the limit of {MAX_STEPS:e}, \
                     and no step within solver.dt's range (≤ {MAX_DT} s) could make up for it"
                );
                c.push("solver.end_time", &fmt_value(so.end_time), &why);
            } else {
                let seconds = steps * 4.0 * self.body_count() as f64 * SECONDS_PER_BODY_EVALUATION;
                let why = format!(
                    "≥ solver.end_time / {MAX_STEPS:e} = {:.3e} s: {steps:.3e} steps exceed the limit of {MAX_STEPS:e} \
                     (about {seconds:.1e} s of RK4 wall time at N = {}); or solver.end_time ≤ {end_bound} s",
                    so.end_time / MAX_STEPS,
                    self.body_count(),
                );
                c.push("solver.dt", &fmt_value(so.dt), &why);
            }
        }
    }
}

impl Solver {
    /// The steps of `dt` (RK4's, or the adaptive methods' observation intervals) a run takes
    /// at most: the last whole one at or before `end_time` (a count a hair under a whole
    /// number by rounding, 0.6 / 0.002 = 299.99999999999994, is that number).
    pub fn steps(&self) -> u64 {
        (self.end_time / self.dt * (1.0 + 1e-12)).floor() as u64
    }

    /// When a run that goes on ends, s: after [`Solver::steps`] steps (0.5 s for an end time
    /// of 0.501 s at 2 ms).
    pub fn last_time(&self) -> f64 {
        self.steps() as f64 * self.dt
    }

    /// The fields' problems each on its own, in its fixed range, without the ranges another
    /// field bounds (output_interval ≥ dt, end_time ≥ dt, the step count), which a whole
    /// scene's [`Scene::problems`] adds: what a command line's flag can be checked against
    /// before any scene is read.
    pub fn own_problems(&self) -> Vec<Problem> {
        let mut c = Checker::default();
        self.check_fixed(&mut c, true);
        c.problems
    }

    /// The fixed ranges; `output_interval`'s own, (0, 1e15] s, only `with_output_interval`
    /// (a scene checks it against its dt instead).
    fn check_fixed(&self, c: &mut Checker, with_output_interval: bool) {
        c.range("solver.dt", self.dt, 0.0, MAX_DT, false, "s");
        // No magnitude cap: the step count's limit bounds it, and says so.
        c.range("solver.end_time", self.end_time, 0.0, f64::MAX, false, "s");
        if with_output_interval {
            c.range("solver.output_interval", self.output_interval, 0.0, MAX_MAGNITUDE, false, "s");
        }
        c.range("solver.max_energy_drift", self.max_energy_drift, MIN_ENERGY_DRIFT, 10.0, true, DRIFT_WHY);
        // Below 1e-14 double precision cannot meet it (`integrate::Tolerances`).
        c.range("solver.rtol", self.rtol, 1e-14, 0.1, true, "(relative tolerance; double precision cannot meet less)");
        c.range("solver.atol", self.atol, MIN_ATOL, 1.0, true, ATOL_WHY);
    }
}

/// "; or, for this x_L, initial.vertical_projection in [lo, hi] m": the h_L range in which
/// these cable elements lay with horizontal projection `x` (m), when there is one
/// ([`catenary::laid_vertical_range`]).
fn vertical_hint(lengths: &[f64], x: f64) -> String {
    match catenary::laid_vertical_range(lengths, x) {
        // Rounded inwards to 1e-6 m, unless the range is narrower than that.
        Some((lo, hi)) => {
            let (a, b) = ((lo * 1e6).ceil() / 1e6, (hi * 1e6).floor() / 1e6);
            let (a, b) = if a <= b { (fmt_value(a), fmt_value(b)) } else { (fmt_value(lo), fmt_value(hi)) };
            format!("; or, for this x_L, initial.vertical_projection in [{a}, {b}] m")
        }
        None => String::new(),
    }
}

impl Scene {
    /// `[checks]`: limits in their ranges.
    fn check_checks(&self, c: &mut Checker) {
        for (field, v, expected) in self.checks.iter().flat_map(|k| k.problems("checks")) {
            c.push(&field, &fmt_value(v), expected);
        }
    }
}

/// Every numeric field of a scene by dotted path (array indices left out) with its unit as the
/// field's documentation states it: "" for a dimensionless number or a count. Held to the doc
/// comments of this file and of `design.rs` by `tests/docs_fresh.rs`.
pub const UNITS: [(&str, &str); 54] = [
    ("meta.paper_stopping_time", "s"),
    ("environment.gravity", "m/s²"),
    ("environment.water_density", "kg/m³"),
    ("environment.kinematic_viscosity", "m²/s"),
    ("environment.seabed_stiffness", "N/m³"),
    ("environment.seabed_friction", ""),
    ("environment.line_friction", ""),
    ("environment.current_surface_speed", "m/s"),
    ("environment.current_exponent", ""),
    ("hydrodynamics.added_mass_coefficient", ""),
    ("hydrodynamics.normal_drag_coefficient", ""),
    ("hydrodynamics.tangential_drag_coefficient", ""),
    ("hydrodynamics.anchor_drag_coefficient", ""),
    ("anchor.mass", "kg"),
    ("anchor.length", "m"),
    ("anchor.width", "m"),
    ("anchor.height", "m"),
    ("chain.elements", ""),
    ("chain.element_length", "m"),
    ("chain.radius", "m"),
    ("chain.mass_per_length", "kg/m"),
    ("chain.proof_load", "N"),
    ("chain.break_load", "N"),
    ("cable.radius", "m"),
    ("cable.mass_per_length", "kg/m"),
    ("cable.break_load", "N"),
    ("cable.stages.elements", ""),
    ("cable.stages.element_length", "m"),
    ("rod.length", "m"),
    ("rod.radius", "m"),
    ("rod.mass_per_length", "kg/m"),
    ("ship.mass", "kg"),
    ("ship.length", "m"),
    ("ship.beam", "m"),
    ("ship.depth", "m"),
    ("ship.hull_roughness", "m"),
    ("ship.hinge_x", "m"),
    ("ship.hinge_z", "m"),
    ("initial.horizontal_projection", "m"),
    ("initial.horizontal_tension", "N"),
    ("initial.top_tension", "N"),
    ("initial.vertical_projection", "m"),
    ("initial.ship_speed", "m/s"),
    ("solver.dt", "s"),
    ("solver.rtol", ""),
    ("solver.atol", ""),
    ("solver.end_time", "s"),
    ("solver.output_interval", "s"),
    ("solver.max_energy_drift", ""),
    ("checks.max_stopping_distance", "m"),
    ("checks.max_stopping_time", "s"),
    ("checks.max_anchor_drag", "m"),
    ("checks.safety_factor", ""),
    ("checks.max_proof_utilisation", ""),
];

/// The unit of the scene field at a dotted path (`ship.mass` → `kg`,
/// `cable.stages[1].element_length` → `m`): "" for a dimensionless number or a count, none
/// for a path that names no number of a scene.
pub fn unit(path: &str) -> Option<&'static str> {
    let mut bare = String::with_capacity(path.len());
    let mut depth = 0usize;
    for c in path.chars() {
        match c {
            '[' => depth += 1,
            ']' => depth = depth.saturating_sub(1),
            c if depth == 0 => bare.push(c),
            _ => {}
        }
    }
    UNITS.iter().find(|(p, _)| *p == bare).map(|(_, u)| *u)
}

/// `path (unit)`, or the path alone for a dimensionless number, a count or an unknown path:
/// an axis label.
pub fn labelled(path: &str) -> String {
    match unit(path) {
        Some(u) if !u.is_empty() => format!("{path} ({u})"),
        _ => path.to_string(),
    }
}

/// The smallest `solver.max_energy_drift`: see the field.
pub const MIN_ENERGY_DRIFT: f64 = 1e-4;

/// Why `solver.max_energy_drift` has [`MIN_ENERGY_DRIFT`], in its refusal.
const DRIFT_WHY: &str = "(relative; a blow-up's detector: below it the integration's own drift stops sound runs)";

/// The smallest `solver.atol`: see the field.
pub const MIN_ATOL: f64 = 1e-16;

/// Why `solver.atol` has [`MIN_ATOL`], in its refusal.
const ATOL_WHY: &str =
    "(absolute tolerance; below it a component at zero, such as a work term at the start, has no error the steps can meet)";

/// The largest scene file read, bytes: a scene is a few kB; a larger file (or `/dev/zero`)
/// is no scene and would only fill the memory.
pub const MAX_SCENE_BYTES: u64 = 16 << 20;

/// A scene file's text: a regular file of at most [`MAX_SCENE_BYTES`].
fn read_scene_file(path: &Path) -> std::io::Result<String> {
    read_text_file(path, MAX_SCENE_BYTES, "a scene's")
}

/// The text of an input file (a scene, a sweep spec, a state, a shard file): a regular file
/// of at most `max` bytes, `whose` naming the limit in the error ("a scene's"). Anything else
/// (`/dev/zero`, a folder, a file far larger than its kind) is refused before it is read:
/// read whole, it would only fill the memory.
pub fn read_text_file(path: &Path, max: u64, whose: &str) -> std::io::Result<String> {
    let meta = std::fs::metadata(path)?;
    if !meta.is_file() {
        return Err(std::io::Error::other("not a regular file"));
    }
    if meta.len() > max {
        return Err(std::io::Error::other(format!("{} bytes, more than {whose} {max}", meta.len())));
    }
    std::fs::read_to_string(path)
}

/// Deserialises `value` (a table built in memory: Python's dict, a scene with overrides); an
/// error ends `in `PATH`` with the array indices in its path (`cable.stages[1].elements`),
/// where toml's own names only the keys (`cable.stages.elements`).
pub fn from_value_at<T: serde::de::DeserializeOwned>(value: toml::Value) -> Result<T, String> {
    serde_path_to_error::deserialize(value).map_err(|e| {
        let path = e.path().to_string();
        let text = e.into_inner().to_string();
        let message = text.trim_end().rsplit_once("\nin `").map_or(text.trim_end(), |(m, _)| m).trim_end();
        if path.is_empty() || path == "." {
            message.to_string()
        } else {
            format!("{message}\nin `{path}`")
        }
    })
}

/// A TOML reader's message with Rust's type names in words: `expected usize` → `expected a
/// whole number ≥ 0`, `expected f64` → `expected a number`; and the number it quotes as the
/// file would write it (`1e300` for a whole number field, not 301 digits).
pub fn plain_types(message: &str) -> String {
    const QUOTED: &str = "floating point `";
    let mut out = match message.split_once(QUOTED) {
        Some((before, rest)) => match rest.split_once('`') {
            Some((number, after)) => match number.parse::<f64>() {
                Ok(v) if extreme(v) => format!("{before}{QUOTED}{}`{after}", fmt_value(v)),
                _ => message.to_string(),
            },
            None => message.to_string(),
        },
        None => message.to_string(),
    };
    for (rust, words) in [
        ("usize", "a whole number ≥ 0"),
        ("u64", "a whole number ≥ 0"),
        ("u32", "a whole number ≥ 0"),
        ("i64", "a whole number"),
        ("i32", "a whole number"),
        ("f64", "a number"),
    ] {
        out = out.replace(&format!("expected {rust}"), &format!("expected {words}"));
    }
    // `expected struct CableStage` → `expected a table`: the file's word, not the type's.
    const STRUCT: &str = "expected struct ";
    while let Some(i) = out.find(STRUCT) {
        let name = out[i + STRUCT.len()..].chars().take_while(|c| c.is_ascii_alphanumeric() || *c == '_').count();
        out.replace_range(i..i + STRUCT.len() + name, "expected a table");
    }
    out
}

/// Formats a value the way a user would write it in the TOML file: as written for ordinary
/// magnitudes, with an exponent (`1e300`, `2.5e-12`) beyond them rather than hundreds of digits.
pub fn fmt_value(v: f64) -> String {
    if v.is_nan() {
        "nan".into()
    } else if extreme(v) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// A bound of a range the message computed, to 6 significant digits, rounded inwards: up
/// for a lower bound (`up`), down for an upper one, so that the range shown holds. The value
/// shown and whether it is itself in the range: a rounded bound is, the exact one (its 6
/// digits already all there is) is not when the range is open there.
fn fmt_bound(v: f64, up: bool) -> (String, bool) {
    if !(v.is_finite() && v != 0.0) {
        return (fmt_value(v), false);
    }
    let scale = 10f64.powi(5 - v.abs().log10().floor() as i32);
    let digits = if up { (v * scale).ceil() } else { (v * scale).floor() };
    let mut r = digits / scale;
    // The product and the quotient round: a bound that came back outside its range moves a
    // digit inwards.
    if (up && r < v) || (!up && r > v) {
        r = (digits + if up { 1.0 } else { -1.0 }) / scale;
    }
    (fmt_value(r), r != v)
}

/// A value the message computed (a bound, a depth), rounded to `decimals` places; in
/// scientific notation with `decimals` digits after the point where positional notation would
/// show no significant digit or hundreds of them.
fn fmt_rounded(v: f64, decimals: usize) -> String {
    if extreme(v) {
        format!("{v:.decimals$e}")
    } else {
        format!("{v:.decimals$}")
    }
}

/// A value the message computed, to `digits` significant digits and no more digits than
/// they need (`0.01`, `20000`, `1.23e-12`).
fn fmt_significant(v: f64, digits: usize) -> String {
    let rounded: f64 = format!("{v:.*e}", digits.saturating_sub(1)).parse().unwrap_or(v);
    fmt_value(rounded)
}

/// Whether a finite, non-zero `v` is too large or too small to read in positional notation.
fn extreme(v: f64) -> bool {
    v.is_finite() && v != 0.0 && !(1e-9..1e15).contains(&v.abs())
}

/// The largest value a positive or non-negative field takes, in its SI unit: far beyond any
/// ship, anchor or line (a 1e15 kg anchor, a 1e15 m element still run and are refused or
/// reported by the physics' own checks), while 1e300 overflowed the products of the loads
/// and the solve into a non-finite acceleration at t = 0 that looked like a step-size failure.
pub const MAX_MAGNITUDE: f64 = 1e15;

/// The smallest value a positive field takes, in its SI unit: far below any ship, anchor or
/// line, while 1e-100 m links, a 1e-300 m rod or a 2.9e-106 kg ship (a wide lognormal
/// sample) underflowed the equations into a non-finite acceleration or an unconverged
/// stability analysis at t = 0, reported as a numerical failure of the rod (exit 3).
pub const MIN_MAGNITUDE: f64 = 1e-15;

/// The range of `environment.water_density`, kg/m³: fresh water is 1000 (958 at 100 °C), sea
/// water about 1025, the densest natural brines (the Dead Sea) about 1240.
pub const WATER_DENSITY: (f64, f64) = (900.0, 1300.0);

/// The smallest draught of a ship afloat, as a fraction of its depth (keel to deck): an empty
/// steel barge floats on about a tenth of its depth; below a hundredth the hull is a plate,
/// and the mass is one in tonnes.
pub const MIN_DRAUGHT_FRACTION: f64 = 0.01;

/// The shortest breaking length of a line, m: its break load over its weight per metre in
/// air. Steel chain and wire rope break under kilometres of their own length (case 1's chain
/// 2.7 km, its cable 18.6 km; fibre ropes more), so a break load below 100 m of the line's
/// weight is a unit slip (kN for N gives metres), not a line.
pub const MIN_BREAKING_LENGTH: f64 = 100.0;

/// Standard gravity g₀, m/s², by which a line's breaking length is defined (whatever the
/// scene's `environment.gravity`).
pub const STANDARD_GRAVITY: f64 = 9.80665;

/// Upper bound of the hydrodynamic coefficients (`[hydrodynamics]`), dimensionless.
///
/// Published coefficients stay below 3: studless chain C_D ≈ 2.4 and C_F ≈ 1.15 on the nominal
/// diameter, wire rope C_D ≈ 1.2, C_M ≈ 1–2, a block anchor's C_D ≈ 1–2. A hundred leaves room
/// for marine growth and for deliberately damped bounding cases (the integrators benchmark's
/// control has the line's drag ×20, C_D = 24.2; case 1 still stops at C_D = 100); far beyond
/// it a coefficient is a typo, and the run failed on a stiffness that read as something else
/// (C_D = 1e6 was diagnosed as a mass ratio).
pub const MAX_HYDRO_COEFFICIENT: f64 = 100.0;

#[derive(Default)]
struct Checker {
    problems: Vec<Problem>,
}

impl Checker {
    fn push(&mut self, field: &str, value: &str, expected: &str) {
        self.problems.push(Problem { field: field.into(), value: value.into(), expected: expected.into() });
    }

    fn positive(&mut self, field: &str, v: f64, unit: &str) {
        if !(v.is_finite() && v > 0.0) {
            self.push(field, &fmt_value(v), &format!("finite and > 0 {unit}"));
        } else if v < MIN_MAGNITUDE {
            self.push(
                field,
                &fmt_value(v),
                &format!("at least {MIN_MAGNITUDE:e} {unit}: smaller values underflow the products of the equations"),
            );
        } else {
            self.magnitude(field, v, unit);
        }
    }

    fn non_negative(&mut self, field: &str, v: f64, unit: &str) {
        if !(v.is_finite() && v >= 0.0) {
            self.push(field, &fmt_value(v), &format!("finite and ≥ 0 {unit}"));
        } else {
            self.magnitude(field, v, unit);
        }
    }

    /// At most [`MAX_MAGNITUDE`].
    fn magnitude(&mut self, field: &str, v: f64, unit: &str) {
        if v > MAX_MAGNITUDE {
            self.push(
                field,
                &fmt_value(v),
                &format!("at most {MAX_MAGNITUDE:e} {unit}: larger values overflow the products of the equations"),
            );
        }
    }

    /// `lo < v ≤ hi` (or `lo ≤ v` when `closed_low`).
    fn range(&mut self, field: &str, v: f64, lo: f64, hi: f64, closed_low: bool, unit: &str) {
        let ok = v.is_finite() && (if closed_low { v >= lo } else { v > lo }) && v <= hi;
        if !ok {
            let open = if closed_low { "[" } else { "(" };
            let hi_text = if hi == f64::MAX { "∞)".to_string() } else { format!("{}]", fmt_value(hi)) };
            self.push(field, &fmt_value(v), &format!("in {open}{}, {hi_text} {unit}", fmt_value(lo)));
        }
    }
}
