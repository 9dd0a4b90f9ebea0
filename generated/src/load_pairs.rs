//! The two-lane element loads (`load_element_pair_<signature>`) against the single element's
//! (`load_element_<signature>`), directly: for every signature with line elements, pairs of
//! random elements and states, special values among them (signed zeros, NaN, infinities, a
//! level element, an element at the surface or on the seabed, a zero length), the rod in
//! air on either lane. Each lane's load and each of its powers must equal the single
//! element's bit for bit (a NaN's sign and payload aside, which Rust leaves unspecified).
//! The scene-level tests (`tests/fused_loads.rs`) hold both to the force modules.

use crate::lanes::F2;
use crate::loads::*;
use crate::{BodyParams, Element, LoadParams, POWER_TERMS};

/// xorshift64*: deterministic, no dependency.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    fn uniform(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * ((self.next() >> 11) as f64 / (1u64 << 53) as f64)
    }

    fn one_in(&mut self, n: u64) -> bool {
        self.next().is_multiple_of(n)
    }

    /// A number in (−scale, scale), now and then a special value.
    fn value(&mut self, scale: f64) -> f64 {
        const SPECIAL: [f64; 7] = [0.0, -0.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 5e-324, 1.0];
        match self.next() % 40 {
            i if (i as usize) < SPECIAL.len() => SPECIAL[i as usize],
            _ => self.uniform(-scale, scale),
        }
    }
}

fn no_volumes(_: &[Element], _: &mut [[f64; 3]]) {}

fn load_params(r: &mut Rng) -> LoadParams {
    LoadParams {
        g: 9.81,
        rho: 1025.0,
        seabed_z: -r.uniform(5.0, 50.0),
        seabed_stiffness: r.uniform(1e3, 1e6),
        line_friction: r.uniform(0.1, 1.0),
        slip_speed: r.uniform(0.01, 0.1),
        normal_drag: 1.2,
        tangential_drag: 0.4,
        current_speed: r.uniform(-2.0, 2.0),
        current_exponent: 1.0 / 7.0,
        water_depth: r.uniform(5.0, 50.0),
        // The anchor's and the ship's numbers: not read by the element loads.
        anchor_volume: 1.0,
        anchor_area: 1.0,
        anchor_drag: 1.0,
        ship_volume: 1.0,
        ship_waterplane_area: 1.0,
        ship_metacentric_height: 1.0,
        ship_wetted_surface: 1.0,
        ship_length: 1.0,
        viscosity: 1e-6,
        roughness_allowance: 0.0,
        min_reynolds: 1e5,
        embedded_volumes: no_volumes,
    }
}

/// One element: its parameters, state `[x, z, θ, v_x, v_z, ω]`, rotation and contact row.
struct Body {
    p: BodyParams,
    e: Element,
    s: [f64; 6],
    t: [f64; 2],
    contact: [f64; 3],
}

fn body(r: &mut Rng, lp: &LoadParams) -> Body {
    let p = BodyParams { mass: r.uniform(1.0, 100.0), added_mass: r.uniform(0.0, 50.0), ..Default::default() };
    let length = if r.one_in(30) { 0.0 } else { r.uniform(0.1, 3.0) };
    let e = Element::new(lp, length, r.uniform(0.01, 0.1), !r.one_in(4));
    let theta = match r.next() % 6 {
        0 => 0.0,
        1 => std::f64::consts::FRAC_PI_2,
        2 => -std::f64::consts::FRAC_PI_2,
        _ => r.uniform(-3.2, 3.2),
    };
    let mut t = [theta.cos(), theta.sin()];
    if r.one_in(10) {
        t = [1.0, if r.one_in(2) { 0.0 } else { -0.0 }];
    }
    if r.one_in(50) {
        t[1] = f64::NAN;
    }
    let reach = 0.5 * length * t[1].abs();
    let z = match r.next() % 8 {
        0 => 0.0,
        1 => -0.0,
        2 => lp.seabed_z,
        3 => reach,
        4 => -reach,
        5 => r.value(2.0),
        _ => r.uniform(-60.0, 5.0),
    };
    let s = [r.value(10.0), z, theta, r.value(3.0), r.value(3.0), r.value(3.0)];
    let contact = match r.next() % 6 {
        0 => [0.0; 3],
        1 => [-0.0, 0.0, 0.0],
        2 => [f64::NAN, f64::NAN, 0.0],
        _ => [r.uniform(0.0, 0.01), r.uniform(0.0, length), 0.0],
    };
    Body { p, e, s, t, contact }
}

/// The bits of `x`, every NaN as one.
fn bits(x: f64) -> u64 {
    if x.is_nan() {
        1
    } else {
        x.to_bits()
    }
}

macro_rules! pairs_equal_singles {
    ($($test:ident $single:ident $pair:ident),* $(,)?) => {
        /// The signatures checked here, against the registry's.
        const CHECKED: &[&str] = &[$(stringify!($test)),*];
        $(
            #[test]
            fn $test() {
                let mut r = Rng(0x9E37_79B9_7F4A_7C15 ^ stringify!($test).len() as u64);
                let mut rods = [0usize; 2];
                for _ in 0..100_000 {
                    let lp = load_params(&mut r);
                    let b = [body(&mut r, &lp), body(&mut r, &lp)];
                    let mut lanes = [F2::splat(0.0); POWER_TERMS];
                    let pair = $pair(
                        [&b[0].p, &b[1].p], &lp, [&b[0].e, &b[1].e], [&b[0].s, &b[1].s],
                        [&b[0].t, &b[1].t], [b[0].contact, b[1].contact], &mut lanes,
                    );
                    for (i, b) in b.iter().enumerate() {
                        rods[i] += usize::from(!b.e.line);
                        let mut power = [0.0; POWER_TERMS];
                        let single = $single(&b.p, &lp, &b.e, &b.s, &b.t, b.contact, &mut power);
                        assert_eq!(pair[i].map(bits), single.map(bits), "lane {i}: {:?} {:?} {:?}", b.s, b.t, b.contact);
                        let lane_power = lanes.map(|l| l.lanes()[i]);
                        assert_eq!(lane_power.map(bits), power.map(bits), "lane {i}'s powers: {:?}", b.s);
                    }
                }
                assert!(rods[0] > 1000 && rods[1] > 1000, "the rod in air on each lane: {rods:?}");
            }
        )*
    };
}

pairs_equal_singles!(
    dry_seabed load_element_dry_seabed load_element_pair_dry_seabed,
    dry_seabed_friction load_element_dry_seabed_friction load_element_pair_dry_seabed_friction,
    wet load_element_wet load_element_pair_wet,
    wet_current load_element_wet_current load_element_pair_wet_current,
    wet_seabed load_element_wet_seabed load_element_pair_wet_seabed,
    wet_seabed_friction load_element_wet_seabed_friction load_element_pair_wet_seabed_friction,
    wet_seabed_current load_element_wet_seabed_current load_element_pair_wet_seabed_current,
    wet_seabed_friction_current load_element_wet_seabed_friction_current load_element_pair_wet_seabed_friction_current,
);

#[test]
fn every_signature_with_line_elements_is_checked() {
    let registry: Vec<&str> = crate::rhs::RHS.iter().map(|(name, _)| *name).filter(|n| *n != "dry").collect();
    assert_eq!(registry, CHECKED);
}
