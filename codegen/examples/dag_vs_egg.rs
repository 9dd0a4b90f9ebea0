//! Hand-rolled DAG or `egg`, measured (issue #4; the table is in docs/codegen.md).
//!
//! For each (function, N, water) it takes the DAG the generator builds (`planar::assemble`,
//! `planar::solve`) and
//!
//! - times the hand-rolled build and counts its operations (`Dag::count`, the counts of
//!   `kanestop codegen` without the dense loop nest of `assemble`);
//! - translates the live DAG into one egg `RecExpr` (one e-node per DAG node, so sharing is
//!   kept; a `list` node holds the outputs), adds it to an `EGraph` and rebuilds: the egg
//!   equivalent of our hash-consing (a);
//! - runs equality saturation with arithmetic rules (commutativity, associativity, the
//!   identities with 0 and 1, negation rules, factoring a·b ± a·c → a·(b ± c)) and constant
//!   folding, under node, time and iteration limits, and extracts with an op-count cost (b).
//!
//! The op counts of egg's results are counted on the extracted `RecExpr`, which egg builds
//! hash-consed (each distinct node once), so they compare with `Dag::count` directly. Each
//! result is also evaluated at one input point against `Dag::eval` (max relative deviation).
//!
//! ```text
//! cargo run --release -p kanestop-codegen --example dag_vs_egg -- \
//!     [--n 46,200] [--funcs assemble,solve_free] [--water dry,wet] [--reps 3] \
//!     [--node-limit 1000000] [--time-limit 30] [--iter-limit 30] [--greedy-max-classes 40000]
//! ```

use std::collections::HashMap;
use std::fmt;
use std::str::FromStr;
use std::time::{Duration, Instant};

use egg::{rewrite as rw, Analysis, CostFunction, DidMerge, EGraph, Extractor, Id, Language, RecExpr, Rewrite, Runner};
use kanestop_chain::{Variant, Water};
use kanestop_codegen::expr::{self, Node, OpCount};
use kanestop_codegen::generate;
use kanestop_codegen::planar::{self, Function};

/// A constant by its bit pattern (egg needs `Ord + Hash`); parses and prints as f64.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
struct Num(u64);

impl Num {
    fn new(v: f64) -> Num {
        Num(if v == 0.0 { 0.0f64 } else { v }.to_bits())
    }
    fn get(self) -> f64 {
        f64::from_bits(self.0)
    }
}

impl FromStr for Num {
    type Err = std::num::ParseFloatError;
    fn from_str(s: &str) -> Result<Num, Self::Err> {
        s.parse::<f64>().map(Num::new)
    }
}

impl fmt::Display for Num {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}", self.get())
    }
}

egg::define_language! {
    enum Math {
        "+" = Add([Id; 2]),
        "-" = Sub([Id; 2]),
        "*" = Mul([Id; 2]),
        "/" = Div([Id; 2]),
        "neg" = Neg(Id),
        "sin" = Sin(Id),
        "cos" = Cos(Id),
        "list" = List(Box<[Id]>),
        Num(Num),
        Input(egg::Symbol),
    }
}

/// Constant folding, as our constructors do it.
#[derive(Default)]
struct Fold;

impl Analysis<Math> for Fold {
    type Data = Option<Num>;

    fn make(egraph: &mut EGraph<Math, Fold>, enode: &Math, _id: Id) -> Option<Num> {
        let c = |i: &Id| egraph[*i].data.map(Num::get);
        let v = match enode {
            Math::Num(n) => return Some(*n),
            Math::Add([a, b]) => c(a)? + c(b)?,
            Math::Sub([a, b]) => c(a)? - c(b)?,
            Math::Mul([a, b]) => c(a)? * c(b)?,
            Math::Div([a, b]) => c(a)? / c(b)?,
            Math::Neg(a) => -c(a)?,
            Math::Sin(a) => c(a)?.sin(),
            Math::Cos(a) => c(a)?.cos(),
            Math::List(_) | Math::Input(_) => return None,
        };
        v.is_finite().then(|| Num::new(v))
    }

    fn merge(&mut self, to: &mut Option<Num>, from: Option<Num>) -> DidMerge {
        // Two folds of one class may differ in the last bit (reassociation): keep the first.
        egg::merge_option(to, from, |_, _| DidMerge(false, false))
    }

    fn modify(egraph: &mut EGraph<Math, Fold>, id: Id) {
        if let Some(n) = egraph[id].data {
            let c = egraph.add(Math::Num(n));
            egraph.union(id, c);
        }
    }
}

/// The rule set; without `assoc` (associativity and the sub ↔ add-neg canonicalisation,
/// the rules that make the e-graph grow without bound) the rest reaches a fixed point.
fn rules(assoc: bool) -> Vec<Rewrite<Math, Fold>> {
    let mut r = vec![
        rw!("comm-add"; "(+ ?a ?b)" => "(+ ?b ?a)"),
        rw!("comm-mul"; "(* ?a ?b)" => "(* ?b ?a)"),
        rw!("add-0"; "(+ ?a 0)" => "?a"),
        rw!("sub-0"; "(- ?a 0)" => "?a"),
        rw!("0-sub"; "(- 0 ?a)" => "(neg ?a)"),
        rw!("sub-self"; "(- ?a ?a)" => "0"),
        rw!("mul-0"; "(* ?a 0)" => "0"),
        rw!("mul-1"; "(* ?a 1)" => "?a"),
        rw!("mul-m1"; "(* ?a -1)" => "(neg ?a)"),
        rw!("div-1"; "(/ ?a 1)" => "?a"),
        rw!("neg-neg"; "(neg (neg ?a))" => "?a"),
        rw!("neg-sub"; "(neg (- ?a ?b))" => "(- ?b ?a)"),
        rw!("neg-mul-out"; "(* (neg ?a) ?b)" => "(neg (* ?a ?b))"),
        rw!("neg-mul-in"; "(neg (* ?a ?b))" => "(* (neg ?a) ?b)"),
        rw!("factor-add"; "(+ (* ?a ?b) (* ?a ?c))" => "(* ?a (+ ?b ?c))"),
        rw!("factor-sub"; "(- (* ?a ?b) (* ?a ?c))" => "(* ?a (- ?b ?c))"),
        rw!("pythagoras"; "(+ (* (cos ?x) (cos ?x)) (* (sin ?x) (sin ?x)))" => "1"),
    ];
    if assoc {
        r.extend([
            rw!("assoc-add"; "(+ ?a (+ ?b ?c))" => "(+ (+ ?a ?b) ?c)"),
            rw!("assoc-mul"; "(* ?a (* ?b ?c))" => "(* (* ?a ?b) ?c)"),
            rw!("sub-canon"; "(- ?a ?b)" => "(+ ?a (neg ?b))"),
            rw!("canon-sub"; "(+ ?a (neg ?b))" => "(- ?a ?b)"),
        ]);
    }
    r
}

/// One per floating-point operation (the tree cost egg's extractor minimises; f64 because
/// the tree size of a shared recursion grows exponentially with N).
struct Ops;

impl CostFunction<Math> for Ops {
    type Cost = f64;
    fn cost<C: FnMut(Id) -> f64>(&mut self, enode: &Math, mut costs: C) -> f64 {
        let own = match enode {
            Math::Num(_) | Math::Input(_) | Math::List(_) => 0.0,
            _ => 1.0,
        };
        enode.fold(own, |sum, id| sum + costs(id))
    }
}

/// A sharing-aware greedy extraction (the "greedy DAG" heuristic of the extraction
/// literature; egg's own `Extractor` minimises tree costs, which counts a shared
/// subexpression once per use and so trades sharing away). The cost of an e-node is the
/// number of distinct operation classes in the union of its children's selections plus
/// itself; sets are bitsets over the classes, so memory is classes²/8 bytes: `None` when
/// that exceeds `max_bytes` or when the selection has a cycle.
fn greedy_dag(eg: &EGraph<Math, Fold>, root: Id, max_bytes: usize) -> Option<RecExpr<Math>> {
    let ids: Vec<Id> = eg.classes().map(|c| c.id).collect();
    let index: HashMap<Id, usize> = ids.iter().enumerate().map(|(i, &id)| (id, i)).collect();
    let n = ids.len();
    let words = n.div_ceil(64);
    if n.saturating_mul(words).saturating_mul(8) > max_bytes {
        return None;
    }
    let mut sets = vec![0u64; n * words];
    let mut cost = vec![usize::MAX; n];
    let mut choice = vec![usize::MAX; n];
    let mut tmp = vec![0u64; words];
    let mut changed = true;
    while changed {
        changed = false;
        for (c, &id) in ids.iter().enumerate() {
            'nodes: for (j, node) in eg[id].nodes.iter().enumerate() {
                tmp.iter_mut().for_each(|w| *w = 0);
                for ch in node.children() {
                    let k = index[&eg.find(*ch)];
                    if cost[k] == usize::MAX {
                        continue 'nodes;
                    }
                    for (t, s) in tmp.iter_mut().zip(&sets[k * words..(k + 1) * words]) {
                        *t |= s;
                    }
                }
                if tmp[c / 64] >> (c % 64) & 1 == 1 {
                    continue; // would depend on itself
                }
                if !matches!(node, Math::Num(_) | Math::Input(_) | Math::List(_)) {
                    tmp[c / 64] |= 1 << (c % 64);
                }
                let k: usize = tmp.iter().map(|w| w.count_ones() as usize).sum();
                if k < cost[c] {
                    cost[c] = k;
                    choice[c] = j;
                    sets[c * words..(c + 1) * words].copy_from_slice(&tmp);
                    changed = true;
                }
            }
        }
    }
    // The selection must be acyclic (a later improvement of a child can close a cycle).
    let mut state = vec![0u8; n]; // 0 new, 1 on the stack, 2 done
    let mut stack = vec![(index[&eg.find(root)], false)];
    while let Some((c, leaving)) = stack.pop() {
        if leaving {
            state[c] = 2;
            continue;
        }
        match state[c] {
            1 => return None,
            2 => continue,
            _ => {}
        }
        state[c] = 1;
        stack.push((c, true));
        for ch in eg[ids[c]].nodes[choice[c]].children() {
            let k = index[&eg.find(*ch)];
            match state[k] {
                1 => return None,
                0 => stack.push((k, false)),
                _ => {}
            }
        }
    }
    let pick = |id: Id| eg[id].nodes[choice[index[&eg.find(id)]]].clone();
    Some(pick(root).build_recexpr(pick))
}

/// The live part of a function's DAG as one RecExpr with a `list` root over its outputs.
fn to_recexpr(f: &Function) -> RecExpr<Math> {
    let dag = &f.dag;
    let roots = f.roots();
    let live = dag.reachable(&roots);
    let mut map: Vec<Option<Id>> = vec![None; dag.len()];
    let mut out = RecExpr::default();
    for i in (0..dag.len()).filter(|&i| live[i]) {
        let m = |x: &expr::Id| map[x.index()].expect("operands precede their users");
        let node = match dag.node(expr::Id::from_index(i)) {
            Node::Const(bits) => Math::Num(Num(*bits)),
            Node::Input(p) => Math::Input(egg::Symbol::from(p.as_str())),
            Node::Add(a, b) => Math::Add([m(a), m(b)]),
            Node::Sub(a, b) => Math::Sub([m(a), m(b)]),
            Node::Mul(a, b) => Math::Mul([m(a), m(b)]),
            Node::Div(a, b) => Math::Div([m(a), m(b)]),
            Node::Neg(a) => Math::Neg(m(a)),
            Node::Sin(a) => Math::Sin(m(a)),
            Node::Cos(a) => Math::Cos(m(a)),
        };
        map[i] = Some(out.add(node));
    }
    let list: Vec<Id> = roots.iter().map(|r| map[r.index()].unwrap()).collect();
    out.add(Math::List(list.into_boxed_slice()));
    out
}

/// Operation counts of a RecExpr (each of its nodes is distinct).
fn count(e: &RecExpr<Math>) -> OpCount {
    let mut c = OpCount::default();
    for node in e.as_ref() {
        match node {
            Math::Add(_) | Math::Sub(_) => c.add += 1,
            Math::Mul(_) => c.mul += 1,
            Math::Div(_) => c.div += 1,
            Math::Neg(_) => c.neg += 1,
            Math::Sin(_) | Math::Cos(_) => c.trig += 1,
            Math::Num(_) | Math::Input(_) | Math::List(_) => {}
        }
    }
    c
}

/// A deterministic input value in [0.5, 1.5) for a place expression.
fn input_value(name: &str) -> f64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for b in name.bytes() {
        h = (h ^ b as u64).wrapping_mul(0x100000001b3);
    }
    0.5 + (h >> 11) as f64 / (1u64 << 53) as f64
}

fn eval(e: &RecExpr<Math>) -> Vec<f64> {
    let nodes = e.as_ref();
    let mut v = vec![0.0; nodes.len()];
    for (i, node) in nodes.iter().enumerate() {
        let x = |id: &Id| v[usize::from(*id)];
        v[i] = match node {
            Math::Num(n) => n.get(),
            Math::Input(s) => input_value(s.as_str()),
            Math::Add([a, b]) => x(a) + x(b),
            Math::Sub([a, b]) => x(a) - x(b),
            Math::Mul([a, b]) => x(a) * x(b),
            Math::Div([a, b]) => x(a) / x(b),
            Math::Neg(a) => -x(a),
            Math::Sin(a) => x(a).sin(),
            Math::Cos(a) => x(a).cos(),
            Math::List(_) => 0.0,
        };
    }
    match nodes.last() {
        Some(Math::List(ids)) => ids.iter().map(|id| v[usize::from(*id)]).collect(),
        _ => unreachable!("the root is a list"),
    }
}

/// max |x − y| / max |y| over the outputs.
fn deviation(x: &[f64], y: &[f64]) -> f64 {
    let scale = y.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(f64::MIN_POSITIVE);
    x.iter().zip(y).fold(0.0f64, |m, (a, b)| m.max((a - b).abs())) / scale
}

fn rss_mb(field: &str) -> f64 {
    let status = std::fs::read_to_string("/proc/self/status").unwrap_or_default();
    status
        .lines()
        .find(|l| l.starts_with(field))
        .and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        .map_or(f64::NAN, |kb| kb / 1024.0)
}

fn median(mut xs: Vec<f64>) -> f64 {
    xs.sort_by(f64::total_cmp);
    xs[xs.len() / 2]
}

fn fmt_ops(c: OpCount) -> String {
    format!("{} ({}+ {}* {}/ {}neg {}trig)", c.total(), c.add, c.mul, c.div, c.neg, c.trig)
}

fn build(func: &str, v: Variant) -> Function {
    match func {
        "assemble" => planar::assemble(v),
        "solve_free" => planar::solve(v, false),
        "solve_stuck" => planar::solve(v, true),
        "kinematics" => planar::kinematics(v),
        "accelerations" => planar::accelerations(v),
        other => panic!("unknown function {other}"),
    }
}

struct Limits {
    nodes: usize,
    time: Duration,
    iters: usize,
    /// Largest e-graph (classes) the greedy DAG extraction is run on.
    greedy_classes: usize,
}

fn case(func: &str, v: Variant, reps: usize, lim: &Limits) {
    let label = format!("{func} N={} {}", v.bodies, v.water.suffix());
    // Hand-rolled: the expansion into the DAG (hash-consing and folding included).
    let mut t_dag = Vec::new();
    let mut f = build(func, v);
    for _ in 0..reps {
        let t = Instant::now();
        f = build(func, v);
        t_dag.push(t.elapsed().as_secs_f64());
    }
    let roots = f.roots();
    let ours = f.dag.count(&roots);
    let reference = f.dag.eval(&roots, &mut |p| input_value(p));
    println!(
        "{label}: hand-rolled DAG {} live nodes, ops {}, build {:.4} s",
        f.dag.reachable(&roots).iter().filter(|&&l| l).count(),
        fmt_ops(ours),
        median(t_dag)
    );

    // (a) The same DAG hash-consed in an e-graph, no rewriting.
    let mut t_add = Vec::new();
    let mut t_ext = Vec::new();
    let mut result = None;
    for _ in 0..reps {
        let t = Instant::now();
        let expr = to_recexpr(&f);
        let mut eg: EGraph<Math, Fold> = EGraph::default();
        let root = eg.add_expr(&expr);
        eg.rebuild();
        t_add.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let (_, best) = Extractor::new(&eg, Ops).find_best(root);
        t_ext.push(t.elapsed().as_secs_f64());
        result = Some((
            eg.number_of_classes(),
            eg.total_number_of_nodes(),
            count(&best),
            deviation(&eval(&best), &reference),
        ));
    }
    let (classes, nodes, c, dev) = result.unwrap();
    println!(
        "  (a) egg hash-cons: {classes} classes, {nodes} e-nodes, ops {}, translate+add+rebuild {:.4} s, extract {:.4} s, deviation {dev:.1e}",
        fmt_ops(c),
        median(t_add),
        median(t_ext)
    );

    // (b) Equality saturation with all rules under the limits; (c) without associativity.
    saturate(&f, &reference, reps, lim, "b", "all rules", &rules(true));
    saturate(&f, &reference, reps, lim, "c", "no associativity", &rules(false));
}

/// Equality saturation under the limits, then both extractions.
fn saturate(
    f: &Function,
    reference: &[f64],
    reps: usize,
    lim: &Limits,
    tag: &str,
    what: &str,
    rules: &[Rewrite<Math, Fold>],
) {
    let mut t_sat = Vec::new();
    let mut t_ext = Vec::new();
    let mut t_greedy = Vec::new();
    let mut result = None;
    for _ in 0..reps {
        let expr = to_recexpr(f);
        let rss0 = rss_mb("VmRSS:");
        let t = Instant::now();
        let runner: Runner<Math, Fold> = Runner::default()
            .with_node_limit(lim.nodes)
            .with_time_limit(lim.time)
            .with_iter_limit(lim.iters)
            .with_expr(&expr)
            .run(rules);
        t_sat.push(t.elapsed().as_secs_f64());
        let rss = rss_mb("VmRSS:") - rss0;
        let t = Instant::now();
        let (_, best) = Extractor::new(&runner.egraph, Ops).find_best(runner.roots[0]);
        t_ext.push(t.elapsed().as_secs_f64());
        let t = Instant::now();
        let greedy = if runner.egraph.number_of_classes() <= lim.greedy_classes {
            greedy_dag(&runner.egraph, runner.roots[0], 1 << 30)
        } else {
            None
        };
        t_greedy.push(t.elapsed().as_secs_f64());
        result = Some((
            runner.iterations.len(),
            format!("{:?}", runner.stop_reason.as_ref().unwrap()),
            runner.egraph.number_of_classes(),
            runner.egraph.total_number_of_nodes(),
            rss,
            (count(&best), deviation(&eval(&best), reference)),
            greedy.map(|g| (count(&g), deviation(&eval(&g), reference))),
        ));
    }
    let (iters, stop, classes, nodes, rss, (c, dev), greedy) = result.unwrap();
    println!(
        "  ({tag}) egg saturation, {what}: {iters} iterations, stop {stop}, {classes} classes, {nodes} e-nodes, +{rss:.0} MB RSS, saturate {:.3} s",
        median(t_sat),
    );
    println!("      tree-cost Extractor: ops {}, extract {:.3} s, deviation {dev:.1e}", fmt_ops(c), median(t_ext));
    match greedy {
        Some((c, dev)) => println!(
            "      greedy DAG extraction: ops {}, extract {:.3} s, deviation {dev:.1e}",
            fmt_ops(c),
            median(t_greedy)
        ),
        None => println!(
            "      greedy DAG extraction: skipped (over {} classes) or cyclic, {:.3} s",
            lim.greedy_classes,
            median(t_greedy)
        ),
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let mut opt: HashMap<String, String> = HashMap::new();
    for pair in args.chunks(2) {
        let key = pair[0].trim_start_matches("--").to_string();
        opt.insert(key, pair.get(1).cloned().expect("--option value"));
    }
    let get = |k: &str, d: &str| opt.get(k).cloned().unwrap_or_else(|| d.to_string());
    let ns: Vec<usize> = get("n", "46,200").split(',').map(|s| s.parse().expect("N")).collect();
    let funcs = get("funcs", "assemble,solve_free");
    let waters: Vec<Water> =
        get("water", "dry,wet").split(',').map(|w| if w == "wet" { Water::On } else { Water::Off }).collect();
    let reps: usize = get("reps", "3").parse().expect("reps");
    let lim = Limits {
        nodes: get("node-limit", "1000000").parse().expect("node limit"),
        time: Duration::from_secs_f64(get("time-limit", "30").parse().expect("time limit")),
        iters: get("iter-limit", "30").parse().expect("iteration limit"),
        greedy_classes: get("greedy-max-classes", "40000").parse().expect("class count"),
    };
    println!(
        "medians of {reps} runs; saturation limits: {} e-nodes, {:?}, {} iterations",
        lim.nodes, lim.time, lim.iters
    );
    for &n in &ns {
        for &w in &waters {
            let v = Variant::new(n, w);
            let mut t_gen = Vec::new();
            for _ in 0..reps {
                let t = Instant::now();
                let g = generate(v);
                t_gen.push(t.elapsed().as_secs_f64());
                std::hint::black_box(g);
            }
            println!(
                "== N = {n}, water {}: whole file generated (all five functions, emission, prettyplease) in {:.3} s",
                w.suffix(),
                median(t_gen)
            );
            for func in funcs.split(',') {
                case(func, v, reps, &lim);
            }
        }
    }
    println!("peak RSS of the process: {:.0} MB", rss_mb("VmHWM:"));
}
