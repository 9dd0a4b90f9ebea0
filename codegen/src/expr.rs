//! The symbolic core: a hash-consed expression DAG over f64.
//!
//! Every node is interned: building the same operation on the same operands twice returns
//! the same [`Id`], so common subexpressions are shared by construction. Commutative
//! operands are put in a canonical order first, so `a·b` and `b·a` are one node too. The
//! constructors fold constants and apply the trivial identities (0·x = 0, 1·x = x,
//! x + 0 = x, x − x = 0, −(−x) = x, cos²x + sin²x = 1), so a quantity that is structurally
//! zero *is* the constant 0 and is never emitted: zero tracking is exact.
//!
//! The folding assumes finite inputs (0·x = 0 is false for x = ∞ or NaN); the kernels are
//! only ever evaluated at finite states.
//!
//! Node ids grow in creation order and a node's operands are always older than the node, so
//! creation order is a topological order: emission walks it once.

// Float comparisons read more plainly as guards than as literal patterns.
#![allow(clippy::redundant_guards)]

use std::collections::HashMap;

/// A node of the DAG.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Id(u32);

impl Id {
    /// Position of the node in creation order.
    pub fn index(self) -> usize {
        self.0 as usize
    }

    /// The node at a position in creation order.
    pub fn from_index(i: usize) -> Id {
        Id(u32::try_from(i).expect("fewer than 2^32 nodes"))
    }
}

/// One operation. Constants are stored by their bit pattern so nodes can be hashed.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    /// A literal.
    Const(u64),
    /// A value read from the kernel's arguments, written as a Rust place expression
    /// (`q[3]`, `p[4].mass`).
    Input(String),
    Add(Id, Id),
    Sub(Id, Id),
    Mul(Id, Id),
    Div(Id, Id),
    Neg(Id),
    Sin(Id),
    Cos(Id),
}

/// Operation counts of the code emitted for a set of outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct OpCount {
    /// Additions and subtractions.
    pub add: usize,
    /// Multiplications.
    pub mul: usize,
    /// Divisions.
    pub div: usize,
    /// Negations.
    pub neg: usize,
    /// Sines and cosines.
    pub trig: usize,
}

impl OpCount {
    /// All floating-point operations.
    pub fn total(&self) -> usize {
        self.add + self.mul + self.div + self.neg + self.trig
    }
}

impl std::ops::AddAssign for OpCount {
    fn add_assign(&mut self, o: OpCount) {
        self.add += o.add;
        self.mul += o.mul;
        self.div += o.div;
        self.neg += o.neg;
        self.trig += o.trig;
    }
}

/// The interned DAG.
#[derive(Default)]
pub struct Dag {
    nodes: Vec<Node>,
    index: HashMap<Node, Id>,
    names: Vec<Option<String>>,
}

impl Dag {
    pub fn new() -> Self {
        Dag::default()
    }

    /// Number of distinct nodes built so far.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    pub fn node(&self, id: Id) -> &Node {
        &self.nodes[id.index()]
    }

    /// The name given to a node with [`Dag::name`], if any.
    pub fn name_of(&self, id: Id) -> Option<&str> {
        self.names[id.index()].as_deref()
    }

    fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.index.get(&node) {
            return id;
        }
        let id = Id(u32::try_from(self.nodes.len()).expect("fewer than 2^32 nodes"));
        self.nodes.push(node.clone());
        self.names.push(None);
        self.index.insert(node, id);
        id
    }

    /// A constant. −0 is stored as +0 so both fold alike.
    pub fn constant(&mut self, v: f64) -> Id {
        assert!(v.is_finite(), "constants must be finite");
        let v = if v == 0.0 { 0.0 } else { v };
        self.intern(Node::Const(v.to_bits()))
    }

    pub fn zero(&mut self) -> Id {
        self.constant(0.0)
    }

    pub fn one(&mut self) -> Id {
        self.constant(1.0)
    }

    /// A value read from the arguments (a Rust place expression).
    pub fn input(&mut self, place: impl Into<String>) -> Id {
        self.intern(Node::Input(place.into()))
    }

    /// The constant value of a node, if it is one.
    pub fn value(&self, id: Id) -> Option<f64> {
        match self.nodes[id.index()] {
            Node::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    pub fn is_zero(&self, id: Id) -> bool {
        self.value(id) == Some(0.0)
    }

    /// Gives a node a readable name for emission (the first name given wins). Constants and
    /// inputs keep their literal form.
    pub fn name(&mut self, id: Id, name: impl Into<String>) -> Id {
        if matches!(self.nodes[id.index()], Node::Const(_) | Node::Input(_)) {
            return id;
        }
        let slot = &mut self.names[id.index()];
        if slot.is_none() {
            *slot = Some(name.into());
        }
        id
    }

    pub fn add(&mut self, a: Id, b: Id) -> Id {
        match (self.value(a), self.value(b)) {
            (Some(x), Some(y)) => return self.constant(x + y),
            (Some(x), _) if x == 0.0 => return b,
            (_, Some(y)) if y == 0.0 => return a,
            _ => {}
        }
        // a + (−b) = a − b, (−a) + b = b − a.
        if let Node::Neg(nb) = self.nodes[b.index()] {
            return self.sub(a, nb);
        }
        if let Node::Neg(na) = self.nodes[a.index()] {
            return self.sub(b, na);
        }
        if let Some(one) = self.pythagoras(a, b) {
            return one;
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Add(a, b))
    }

    /// cos²x + sin²x = 1 (either order).
    fn pythagoras(&mut self, a: Id, b: Id) -> Option<Id> {
        let square_of = |dag: &Dag, id: Id| match dag.nodes[id.index()] {
            Node::Mul(x, y) if x == y => Some(x),
            _ => None,
        };
        let (x, y) = (square_of(self, a)?, square_of(self, b)?);
        let arg = |dag: &Dag, id: Id| match dag.nodes[id.index()] {
            Node::Sin(t) => Some((t, false)),
            Node::Cos(t) => Some((t, true)),
            _ => None,
        };
        match (arg(self, x)?, arg(self, y)?) {
            ((t, c1), (u, c2)) if t == u && c1 != c2 => Some(self.one()),
            _ => None,
        }
    }

    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        if a == b {
            return self.zero();
        }
        match (self.value(a), self.value(b)) {
            (Some(x), Some(y)) => return self.constant(x - y),
            (Some(x), _) if x == 0.0 => return self.neg(b),
            (_, Some(y)) if y == 0.0 => return a,
            _ => {}
        }
        if let Node::Neg(nb) = self.nodes[b.index()] {
            return self.add(a, nb);
        }
        self.intern(Node::Sub(a, b))
    }

    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        match (self.value(a), self.value(b)) {
            (Some(x), Some(y)) => return self.constant(x * y),
            (Some(x), _) | (_, Some(x)) if x == 0.0 => return self.zero(),
            (Some(x), _) if x == 1.0 => return b,
            (_, Some(y)) if y == 1.0 => return a,
            (Some(x), _) if x == -1.0 => return self.neg(b),
            (_, Some(y)) if y == -1.0 => return self.neg(a),
            _ => {}
        }
        // Pull negations out so that (−a)·b and a·(−b) share a·b.
        match (self.nodes[a.index()].clone(), self.nodes[b.index()].clone()) {
            (Node::Neg(x), Node::Neg(y)) => return self.mul(x, y),
            (Node::Neg(x), _) => {
                let p = self.mul(x, b);
                return self.neg(p);
            }
            (_, Node::Neg(y)) => {
                let p = self.mul(a, y);
                return self.neg(p);
            }
            _ => {}
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Mul(a, b))
    }

    pub fn div(&mut self, a: Id, b: Id) -> Id {
        assert!(!self.is_zero(b), "division by a structural zero");
        match (self.value(a), self.value(b)) {
            (Some(x), Some(y)) => return self.constant(x / y),
            (Some(x), _) if x == 0.0 => return self.zero(),
            (_, Some(y)) if y == 1.0 => return a,
            _ => {}
        }
        self.intern(Node::Div(a, b))
    }

    pub fn neg(&mut self, a: Id) -> Id {
        if let Some(x) = self.value(a) {
            return self.constant(-x);
        }
        match self.nodes[a.index()] {
            Node::Neg(x) => x,
            Node::Sub(x, y) => self.sub(y, x),
            _ => self.intern(Node::Neg(a)),
        }
    }

    pub fn sin(&mut self, a: Id) -> Id {
        if let Some(x) = self.value(a) {
            return self.constant(x.sin());
        }
        self.intern(Node::Sin(a))
    }

    pub fn cos(&mut self, a: Id) -> Id {
        if let Some(x) = self.value(a) {
            return self.constant(x.cos());
        }
        self.intern(Node::Cos(a))
    }

    /// Σ terms (left to right).
    pub fn sum(&mut self, terms: &[Id]) -> Id {
        let mut acc = self.zero();
        for &t in terms {
            acc = self.add(acc, t);
        }
        acc
    }

    /// a·b + c·d.
    pub fn dot2(&mut self, a: [Id; 2], b: [Id; 2]) -> Id {
        let x = self.mul(a[0], b[0]);
        let z = self.mul(a[1], b[1]);
        self.add(x, z)
    }

    /// Marks every node the `roots` depend on, in creation order.
    pub fn reachable(&self, roots: &[Id]) -> Vec<bool> {
        let mut live = vec![false; self.nodes.len()];
        for &r in roots {
            live[r.index()] = true;
        }
        for i in (0..self.nodes.len()).rev() {
            if !live[i] {
                continue;
            }
            match self.nodes[i] {
                Node::Const(_) | Node::Input(_) => {}
                Node::Add(a, b) | Node::Sub(a, b) | Node::Mul(a, b) | Node::Div(a, b) => {
                    live[a.index()] = true;
                    live[b.index()] = true;
                }
                Node::Neg(a) | Node::Sin(a) | Node::Cos(a) => live[a.index()] = true,
            }
        }
        live
    }

    /// Operation counts of the code that computes `roots`.
    pub fn count(&self, roots: &[Id]) -> OpCount {
        let live = self.reachable(roots);
        let mut c = OpCount::default();
        for (node, _) in self.nodes.iter().zip(&live).filter(|(_, &l)| l) {
            match node {
                Node::Add(..) | Node::Sub(..) => c.add += 1,
                Node::Mul(..) => c.mul += 1,
                Node::Div(..) => c.div += 1,
                Node::Neg(..) => c.neg += 1,
                Node::Sin(..) | Node::Cos(..) => c.trig += 1,
                Node::Const(_) | Node::Input(_) => {}
            }
        }
        c
    }

    /// Evaluates `root` numerically, reading inputs through `input` (for tests of the
    /// expansion without compiling it).
    pub fn eval(&self, roots: &[Id], input: &mut dyn FnMut(&str) -> f64) -> Vec<f64> {
        let live = self.reachable(roots);
        let mut val = vec![0.0; self.nodes.len()];
        for i in 0..self.nodes.len() {
            if !live[i] {
                continue;
            }
            val[i] = match &self.nodes[i] {
                Node::Const(bits) => f64::from_bits(*bits),
                Node::Input(place) => input(place),
                Node::Add(a, b) => val[a.index()] + val[b.index()],
                Node::Sub(a, b) => val[a.index()] - val[b.index()],
                Node::Mul(a, b) => val[a.index()] * val[b.index()],
                Node::Div(a, b) => val[a.index()] / val[b.index()],
                Node::Neg(a) => -val[a.index()],
                Node::Sin(a) => val[a.index()].sin(),
                Node::Cos(a) => val[a.index()].cos(),
            };
        }
        roots.iter().map(|r| val[r.index()]).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_expressions_are_one_node() {
        let mut d = Dag::new();
        let (x, y) = (d.input("x"), d.input("y"));
        let a = d.mul(x, y);
        let b = d.mul(y, x);
        assert_eq!(a, b);
        let s1 = d.add(a, x);
        let s2 = d.add(x, b);
        assert_eq!(s1, s2);
        assert_eq!(d.len(), 4);
    }

    #[test]
    fn trivial_identities_fold() {
        let mut d = Dag::new();
        let x = d.input("x");
        let (zero, one) = (d.zero(), d.one());
        assert_eq!(d.mul(x, zero), zero);
        assert_eq!(d.mul(one, x), x);
        assert_eq!(d.add(x, zero), x);
        assert_eq!(d.sub(x, x), zero);
        let n = d.neg(x);
        assert_eq!(d.neg(n), x);
        assert_eq!(d.add(x, n), zero);
        let two = d.constant(2.0);
        let three = d.constant(3.0);
        let six = d.mul(two, three);
        assert_eq!(d.value(six), Some(6.0));
        let (s, c) = (d.sin(x), d.cos(x));
        let (ss, cc) = (d.mul(s, s), d.mul(c, c));
        assert_eq!(d.add(cc, ss), one);
    }

    #[test]
    fn counts_only_what_the_roots_need() {
        let mut d = Dag::new();
        let (x, y) = (d.input("x"), d.input("y"));
        let p = d.mul(x, y);
        let s = d.add(p, x);
        let _unused = d.sin(y);
        let c = d.count(&[s]);
        assert_eq!((c.add, c.mul, c.trig), (1, 1, 0));
        let v = d.eval(&[s], &mut |name| if name == "x" { 2.0 } else { 5.0 });
        assert_eq!(v, vec![12.0]);
    }
}
