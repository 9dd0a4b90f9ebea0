//! The paper's statements about its results, each as a test (issue 19). Table 3's values are
//! checked case by case in `paper_cases.rs`; here are the paper's other claims (Sections 4.2
//! and 4.3) and Table 3's trends (each case's stopping time minus case 1's).
//!
//! Every claim is a pure function of the measured numbers, so it can be shown to fail on
//! changed data (the `*_flipped` tests, some on a changed scene). The 19 cases run once, in
//! parallel, and are shared by the tests. The figures in `docs/validation.md` between the
//! `claims:begin` / `claims:end` markers are rendered here: a stale file fails
//! `validation_doc_is_fresh` and is rewritten. The figures other docs quote from these runs
//! in prose are checked by `prose_figures_are_what_the_runs_give` and
//! `readme_figures_are_what_the_code_computes` (docs/validation.md lists every doc check).
//!
//! Thresholds (fixed before measuring; docs/validation.md says why): over a group of cases
//! (case 1 and the cases that change one parameter), the spread of the peak tension is
//! (max − min) / case 1's; "significantly influenced" is a spread ≥ 10 %, "a little effect"
//! 2 % ≤ spread < 10 %, "no influence" < 2 %. The peak is the chain's: the largest tension at
//! any joint with a chain link on one side (joints 2–17 in case 1), over every step.

use std::sync::OnceLock;

use kanestop_runtime::generated::GeneratedKernel;
use kanestop_runtime::model::Model;
use kanestop_runtime::paper::CASES;
use kanestop_runtime::scene::Scene;
use kanestop_runtime::simulate::{self, RunResult, Stop};

// ---- thresholds -------------------------------------------------------------------------

/// "Influenced significantly": the group's peak spread is at least this.
const SIGNIFICANT: f64 = 0.10;
/// "No influence": the group's peak spread is below this ("a little" lies in between).
const NONE: f64 = 0.02;
/// "About 2.2 times" at 5 m/s: within 10 % of 2.2.
const SPEED_RATIO: (f64, f64) = (2.2 * 0.9, 2.2 * 1.1);
/// "Approximately 1.5 seconds": within 0.5 s.
const ANCHOR_START: (f64, f64) = (1.0, 2.0);
/// Eq. 63's balance "below 0.5 %".
const ENERGY: f64 = 0.005;
/// A trend is reproduced when the case's difference to case 1 is within this of the paper's,
/// or within `TREND_REL` of the paper's difference, whichever is larger.
const TREND_ABS: f64 = 0.2;
const TREND_REL: f64 = 0.10;
/// Step-size check: the stopping time within this (s) and the chain peak within `NONE`
/// across dt = 0.001, 0.002 and 0.004 s.
const STEP_TIME: f64 = 0.01;

// ---- the runs ---------------------------------------------------------------------------

/// What one run of a paper case gave, with the joints' limits.
struct Measured {
    number: usize,
    change: &'static str,
    paper: f64,
    result: RunResult,
    /// Joints k (index k − 2) with a chain link on one side.
    chain_joint: Vec<bool>,
    /// (proof, breaking) of each joint k (index k − 2), N.
    limits: Vec<(Option<f64>, Option<f64>)>,
}

impl Measured {
    fn time(&self) -> f64 {
        assert_eq!(self.result.stop, Stop::ShipStopped, "case {}: {:?}", self.number, self.result.stop);
        self.result.stopping_time.unwrap()
    }
    /// The chain peak (N) and its joint k.
    fn chain_peak(&self) -> (f64, usize) {
        chain_peak(&self.result, &self.chain_joint)
    }
    fn all_peak(&self) -> (f64, usize) {
        let (k, p) = self.result.peak_tension().unwrap();
        (p.tension, k)
    }
    fn peaks(&self) -> Vec<f64> {
        self.result.peak_tensions.iter().map(|p| p.tension).collect()
    }
}

fn chain_peak(r: &RunResult, chain_joint: &[bool]) -> (f64, usize) {
    r.peak_tensions
        .iter()
        .enumerate()
        .filter(|(i, _)| chain_joint[*i])
        .map(|(i, p)| (p.tension, i + 2))
        .max_by(|a, b| a.0.total_cmp(&b.0))
        .unwrap()
}

fn measure(number: usize, scene: &Scene) -> Measured {
    let case = CASES.iter().find(|c| c.number == number).unwrap();
    let model = Model::new(scene).unwrap();
    let result = simulate::run(&model, Box::new(GeneratedKernel::new(&model.chain).unwrap()));
    let joints = 2..=model.body_count();
    let limits: Vec<_> = joints.clone().map(|k| model.joint_limits(k)).map(|l| (l.proof, l.breaking)).collect();
    // A joint with a chain link on one side is the one whose limit includes the chain's proof load.
    let chain_joint = limits.iter().map(|l| l.0.is_some()).collect();
    Measured { number, change: case.change, paper: case.stopping_time, result, chain_joint, limits }
}

/// The 19 cases at the paper's dt = 0.002 s, then case 1 at 0.001 s and 0.004 s.
fn runs() -> &'static [Measured] {
    static RUNS: OnceLock<Vec<Measured>> = OnceLock::new();
    RUNS.get_or_init(|| {
        let mut jobs: Vec<(usize, Scene)> = CASES.iter().map(|c| (c.number, c.scene())).collect();
        for dt in [0.001, 0.004] {
            let mut s = CASES[0].scene();
            s.solver.dt = dt;
            s.solver.output_interval = s.solver.output_interval.max(dt);
            jobs.push((1, s));
        }
        // Two workers: the machine has two cores.
        let next = std::sync::atomic::AtomicUsize::new(0);
        let mut out: Vec<Option<Measured>> = (0..jobs.len()).map(|_| None).collect();
        let done = std::sync::Mutex::new(&mut out);
        std::thread::scope(|s| {
            for _ in 0..2 {
                s.spawn(|| loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                    let Some((n, scene)) = jobs.get(i) else { break };
                    let m = measure(*n, scene);
                    done.lock().unwrap()[i] = Some(m);
                });
            }
        });
        out.into_iter().map(Option::unwrap).collect()
    })
}

fn case(n: usize) -> &'static Measured {
    &runs()[n - 1]
}

fn chain_peaks(group: &[usize]) -> Vec<f64> {
    group.iter().map(|&n| case(n).chain_peak().0).collect()
}

// ---- the claims, as pure functions ------------------------------------------------------

/// (max − min) / the first (case 1's).
fn spread(peaks: &[f64]) -> f64 {
    let max = peaks.iter().cloned().fold(f64::MIN, f64::max);
    let min = peaks.iter().cloned().fold(f64::MAX, f64::min);
    (max - min) / peaks[0]
}

fn significant(peaks: &[f64]) -> bool {
    spread(peaks) >= SIGNIFICANT
}

fn little(peaks: &[f64]) -> bool {
    (NONE..SIGNIFICANT).contains(&spread(peaks))
}

fn no_influence(peaks: &[f64]) -> bool {
    spread(peaks) < NONE
}

/// "The maximum tensions become increasingly big at the higher numbered joints": every
/// joint's peak is at least (1 − NONE) times the largest peak at any lower-numbered joint.
/// Returns the first joint k that breaks it, or None.
fn first_decrease(peaks: &[f64]) -> Option<usize> {
    let mut max = 0.0f64;
    for (i, &p) in peaks.iter().enumerate() {
        if p < (1.0 - NONE) * max {
            return Some(i + 2);
        }
        max = max.max(p);
    }
    None
}

/// Joints above their proof or break load: (k, tension, limit).
fn over_limits(peaks: &[f64], limits: &[(Option<f64>, Option<f64>)]) -> Vec<(usize, f64, f64)> {
    let mut over = Vec::new();
    for (i, (&p, l)) in peaks.iter().zip(limits).enumerate() {
        for limit in [l.0, l.1].into_iter().flatten() {
            if p >= limit {
                over.push((i + 2, p, limit));
            }
        }
    }
    over
}

fn speed_ratio_holds(ratio: f64) -> bool {
    (SPEED_RATIO.0..=SPEED_RATIO.1).contains(&ratio)
}

fn anchor_start_holds(t: f64) -> bool {
    (ANCHOR_START.0..=ANCHOR_START.1).contains(&t)
}

fn energy_holds(drifts: &[f64]) -> bool {
    drifts.iter().all(|&d| d < ENERGY)
}

/// (stopping-time difference to case 1 − the paper's), s.
fn trend_error(t: f64, t1: f64, paper: f64, paper1: f64) -> f64 {
    (t - t1) - (paper - paper1)
}

fn trend_holds(error: f64, paper_difference: f64) -> bool {
    error.abs() <= TREND_ABS.max(TREND_REL * paper_difference.abs())
}

/// Step-size check: (stopping times, chain peaks) at several steps agree.
fn step_size_holds(times: &[f64], peaks: &[f64]) -> bool {
    let (lo, hi) = times.iter().fold((f64::MAX, f64::MIN), |(a, b), &t| (a.min(t), b.max(t)));
    hi - lo < STEP_TIME && no_influence(peaks)
}

// ---- the groups -------------------------------------------------------------------------

const FRICTION: [usize; 3] = [1, 2, 3];
const ANCHOR_MASS: [usize; 3] = [1, 4, 5];
const DEPTH: [usize; 3] = [1, 12, 13];
const SPEED: [usize; 3] = [1, 14, 15];
const SHIP_MASS: [usize; 3] = [1, 16, 17];
const CURRENT: [usize; 3] = [1, 18, 19];
const CHAIN_RADIUS: [usize; 3] = [1, 6, 7];
const CABLE_LENGTH: [usize; 3] = [1, 8, 9];
const PROJECTION: [usize; 3] = [1, 10, 11];

/// Trends the model does not reproduce within the bound, with the error measured (s) and the
/// margin asserted around it: a fix fails the test, so the doc is updated with it.
/// Case 19: the 2 m/s following current adds 0.48 s more than in the paper (docs/validation.md,
/// "Case 19").
const TREND_EXCEPTIONS: [(usize, f64); 1] = [(19, 0.48)];

// ---- Section 4.3.7 (Figure 33) ----------------------------------------------------------

#[test]
fn peaks_influenced_significantly_by_friction_anchor_mass_depth_and_speed() {
    // Section 4.3.7: "the constraint peaks are influenced significantly by frictional
    // coefficient, anchor mass, water depth and initial ship velocity".
    for (what, group) in [("friction", FRICTION), ("anchor mass", ANCHOR_MASS), ("depth", DEPTH), ("speed", SPEED)] {
        let p = chain_peaks(&group);
        assert!(significant(&p), "{what} {group:?}: chain peaks {p:?}, spread {:.1} %", 100.0 * spread(&p));
    }
}

#[test]
fn peak_at_5_m_s_is_about_2_2_times_case_1() {
    // Sections 4.3.4 ("nearly 2.2 times larger") and 4.3.7.
    let ratio = case(15).chain_peak().0 / case(1).chain_peak().0;
    assert!(speed_ratio_holds(ratio), "case 15 / case 1 chain peak {ratio:.3}");
}

#[test]
fn ship_mass_and_current_have_a_little_effect_on_the_peaks() {
    // Section 4.3.7: "the ship displacement mass and current have a little effect on the peaks"
    // (4.3.5, 4.3.6).
    for (what, group) in [("ship mass", SHIP_MASS), ("current", CURRENT)] {
        let p = chain_peaks(&group);
        assert!(little(&p), "{what} {group:?}: chain peaks {p:?}, spread {:.1} %", 100.0 * spread(&p));
    }
}

#[test]
fn chain_radius_cable_length_and_projection_have_no_influence_on_the_peaks() {
    // Section 4.3.7: "anchor chain radius, cable length and its horizontal projected length
    // have no influence on the maximum values".
    for (what, group) in [("cable length", CABLE_LENGTH), ("projection", PROJECTION)] {
        let p = chain_peaks(&group);
        assert!(no_influence(&p), "{what} {group:?}: chain peaks {p:?}, spread {:.1} %", 100.0 * spread(&p));
    }
    // Not reproduced for the chain radius: the heavier chains (1.3× and 1.6× case 1's unit
    // mass) raise the chain peak by 1.2 % and 2.6 %, "a little" by the thresholds fixed
    // beforehand (docs/validation.md). Asserted as measured, so a change shows.
    let p = chain_peaks(&CHAIN_RADIUS);
    assert!(
        !no_influence(&p) && little(&p),
        "chain radius {CHAIN_RADIUS:?}: chain peaks {p:?}, spread {:.1} %",
        100.0 * spread(&p)
    );
    assert!(p[0] < p[1] && p[1] < p[2], "chain peaks rise with the chain's weight: {p:?}");
}

#[test]
fn peaks_grow_toward_the_higher_numbered_joints() {
    // Section 4.3.7: "for each case, the maximum tensions become increasingly big at the
    // 'higher numbered' joints".
    for m in &runs()[..19] {
        let p = m.peaks();
        assert_eq!(first_decrease(&p), None, "case {}: joint peaks (kN) {:?}", m.number, kn(&p));
    }
}

#[test]
fn peaks_stay_below_proof_and_break_load() {
    // Sections 4.2 and 4.3.7: the peaks are "well below the proof stress of the chain
    // selected and the yield stress of the cable".
    for m in &runs()[..19] {
        let over = over_limits(&m.peaks(), &m.limits);
        assert!(over.is_empty(), "case {}: (joint, tension, limit) {over:?}", m.number);
    }
}

// ---- Sections 4.2 and 4.3.1 -------------------------------------------------------------

#[test]
fn anchor_starts_about_1_5_s_after_the_start() {
    // Section 4.3.1: "It takes approximately 1.5 seconds before anchor movement occurs."
    let t = case(1).result.anchor_start().expect("the anchor slides in case 1");
    assert!(anchor_start_holds(t), "case 1: anchor starts at {t:.3} s");
}

#[test]
fn energy_balance_holds_within_half_a_percent() {
    // Section 4.2 (Eq. 63): the balance drifts by less than 0.5 % in every case.
    let drifts: Vec<f64> = runs().iter().map(|m| m.result.max_energy_drift).collect();
    assert!(energy_holds(&drifts), "{drifts:?}");
}

#[test]
fn the_step_of_0_002_s_is_converged() {
    // Section 4.2 (Figure 14): "different time steps were examined".
    let (times, peaks) = step_study();
    assert!(step_size_holds(&times, &peaks), "dt 0.002, 0.001, 0.004 s: stop {times:?} s, chain peak {peaks:?} N");
}

fn step_study() -> (Vec<f64>, Vec<f64>) {
    let r = [&runs()[0], &runs()[19], &runs()[20]];
    (r.iter().map(|m| m.time()).collect(), r.iter().map(|m| m.chain_peak().0).collect())
}

// ---- Table 3's trends -------------------------------------------------------------------

#[test]
fn table_3_differences_to_case_1_are_reproduced() {
    let (t1, p1) = (case(1).time(), case(1).paper);
    let mut failures = Vec::new();
    for m in &runs()[1..19] {
        let e = trend_error(m.time(), t1, m.paper, p1);
        match TREND_EXCEPTIONS.iter().find(|x| x.0 == m.number) {
            Some(&(_, measured)) => {
                assert!(!trend_holds(e, m.paper - p1), "case {}: now reproduced ({e:+.3} s): update the doc", m.number);
                assert!(
                    (e - measured).abs() < 0.05,
                    "case {}: trend error {e:+.3} s, documented {measured:+.2} s",
                    m.number
                );
            }
            None if !trend_holds(e, m.paper - p1) => failures.push(format!("case {}: {e:+.3} s", m.number)),
            None => {}
        }
    }
    assert!(failures.is_empty(), "differences to case 1 off the paper's by more than the bound: {failures:?}");
}

// ---- the checkers fail on broken claims -------------------------------------------------

fn run_scene(number: usize, scene: &Scene) -> Measured {
    measure(number, scene)
}

#[test]
fn claims_fail_when_flipped() {
    // On data: each checker rejects the opposite of its claim.
    assert!(!significant(&[400e3, 410e3, 420e3]) && significant(&[400e3, 450e3, 500e3]));
    assert!(!little(&[400e3, 401e3, 402e3]) && !little(&[400e3, 450e3, 500e3]) && little(&[400e3, 410e3, 420e3]));
    assert!(!no_influence(&[400e3, 410e3, 420e3]) && no_influence(&[400e3, 401e3, 402e3]));
    assert_eq!(first_decrease(&[1.0, 2.0, 1.5, 3.0]), Some(4));
    assert_eq!(first_decrease(&[1.0, 2.0, 1.99, 3.0]), None);
    assert_eq!(over_limits(&[1.0, 5.0], &[(Some(4.0), Some(6.0)), (None, Some(6.0))]), vec![]);
    assert_eq!(over_limits(&[1.0, 5.0], &[(Some(4.0), Some(6.0)), (Some(4.0), Some(6.0))]), vec![(3, 5.0, 4.0)]);
    assert!(!speed_ratio_holds(1.0) && !speed_ratio_holds(2.5) && speed_ratio_holds(2.2));
    assert!(!anchor_start_holds(0.4) && anchor_start_holds(1.5));
    assert!(!energy_holds(&[1e-8, 0.006]));
    assert!(!trend_holds(0.3, 1.0) && trend_holds(0.3, 4.0) && trend_holds(0.15, 0.0));
    assert!(!step_size_holds(&[19.8, 19.82], &[4e5, 4e5]) && !step_size_holds(&[19.8, 19.8], &[4e5, 4.2e5]));
}

#[test]
fn claims_fail_on_changed_scenes() {
    // Friction made irrelevant: cases 2 and 3 with case 1's μ. The friction group's peaks no
    // longer differ significantly.
    let same_mu: Vec<Measured> = [2, 3]
        .iter()
        .map(|&n| {
            let mut s = CASES[n - 1].scene();
            s.environment.seabed_friction = CASES[0].friction;
            run_scene(n, &s)
        })
        .collect();
    let p = [case(1).chain_peak().0, same_mu[0].chain_peak().0, same_mu[1].chain_peak().0];
    assert!(!significant(&p), "friction group with one μ: {p:?}");
    // Case 15 at case 1's speed: not 2.2 times.
    let mut s = CASES[14].scene();
    s.initial.ship_speed = CASES[0].ship_speed;
    let slow = run_scene(15, &s);
    assert!(!speed_ratio_holds(slow.chain_peak().0 / case(1).chain_peak().0));
    // A heavier anchor chain (cases 6, 7 with 4× the unit mass): the chain radius now matters.
    let heavy: Vec<f64> = [6, 7]
        .iter()
        .map(|&n| {
            let mut s = CASES[n - 1].scene();
            s.chain.mass_per_length *= 4.0 * (n - 5) as f64;
            run_scene(n, &s).chain_peak().0
        })
        .collect();
    let p = [case(1).chain_peak().0, heavy[0], heavy[1]];
    assert!(!no_influence(&p), "heavy chains: {p:?}");
    // A chain proof load of 100 kN: exceeded.
    let mut s = CASES[0].scene();
    s.chain.proof_load = 100e3;
    let weak = run_scene(1, &s);
    assert!(!over_limits(&weak.peaks(), &weak.limits).is_empty());
}

// ---- the rendered figures in docs/validation.md -----------------------------------------

fn kn(p: &[f64]) -> Vec<String> {
    p.iter().map(|x| format!("{:.0}", x / 1e3)).collect()
}

fn pct(x: f64) -> String {
    format!("{:+.2} %", 100.0 * x).replace('-', "−")
}

fn signed(x: f64, digits: usize) -> String {
    format!("{x:+.digits$}").replace('-', "−")
}

fn verdict(ok: bool) -> &'static str {
    if ok {
        "holds"
    } else {
        "**not reproduced**"
    }
}

fn render() -> String {
    let r = runs();
    let (t1, p1) = (r[0].time(), r[0].paper);
    let mut o = String::new();
    o.push_str("<!-- claims:begin: rendered by tests/paper_claims.rs from the runs; do not edit by hand -->\n\n");
    o.push_str(
        "| case | change | stop (s) | Table 3 (s) | diff | Δ to case 1 (s) | paper's Δ (s) | Δ error (s) | \
         chain peak (kN, joint) | peak, all joints (kN, joint) | anchor slides at (s) | energy drift |\n",
    );
    o.push_str("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
    for m in &r[..19] {
        let t = m.time();
        let (cp, ck) = m.chain_peak();
        let (ap, ak) = m.all_peak();
        let (d, dp) = (t - t1, m.paper - p1);
        let e = trend_error(t, t1, m.paper, p1);
        let flag = if m.number > 1 && !trend_holds(e, dp) { " ✗" } else { "" };
        o.push_str(&format!(
            "| {} | {} | {t:.3} | {:.3} | {} | {} | {} | {}{flag} | {:.1} ({ck}) | {:.1} ({ak}) | {:.3} | {:.1e} |\n",
            m.number,
            m.change,
            m.paper,
            pct((t - m.paper) / m.paper),
            signed(d, 3),
            signed(dp, 3),
            signed(e, 3),
            cp / 1e3,
            ap / 1e3,
            m.result.anchor_start().unwrap(),
            m.result.max_energy_drift,
        ));
    }
    o.push_str(&format!(
        "\nΔ error = (stop − case 1's stop) − (Table 3 − Table 3's case 1); ✗ where it exceeds \
         max({TREND_ABS} s, {:.0} % of the paper's Δ).\n\n",
        100.0 * TREND_REL
    ));
    o.push_str("| claim (section) | cases | measured (chain peaks, kN) | spread | criterion | verdict |\n");
    o.push_str("| --- | --- | --- | --- | --- | --- |\n");
    /// A claim, its cases, the test on their chain peaks and the test's wording.
    type Claim = (&'static str, &'static [usize], fn(&[f64]) -> bool, &'static str);
    let groups: [Claim; 9] = [
        ("significant: friction (4.3.7)", &FRICTION, significant, "≥ 10 %"),
        ("significant: anchor mass (4.3.7)", &ANCHOR_MASS, significant, "≥ 10 %"),
        ("significant: water depth (4.3.7)", &DEPTH, significant, "≥ 10 %"),
        ("significant: ship speed (4.3.7)", &SPEED, significant, "≥ 10 %"),
        ("a little: ship mass (4.3.5, 4.3.7)", &SHIP_MASS, little, "2–10 %"),
        ("a little: current (4.3.6, 4.3.7)", &CURRENT, little, "2–10 %"),
        ("none: chain radius (4.3.3, 4.3.7)", &CHAIN_RADIUS, no_influence, "< 2 %"),
        ("none: cable length (4.3.3, 4.3.7)", &CABLE_LENGTH, no_influence, "< 2 %"),
        ("none: horizontal projection (4.3.3, 4.3.7)", &PROJECTION, no_influence, "< 2 %"),
    ];
    for (claim, group, check, criterion) in groups {
        let p = chain_peaks(group);
        let cases: Vec<String> = group.iter().map(|n| n.to_string()).collect();
        o.push_str(&format!(
            "| {claim} | {} | {} | {:.1} % | {criterion} | {} |\n",
            cases.join(", "),
            kn(&p).join(", "),
            100.0 * spread(&p),
            verdict(check(&p))
        ));
    }
    let ratio = case(15).chain_peak().0 / case(1).chain_peak().0;
    o.push_str(&format!(
        "| about 2.2× at 5 m/s (4.3.4, 4.3.7) | 1, 15 | ratio {ratio:.2} | | 1.98–2.42 | {} |\n",
        verdict(speed_ratio_holds(ratio))
    ));
    let decreasing: Vec<String> = r[..19]
        .iter()
        .filter_map(|m| first_decrease(&m.peaks()).map(|k| format!("{} (joint {k})", m.number)))
        .collect();
    o.push_str(&format!(
        "| peaks grow toward higher joints (4.3.7) | all | {} | | no joint's peak 2 % below a lower joint's | {} |\n",
        if decreasing.is_empty() { "every case".to_string() } else { format!("falls in {}", decreasing.join(", ")) },
        verdict(decreasing.is_empty())
    ));
    let worst = r[..19]
        .iter()
        .flat_map(|m| m.peaks().into_iter().zip(m.limits.clone()).map(|(p, l)| p / l.0.or(l.1).unwrap()))
        .fold(0.0f64, f64::max);
    let over = r[..19].iter().any(|m| !over_limits(&m.peaks(), &m.limits).is_empty());
    o.push_str(&format!(
        "| below proof and break load (4.2, 4.3.7) | all | largest peak / its joint's lowest limit {:.2} | | < 1 | {} |\n",
        worst,
        verdict(!over)
    ));
    let start = r[0].result.anchor_start().unwrap();
    o.push_str(&format!(
        "| anchor starts after about 1.5 s (4.3.1) | 1 | {start:.3} s | | 1.0–2.0 s | {} |\n",
        verdict(anchor_start_holds(start))
    ));
    let drifts: Vec<f64> = r.iter().map(|m| m.result.max_energy_drift).collect();
    o.push_str(&format!(
        "| energy balance below 0.5 % (4.2, Eq. 63) | all | largest drift {:.1e} | | < 5e-3 | {} |\n",
        drifts.iter().cloned().fold(0.0, f64::max),
        verdict(energy_holds(&drifts))
    ));
    let (times, peaks) = step_study();
    o.push_str(&format!(
        "| dt = 0.002 s is converged (4.2, Figure 14) | 1 at dt = 0.002, 0.001, 0.004 s | stop {} s; chain peak {} kN | {:.2} % | stop within {STEP_TIME} s, peak < 2 % | {} |\n",
        times.iter().map(|t| format!("{t:.4}")).collect::<Vec<_>>().join(", "),
        peaks.iter().map(|p| format!("{:.1}", p / 1e3)).collect::<Vec<_>>().join(", "),
        100.0 * spread(&peaks),
        verdict(step_size_holds(&times, &peaks))
    ));
    let diffs: Vec<f64> = r[..19].iter().map(|m| ((m.time() - m.paper) / m.paper).abs()).collect();
    let within = |bound: f64| diffs.iter().filter(|&&d| d < bound).count();
    let worst = r[..19].iter().zip(&diffs).max_by(|a, b| a.1.total_cmp(b.1)).unwrap();
    o.push_str(&format!(
        "\nSummary: {} of 19 cases within 1 % of Table 3, {} within 1.5 %, {} within 5 %; the largest \
         difference is case {}'s ({}).\n",
        within(0.01),
        within(0.015),
        within(0.05),
        worst.0.number,
        pct((worst.0.time() - worst.0.paper) / worst.0.paper)
    ));
    o.push_str("\n<!-- claims:end -->");
    o
}

#[test]
fn validation_doc_is_fresh() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("docs/validation.md");
    let text = std::fs::read_to_string(&path).unwrap();
    let (a, b) =
        (text.find("<!-- claims:begin").expect("begin marker"), text.find("<!-- claims:end -->").expect("end marker"));
    let fresh = format!("{}{}{}", &text[..a], render(), &text[b + "<!-- claims:end -->".len()..]);
    if fresh != text {
        std::fs::write(&path, &fresh).unwrap();
        panic!("docs/validation.md's measured figures were stale and have been regenerated: review and commit it");
    }
}

/// The README's figures that the code computes: case 1's stopping time against the paper's
/// (two decimals), the largest relative difference of the 19 cases ("within X %", rounded up
/// to 0.1 %), and the Python example's printed stopping time, to the last digit.
#[test]
fn readme_figures_are_what_the_code_computes() {
    let readme = std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("README.md")).unwrap();
    let c1 = case(1);
    let t1 = c1.result.stopping_time.expect("case 1 stops");
    let quoted = format!("({:.2} s against {:.2} s)", t1, c1.paper);
    assert!(readme.contains(&quoted), "README should quote case 1 as {quoted}");
    let worst =
        runs()[..19].iter().map(|m| (m.result.stopping_time.unwrap() - m.paper).abs() / m.paper).fold(0.0, f64::max);
    let within = format!("within {:.1} % of", (worst * 1000.0).ceil() / 10.0);
    assert!(readme.contains(&within), "README should say the 19 cases are {within} Table 3 (worst {worst:.4})");
    let python = format!("\n# {t1}\n");
    assert!(readme.contains(&python), "README's Python example should print {t1}");
}

// ---- figures quoted in the docs' prose ---------------------------------------------------

/// A doc with its whitespace collapsed, so a quoted phrase matches across line breaks.
fn flat_doc(name: &str) -> String {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(name);
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{name}: {e}"));
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The figures of a doc's prose that the runs give: each `phrase` must appear in the doc.
struct Quotes {
    missing: Vec<String>,
}

impl Quotes {
    fn expect(&mut self, doc: &str, text: &str, phrase: String) {
        if !text.contains(&phrase) {
            self.missing.push(format!("{doc} should say: {phrase}"));
        }
    }
    /// A table row: the line of `doc` that starts with `start` holds each of `cells`.
    fn row(&mut self, doc: &str, raw: &str, start: &str, cells: &[String]) {
        match raw.lines().map(str::trim_start).find(|l| l.starts_with(start)) {
            None => self.missing.push(format!("{doc}: no table row starting {start}")),
            Some(line) => {
                for c in cells {
                    if !line.contains(c.as_str()) {
                        self.missing.push(format!("{doc}: row {start}… should hold {c}"));
                    }
                }
            }
        }
    }
}

/// "6446" → "6 446", as the docs write thousands.
fn thousands(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, c) in s.chars().enumerate() {
        if i > 0 && (s.len() - i) % 3 == 0 {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// Rounded up to `digits` decimals: what "within x" may quote.
fn ceil_to(x: f64, digits: i32) -> String {
    let scale = 10f64.powi(digits);
    format!("{:.*}", digits as usize, (x * scale).ceil() / scale)
}

/// Case numbers as the docs list them: runs of three or more as "a–b", the last after "and".
fn case_list(cases: &[usize]) -> String {
    let mut parts: Vec<String> = Vec::new();
    let mut i = 0;
    while i < cases.len() {
        let mut j = i;
        while j + 1 < cases.len() && cases[j + 1] == cases[j] + 1 {
            j += 1;
        }
        if j >= i + 2 {
            parts.push(format!("{}–{}", cases[i], cases[j]));
        } else {
            parts.extend(cases[i..=j].iter().map(|c| c.to_string()));
        }
        i = j + 1;
    }
    match parts.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => parts.join(""),
    }
}

/// Kendall's τ between the runs' stopping times and Table 3's.
fn kendall_tau(pairs: &[(f64, f64)]) -> f64 {
    let (mut concordant, mut discordant) = (0i64, 0i64);
    for i in 0..pairs.len() {
        for j in i + 1..pairs.len() {
            if (pairs[i].0 - pairs[j].0) * (pairs[i].1 - pairs[j].1) > 0.0 {
                concordant += 1;
            } else {
                discordant += 1;
            }
        }
    }
    (concordant - discordant) as f64 / (concordant + discordant) as f64
}

/// The Case 19 study's scene changes (docs/validation.md): a uniform current (the profile's
/// exponent → 0) and no anchor drag at all, on cases 1, 18 and 19.
fn case_19_variants() -> (Vec<f64>, Vec<f64>) {
    /// A scene change of the study.
    type Change = fn(&mut Scene);
    let uniform: Change = |s| s.environment.current_exponent = 1e-12;
    let no_drag: Change = |s| s.hydrodynamics.anchor_drag_coefficient = 0.0;
    let stop = |&(n, change): &(usize, Change)| {
        let mut s = CASES[n - 1].scene();
        change(&mut s);
        measure(n, &s).time()
    };
    let jobs: [(usize, Change); 5] = [(18, uniform), (19, uniform), (1, no_drag), (18, no_drag), (19, no_drag)];
    // Two workers: the machine has two cores.
    let times: Vec<f64> = std::thread::scope(|s| {
        let handles: Vec<_> = jobs.chunks(3).map(|c| s.spawn(move || c.iter().map(stop).collect::<Vec<_>>())).collect();
        handles.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    (vec![case(1).time(), times[0], times[1]], times[2..].to_vec())
}

/// The figures the docs quote in prose (docs/validation.md below the rendered tables,
/// docs/model-choices.md, docs/codegen.md, docs/integrators.md, docs/python.md), computed
/// from the same runs: a doc that quotes a stale figure fails here, naming the phrase the
/// runs give now (edit the doc to it). The README's are `readme_figures_are_what_the_code_computes`.
#[test]
fn prose_figures_are_what_the_runs_give() {
    use kanestop_runtime::forces::current::Current;
    use kanestop_runtime::forces::Forces;
    let r = runs();
    let mut q = Quotes { missing: Vec::new() };

    // docs/validation.md.
    let v = "docs/validation.md";
    let val = flat_doc(v);
    let c1 = case(1);
    let (t1, p1) = (c1.time(), c1.paper);
    let worst = r[..19].iter().map(|m| ((m.time() - m.paper) / m.paper).abs()).fold(0.0, f64::max);
    q.expect(v, &val, format!("stopping times are within {} % of Table 3", ceil_to(100.0 * worst, 1)));
    let last_chain_joint = c1.chain_joint.iter().rposition(|&c| c).unwrap() + 2;
    q.expect(v, &val, format!("(joints 2–{last_chain_joint} in case 1: anchor–chain to chain–cable)"));
    let pairs: Vec<(f64, f64)> = r[..19].iter().map(|m| (m.time(), m.paper)).collect();
    q.expect(v, &val, format!("(Kendall's τ = {:.3})", kendall_tau(&pairs)));
    q.expect(
        v,
        &val,
        format!(
            "early in most cases, and {:.1} % early at 5 m/s",
            -100.0 * (case(15).time() - case(15).paper) / case(15).paper
        ),
    );
    q.expect(v, &val, format!("case 1's anchor starts to slide at {:.3} s", c1.result.anchor_start().unwrap()));
    let ((cp, ck), (ap, _)) = (c1.chain_peak(), c1.all_peak());
    q.expect(
        v,
        &val,
        format!("the chain's is at the chain–cable joint ({ck}), {:.0} % below it", 100.0 * (ap - cp) / ap),
    );
    let sig: Vec<f64> = [FRICTION, ANCHOR_MASS, DEPTH, SPEED].iter().map(|g| 100.0 * spread(&chain_peaks(g))).collect();
    let (lo, hi) = sig.iter().fold((f64::MAX, f64::MIN), |(a, b), &s| (a.min(s), b.max(s)));
    q.expect(v, &val, format!("all four groups spread by {lo:.0}–{hi:.0} %"));
    let depth = kn(&chain_peaks(&DEPTH));
    let h_l: Vec<String> = DEPTH.iter().map(|&n| format!("{:.0}", CASES[n - 1].vertical)).collect();
    q.expect(v, &val, format!("({} kN for h_L = {} m)", depth.join(" → "), h_l.join(", ")));
    let s = |g: &[usize]| 100.0 * spread(&chain_peaks(g));
    q.expect(
        v,
        &val,
        format!(
            "Ship mass ({:.1} %) and current ({:.1} %) have \"a little effect\", cable length ({:.1} %) and horizontal projection ({:.1} %) none",
            s(&SHIP_MASS),
            s(&CURRENT),
            s(&CABLE_LENGTH),
            s(&PROJECTION)
        ),
    );
    let radius = chain_peaks(&CHAIN_RADIUS);
    let heavier = |n: usize| CASES[n - 1].scene().chain.mass_per_length / CASES[0].scene().chain.mass_per_length;
    q.expect(
        v,
        &val,
        format!(
            "moves the chain peak by {:.1} % ({:.1} % and {:.1} % for the {:.1}× and {:.1}× heavier chains of cases 6, 7)",
            s(&CHAIN_RADIUS),
            100.0 * (radius[1] / radius[0] - 1.0),
            100.0 * (radius[2] / radius[0] - 1.0),
            heavier(6),
            heavier(7)
        ),
    );
    q.expect(v, &val, format!("At 5 m/s the chain peak is {:.2}× case 1's", case(15).chain_peak().0 / cp));
    let utilisation = r[..19]
        .iter()
        .flat_map(|m| m.peaks().into_iter().zip(m.limits.clone()).map(|(p, l)| p / l.0.or(l.1).unwrap()))
        .fold(0.0f64, f64::max);
    q.expect(v, &val, format!("the largest is {utilisation:.2} of its joint's lowest limit"));
    // Trends: the cases within the absolute bound, those within the relative one, the rest.
    let trend = |m: &Measured| (trend_error(m.time(), t1, m.paper, p1), m.paper - p1);
    let (mut close, mut relative, mut missed) = (Vec::new(), Vec::new(), Vec::new());
    for m in &r[1..19] {
        let (e, dp) = trend(m);
        if e.abs() <= TREND_ABS {
            close.push(m.number);
        } else if trend_holds(e, dp) {
            relative.push(format!("{} ({} s of {} s)", m.number, signed(e, 2), signed(dp, 2)));
        } else {
            missed.push(m.number);
        }
    }
    q.expect(v, &val, format!("within {TREND_ABS} s of the paper's for cases {}", case_list(&close)));
    q.expect(
        v,
        &val,
        format!("case {} within {:.0} % of the paper's difference", relative.join(" and "), 100.0 * TREND_REL),
    );
    assert_eq!(missed, [19], "the doc's trend prose is about case 19 alone");
    let c19 = case(19);
    let (e19, dp19) = trend(c19);
    let d19 = c19.time() - t1;
    q.expect(
        v,
        &val,
        format!(
            "**case 19 not reproduced**: the {:.0} m/s current adds {d19:.2} s, the paper's {dp19:.2} s ({} s, {:.0} %)",
            CASES[18].current,
            signed(e19, 2),
            100.0 * e19 / dp19
        ),
    );
    let (times, peaks) = step_study();
    let (tlo, thi) = times.iter().fold((f64::MAX, f64::MIN), |(a, b), &t| (a.min(t), b.max(t)));
    q.expect(
        v,
        &val,
        format!(
            "stops within {} ms and its chain peak moves by {:.2} %",
            ceil_to(1e3 * (thi - tlo), 1),
            100.0 * spread(&peaks)
        ),
    );
    let drift = r.iter().map(|m| m.result.max_energy_drift).fold(0.0, f64::max);
    q.expect(v, &val, format!("drifts by at most {drift:.1e}"));
    // Case 19's section: the anchor's current and drag from the scene, the study's computable rows.
    let scene19 = CASES[18].scene();
    let model19 = Model::new(&scene19).unwrap();
    let current = Current {
        surface_speed: 1.0,
        exponent: scene19.environment.current_exponent,
        depth: model19.water_depth(),
        seabed_z: model19.seabed_z,
    };
    let height = scene19.anchor.height;
    let at_centroid = current.at(model19.seabed_z + height / 2.0);
    q.expect(v, &val, format!("{:.2} m above the seabed: {at_centroid:.2} U_ST", height / 2.0));
    q.expect(v, &val, format!("case 1 has no current and is unchanged at {t1:.3} s"));
    let drag = |u: f64| Forces::new(&model19).anchor.drag(scene19.environment.water_density, 0.0, u).abs() / 1e3;
    let (speed, following) = (CASES[0].ship_speed, at_centroid * CASES[18].current);
    q.expect(
        v,
        &val,
        format!(
            "is {:.0} kN at {speed:.0} m/s in still water, {:.0} kN against {following:.2} m/s of following current",
            drag(speed),
            drag(speed - following)
        ),
    );
    let average =
        (0..1000).map(|i| current.at(model19.seabed_z + height * (i as f64 + 0.5) / 1000.0)).sum::<f64>() / 1000.0;
    q.expect(
        v,
        &val,
        format!("over the anchor's {height:.1} m height ({average:.2} U_ST instead of {at_centroid:.2})"),
    );
    q.expect(v, &val, format!("Of case 19's {d19:.2} s"));
    q.expect(
        v,
        &val,
        format!(
            "not reproduced by {} s ({:.1} % of its stopping time; the stopping time itself is {} off Table 3's",
            signed(e19, 2),
            100.0 * e19 / c19.time(),
            pct((c19.time() - c19.paper) / c19.paper)
        ),
    );
    let raw_val = std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(v)).unwrap();
    q.expect(v, &val, format!("Δ19 − paper's {dp19:.3} s"));
    let study_row = |t: [f64; 3]| {
        let d = t[2] - t[0];
        vec![format!("| {:.3} | {:.3} | {d:.3} | {} |", t[1], t[2], signed(d - dp19, 3))]
    };
    q.row(v, &raw_val, "| none (as committed) |", &study_row([t1, case(18).time(), c19.time()]));
    let (uniform, no_drag) = case_19_variants();
    q.row(v, &raw_val, "| uniform current", &study_row([uniform[0], uniform[1], uniform[2]]));
    let mut cells = study_row([no_drag[0], no_drag[1], no_drag[2]]);
    cells.push(format!("(case 1: {:.3} s)", no_drag[0]));
    q.row(v, &raw_val, "| no anchor drag at all", &cells);
    q.expect(
        v,
        &val,
        format!(
            "(Without any anchor drag the ship stops later, {:.3} s in case 1, and the current then adds only {:.2} s.",
            no_drag[0],
            no_drag[2] - no_drag[0]
        ),
    );
    let ship = kanestop_runtime::forces::ship::ShipHydro::new(
        scene19.ship.mass,
        scene19.ship.length,
        scene19.ship.beam,
        scene19.ship.hull_roughness,
        scene19.environment.water_density,
        scene19.environment.gravity,
        scene19.environment.kinematic_viscosity,
    );
    q.expect(v, &val, format!("ship's current at mid-draught ({:.2} m)", ship.volume / ship.waterplane_area / 2.0));

    // docs/model-choices.md: Eq. 62 with the ½, as committed (the printed form needs a changed build).
    let mc = "docs/model-choices.md";
    let raw_mc = std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(mc)).unwrap();
    for n in [1, 15, 19] {
        let m = case(n);
        q.row(
            mc,
            &raw_mc,
            &format!("| {n} |"),
            &[format!("| {:.3} s ({}) | {:.3} s |", m.time(), pct((m.time() - m.paper) / m.paper), m.paper)],
        );
    }

    // docs/codegen.md: case 1's stopping time to the last digit (rolled and unrolled alike:
    // tests/generated_run.rs), and the whole-runs table's simulated times and solves.
    let cg = "docs/codegen.md";
    let codegen = flat_doc(cg);
    let raw_cg = std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(cg)).unwrap();
    q.expect(cg, &codegen, format!("stopping time {t1} s with both forms"));
    for n in [1, 17] {
        let m = case(n);
        q.row(
            cg,
            &raw_cg,
            &format!("| {n} | {:.3} s |", m.time()),
            &[format!("| {} |", thousands(m.result.rhs_evaluations))],
        );
    }

    // docs/integrators.md: case 1's RK4 evaluations.
    let ig = "docs/integrators.md";
    let integrators = flat_doc(ig);
    q.expect(ig, &integrators, format!("→ {} evaluations", thousands(c1.result.rhs_evaluations)));
    let rest =
        c1.result.anchor_events.iter().rev().find(|e| e.now == kanestop_runtime::kernel::AnchorDof::Stuck).unwrap().t;
    q.expect(ig, &integrators, format!("The anchor comes to rest at {rest:.3} s, {:.1} s before the ship", t1 - rest));

    // docs/python.md: the anchor's first switch in the example's DP5 run of case 1.
    let mut s = CASES[0].scene();
    s.solver.integrator = kanestop_runtime::scene::Method::Dp5;
    (s.solver.dt, s.solver.rtol, s.solver.atol) = (0.02, 1e-4, 1e-6);
    s.solver.output_interval = s.solver.output_interval.max(s.solver.dt);
    let dp5 = measure(1, &s);
    let py = "docs/python.md";
    q.expect(py, &flat_doc(py), format!("[{{\"t\": {:.4}, \"anchor\": \"free\"}}", dp5.result.anchor_start().unwrap()));

    assert!(q.missing.is_empty(), "stale figures (edit the docs to what the runs give):\n{}", q.missing.join("\n"));
}

#[test]
fn quoted_figures_are_formatted_as_the_docs_write_them() {
    assert_eq!(case_list(&[2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 16, 18]), "2–14, 16 and 18");
    assert_eq!(case_list(&[2, 3, 5]), "2, 3 and 5");
    assert_eq!(case_list(&[4]), "4");
    assert_eq!(thousands(40243), "40 243");
    assert_eq!(ceil_to(2.137, 1), "2.2");
    assert!((kendall_tau(&[(1.0, 2.0), (2.0, 3.0), (3.0, 1.0)]) + 1.0 / 3.0).abs() < 1e-12);
    let mut q = Quotes { missing: Vec::new() };
    q.expect("d", "stops at 19.808 s", "stops at 19.809 s".into());
    q.row("d", "| 1 | 19.808 s | 40 243 |", "| 1 |", &["| 40 244 |".into()]);
    q.row("d", "| 1 | 19.808 s |", "| 2 |", &[]);
    assert_eq!(q.missing.len(), 3, "{:?}", q.missing);
}
