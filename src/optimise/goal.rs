//! What a search minimises, and the Pareto front of friction against clearance.

use serde::Serialize;

use crate::time::Outcome;

/// What a search minimises, in outcomes relative to the plain liner: a = f̄/f̄_plain,
/// b = C_min,plain/C_min (both 1 for the plain liner, lower is better).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Goal {
    Friction,
    Clearance,
    /// Chebyshev scalarisation max(w·(a − a*), (1 − w)·(b − b*)) about the ideal point
    /// (a*, b*) of the single-objective searches.
    Balanced {
        w: f64,
        ideal: (f64, f64),
    },
}

/// Cost of a failed evaluation: worse than any plausible design, finite for the swarm.
pub(crate) const FAILED_COST: f64 = 10.0;

impl Goal {
    pub fn cost(&self, o: &Outcome, plain: &Outcome) -> f64 {
        let a = o.f_mean / plain.f_mean;
        let b = plain.c_min / o.c_min;
        match *self {
            Goal::Friction => a,
            Goal::Clearance => b,
            Goal::Balanced { w, ideal } => (w * (a - ideal.0)).max((1.0 - w) * (b - ideal.1)),
        }
    }
}

/// Indices of the non-dominated points (minimise x, maximise y).
pub fn pareto(points: &[(f64, f64)]) -> Vec<usize> {
    (0..points.len())
        .filter(|&i| {
            let (xi, yi) = points[i];
            xi.is_finite()
                && yi.is_finite()
                && !points
                    .iter()
                    .enumerate()
                    .any(|(j, &(xj, yj))| j != i && xj <= xi && yj >= yi && (xj < xi || yj > yi))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pareto_keeps_only_non_dominated_points() {
        let p = [
            (1.0, 1.0),
            (0.9, 0.8),
            (0.95, 1.2),
            (1.1, 1.3),
            (0.9, 0.7),
            (1.2, 1.0),
        ];
        assert_eq!(pareto(&p), vec![1, 2, 3]);
    }
}
