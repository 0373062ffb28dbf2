//! Film solvers of the lab: kept to measure (the multigrid classes) or to show failure (plain
//! Gauss–Seidel, the Reynolds cut-off, explicit coupling). Each is a
//! [`texopt::solve::FilmMethod`], run by the product's own transient.

mod cutoff;
mod explicit;
mod gauss_seidel;
mod newton_mg;

pub use cutoff::Cutoff;
pub use explicit::Explicit;
pub use gauss_seidel::{GaussSeidel, GS_RESIDUAL};
pub use newton_mg::{MgTolerance, NewtonMultigrid};

use texopt::model::case::CaseSpec;
use texopt::solve::{FilmError, FilmMethod, Method, Step};
use texopt::time::{Numerics, Transient};

/// Every film solver the lab can run: the product's two and its own.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Solver {
    Direct,
    Reference,
    Multigrid,
    PtMultigrid,
    GaussSeidel,
}

impl Solver {
    pub const ALL: [Solver; 5] = [
        Solver::Direct,
        Solver::Reference,
        Solver::Multigrid,
        Solver::PtMultigrid,
        Solver::GaussSeidel,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Solver::Direct => "direct",
            Solver::Reference => "reference",
            Solver::Multigrid => "multigrid",
            Solver::PtMultigrid => "pt-multigrid",
            Solver::GaussSeidel => "gauss-seidel",
        }
    }

    pub fn parse(s: &str) -> Result<Solver, String> {
        Solver::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                let names: Vec<_> = Solver::ALL.iter().map(|m| m.name()).collect();
                format!("no solver {s:?}; choose from {}", names.join(", "))
            })
    }

    /// A solver of this kind.
    pub fn build(self) -> Box<dyn FilmMethod> {
        match self {
            Solver::Direct => Method::Direct.solver(),
            Solver::Reference => Method::Reference.solver(),
            Solver::Multigrid => Box::new(NewtonMultigrid::new(MgTolerance::default())),
            Solver::PtMultigrid => Box::new(crate::pt_multigrid::PtSolver::default()),
            Solver::GaussSeidel => Box::new(GaussSeidel::new()),
        }
    }

    /// A transient of `case` on `num` run by this solver.
    pub fn transient(self, case: &CaseSpec, num: &Numerics) -> Transient {
        Transient::with_solver(case, num, self.build())
    }
}

/// A transient of `case` on `num` under the Reynolds cut-off: a full film (θ ≡ 1) from the
/// start, the cut-off solver in every step.
pub fn cutoff_transient(case: &CaseSpec, num: &Numerics) -> Transient {
    let mut t = Transient::with_solver(case, num, Box::new(Cutoff::default()));
    t.lay_film(|scene, k, z| scene.gap.h(&scene.grid, k, z));
    t
}

/// A transient of `case` on `num` with the ring coupled explicitly (the direct solver at the
/// predicted Z).
pub fn explicit_transient(case: &CaseSpec, num: &Numerics) -> Transient {
    Transient::with_solver(case, num, Box::new(Explicit::new(Method::Direct.solver())))
}

/// Refuses a problem with nonzero cavity pressures (docs/model.md §3) for a solver whose own
/// active-set rule holds cavities at p = 0: only the product's pieces (the direct, reference
/// and multigrid solvers) carry the cavity pressure.
pub fn refuse_cavity_pressure(step: &Step, solver: &str) -> Result<(), FilmError> {
    let bc = step.boundary;
    if bc.cavity_left == 0.0 && bc.cavity_right == 0.0 {
        return Ok(());
    }
    Err(FilmError::Other(format!(
        "the {solver} solver holds cavities at p = 0, but this problem's cavity pressures are \
         {:e} (left) and {:e} (right): use the direct, reference or multigrid solver",
        bc.cavity_left, bc.cavity_right
    )))
}
