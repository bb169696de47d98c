//! Tracing: the graph of the current thread, and [`Ex`], the [`Scalar`] whose
//! arithmetic records nodes in it.

use super::{Graph, Id};
use crate::number::scalar::Scalar;
use std::cell::RefCell;
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Sub};

thread_local! {
    static CURRENT: RefCell<Option<Graph>> = const { RefCell::new(None) };
}

fn with_graph<R>(f: impl FnOnce(&mut Graph) -> R) -> R {
    CURRENT.with(|g| {
        let mut g = g.borrow_mut();
        let g = g
            .as_mut()
            .expect("expression arithmetic outside a kernel_gen::graph::Trace");
        f(g)
    })
}

/// A handle to a node of the graph being traced on this thread.
#[derive(Clone, Copy, PartialEq, Eq, Hash)]
pub struct Ex(pub Id);

impl fmt::Debug for Ex {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "t{}", self.0)
    }
}

/// Records arithmetic on [`Ex`] into a fresh graph for as long as it lives on this
/// thread; [`Trace::finish`] hands the graph back.
pub struct Trace {
    _private: (),
}

impl Trace {
    /// Start tracing on this thread. Panics if a trace is already running here.
    pub fn begin() -> Trace {
        CURRENT.with(|g| {
            let mut g = g.borrow_mut();
            assert!(g.is_none(), "a Trace is already running on this thread");
            *g = Some(Graph::default());
        });
        Trace { _private: () }
    }

    /// A new named input of the traced function.
    pub fn input(&self, name: &str) -> Ex {
        Ex(with_graph(|g| g.input(name)))
    }

    /// Stop tracing and return the graph.
    pub fn finish(self) -> Graph {
        let g = CURRENT
            .with(|g| g.borrow_mut().take())
            .expect("trace running");
        std::mem::forget(self);
        g
    }
}

impl Drop for Trace {
    fn drop(&mut self) {
        CURRENT.with(|g| g.borrow_mut().take());
    }
}

impl Ex {
    /// The constant value of this node, if it is one.
    pub fn as_const(self) -> Option<f64> {
        with_graph(|g| g.as_const(self.0))
    }
}

impl Ex {
    /// `if l > r { a } else { b }` ([`Op::Select`](crate::graph::Op::Select)).
    pub fn select_gt(l: Ex, r: Ex, a: Ex, b: Ex) -> Ex {
        Ex(with_graph(|g| g.select_gt(l.0, r.0, a.0, b.0)))
    }
}

impl Add for Ex {
    type Output = Ex;
    fn add(self, b: Ex) -> Ex {
        Ex(with_graph(|g| g.add(self.0, b.0)))
    }
}
impl Sub for Ex {
    type Output = Ex;
    fn sub(self, b: Ex) -> Ex {
        Ex(with_graph(|g| g.sub(self.0, b.0)))
    }
}
impl Mul for Ex {
    type Output = Ex;
    fn mul(self, b: Ex) -> Ex {
        Ex(with_graph(|g| g.mul(self.0, b.0)))
    }
}
impl Div for Ex {
    type Output = Ex;
    fn div(self, b: Ex) -> Ex {
        Ex(with_graph(|g| g.div(self.0, b.0)))
    }
}
impl Neg for Ex {
    type Output = Ex;
    fn neg(self) -> Ex {
        Ex(with_graph(|g| g.neg(self.0)))
    }
}

impl Scalar for Ex {
    fn cst(c: f64) -> Self {
        Ex(with_graph(|g| g.constant(c)))
    }
    fn sqrt(&self) -> Self {
        Ex(with_graph(|g| g.sqrt(self.0)))
    }
    fn powi(&self, n: i32) -> Self {
        Ex(with_graph(|g| g.powi(self.0, n)))
    }
    /// Lowered into arithmetic for a non-positive argument ([`super::elementary`]).
    fn exp(&self) -> Self {
        super::elementary::exp(*self)
    }
    /// Lowered into arithmetic ([`super::elementary`]).
    fn erfc(&self) -> Self {
        super::elementary::erfc(*self)
    }
    fn to_f64(&self) -> f64 {
        self.as_const().unwrap_or(f64::NAN)
    }
    fn is_known_zero(&self) -> bool {
        self.as_const() == Some(0.0)
    }
}
