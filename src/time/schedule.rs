//! The operating point each step runs at, in the run's scaled units (docs/model.md §1–2): the
//! liner's speed, the ring's load and the oil supplied, read by the step from a schedule (the
//! case's own, constant, for a run to its periodic regime).

use crate::model::case::CaseSpec;

/// What a step takes from the engine at its time: liner speed u (units of U), the ring's
/// load W_ps and the inlet film d_oil (µm).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OperatingPoint {
    pub u: f64,
    pub w_ps: f64,
    pub d_oil: f64,
}

impl OperatingPoint {
    /// The case's own operating point.
    pub fn of(case: &CaseSpec) -> Self {
        OperatingPoint {
            u: case.u,
            w_ps: case.w_ps,
            d_oil: case.d_oil,
        }
    }
}

/// Where a run's operating point comes from, asked at every step's time.
#[derive(Clone, Debug, PartialEq)]
pub enum Schedule {
    /// The same point at every step.
    Constant(OperatingPoint),
}

impl Schedule {
    /// The operating point at time `t`.
    pub fn at(&self, _t: f64) -> OperatingPoint {
        match self {
            Schedule::Constant(p) => *p,
        }
    }
}
