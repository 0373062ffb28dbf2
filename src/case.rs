//! What defines one evaluation: the physical case (ring, liner texture, operating point) and
//! the numerical fidelity, with the validity rules of model.md §2 checked up front.

use serde::{Deserialize, Serialize};

use crate::film::{Boundary, Cavitation, Method, Tolerance};
use std::sync::Arc;

use crate::geometry::{CircularArc, Contact, HalfEllipsoid, Liner};

/// A lattice of half-ellipsoidal pockets (model.md §2). Lengths in cm, depth in µm.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Texture {
    /// Pocket semiaxis along the sliding direction x1 (cm).
    pub l1: f64,
    /// Pocket semiaxis across the sliding direction (cm).
    pub l2: f64,
    /// Lattice period along x1 (cm).
    pub per: f64,
    /// Lattice period along x2 (cm).
    pub width: f64,
    /// Pocket depth (µm).
    pub depth: f64,
    /// x1 of a pocket centre at t = 0 (cm): the texture's initial phase.
    #[serde(default)]
    pub phase: f64,
}

impl Texture {
    /// Square lattice of circular pockets (the paper's family): l2 = l1, width = per.
    pub fn circular(l1: f64, per: f64, depth: f64) -> Self {
        Texture {
            l1,
            l2: l1,
            per,
            width: per,
            depth,
            phase: 0.0,
        }
    }
    /// Textured area fraction π·l1·l2/(per·width).
    pub fn area_fraction(&self) -> f64 {
        std::f64::consts::PI * self.l1 * self.l2 / (self.per * self.width)
    }
}

/// One physical case. Defaults are the paper's operating point (model.md §1–4, §7).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct CaseSpec {
    /// Ring face radius R (cm); f64::INFINITY for a flat ring (written "inf").
    #[serde(rename = "R", with = "radius")]
    pub r: f64,
    /// None: untextured liner.
    pub texture: Option<Texture>,
    /// Liner speed u (units of U = 10 m/s).
    pub u: f64,
    /// Ring pre-stress load per unit width W_ps (units of 2.4e7 N/m).
    pub w_ps: f64,
    /// Ring mass per unit width m (units of 2.4e7 kg/m).
    pub mass: f64,
    /// Inlet oil film thickness (µm).
    pub d_oil: f64,
    /// Shear threshold θ_s of the Couette switch (eq. 9).
    pub theta_s: f64,
    /// Gap outside the ring e (µm).
    pub e: f64,
    /// Initial ring position Z(0) (µm) and velocity Z'(0).
    pub z0: f64,
    pub v0: f64,
}

impl CaseSpec {
    /// The film's boundary data (model.md §3): p = 0 at both ends, the oil supply d_oil
    /// carried in at x1 = 0 by the liner's speed.
    pub fn film_boundary(&self) -> Boundary {
        Boundary {
            u: self.u,
            p_left: 0.0,
            p_right: 0.0,
            phi_inlet: self.d_oil,
        }
    }

    /// The paper's operating point for a ring of radius R, untextured liner.
    pub fn paper(r: f64) -> Self {
        CaseSpec {
            r,
            texture: None,
            u: 1.0,
            w_ps: 1.66e-6,
            mass: 2.0e-9,
            d_oil: 20.0,
            theta_s: 0.95,
            e: 1000.0,
            z0: 2.5,
            v0: 0.0,
        }
    }
    pub fn with_texture(mut self, t: Texture) -> Self {
        self.texture = Some(t);
        self
    }

    /// The contact geometry (paper's domain and ring width).
    pub fn contact(&self) -> Contact {
        let liner = match &self.texture {
            None => Liner::smooth(),
            Some(t) => Liner {
                pocket: Some(Arc::new(HalfEllipsoid {
                    l1_cm: t.l1,
                    l2_cm: t.l2,
                    depth_um: t.depth,
                })),
                per_cm: t.per,
                width_cm: t.width,
                phase_cm: t.phase,
            },
        };
        let mut c = Contact::paper(Arc::new(CircularArc { radius_cm: self.r }), liner);
        c.e_um = self.e;
        c
    }

    /// Short label for messages, e.g. "R=0.8 l1=0.01 l2=0.01 per=0.06 width=0.06 depth=5".
    pub fn label(&self) -> String {
        let mut s = format!("R={}", self.r);
        if let Some(t) = &self.texture {
            s += &format!(
                " l1={} l2={} per={} width={} depth={}",
                t.l1, t.l2, t.per, t.width, t.depth
            );
            if t.phase != 0.0 {
                s += &format!(" phase={}", t.phase);
            }
        } else {
            s += " untextured";
        }
        s
    }
}

/// Numerical fidelity and run control.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Numerics {
    /// Cells along x1 over the domain [0, 0.2].
    pub n1: usize,
    /// Cells along x2 over the simulated half texture cell.
    pub n2: usize,
    /// Largest time step (L/U units); the step used divides the texture period exactly.
    pub dt: f64,
    /// Periodic regime reached when the estimated distance of the period-mean f and Z from
    /// their periodic limits (geometric tail of the cycle-to-cycle changes) is below this,
    /// relative.
    pub periodic_tol: f64,
    /// Guard: give up (converged = false) after this much simulated time.
    pub t_max: f64,
    /// At least this many texture periods are simulated.
    pub min_periods: usize,
    /// Linear solver of the film iteration.
    #[serde(default)]
    pub solver: Method,
    /// Film solve tolerance (multigrid): largest nodal mass residual relative to the
    /// Couette flux through the thinnest film under the ring.
    #[serde(default = "default_solve_tol")]
    pub solve_tol: f64,
    /// Multigrid: most V-cycles per linear solve.
    #[serde(default = "default_cycles")]
    pub cycles: usize,
    /// Initial state of the transient.
    #[serde(default)]
    pub start: Start,
    /// Jump the state along a dominant, monotone slow mode to its limit when the period means
    /// show one (geometric extrapolation of the period-end states; the periodic regime is
    /// then verified on fresh periods).
    #[serde(default = "yes")]
    pub extrapolate: bool,
    /// Coarse approach: reach the periodic regime first on a mesh of this many x2 cells (same
    /// N1 and time step; raised where a pocket would span fewer than 2 cells), then carry the
    /// state over to this mesh and run on to its own periodic regime. The answer is this
    /// mesh's (the periodic regime does not depend on the start, tests/solvers.rs); the
    /// coarse mesh only takes the ring's transient, where a step costs a few band
    /// factorisations (∝ N2³). None, or not below n2: off. Off in `Numerics::default()` (the
    /// plain method, which the tests compare against); the `paper` and `fine` tiers set it.
    /// Not serialised when off, so cache keys of runs without it do not carry it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub approach_n2: Option<usize>,
    /// How the ring equation is coupled to the film (implicit unless studying failure).
    /// Not serialised when implicit, so cache keys of ordinary runs do not carry it.
    #[serde(default, skip_serializing_if = "Coupling::is_implicit")]
    pub coupling: Coupling,
    /// Cavitation model (Elrod–Adams unless studying failure). Not serialised when
    /// Elrod–Adams, so cache keys of ordinary runs do not carry it.
    #[serde(default, skip_serializing_if = "Cavitation::is_elrod_adams")]
    pub cavitation: Cavitation,
}

/// Coupling of the ring dynamics to the film (model.md §4).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Coupling {
    /// Newmark average acceleration with Z an unknown of the film iteration (default).
    #[default]
    Implicit,
    /// Explicit central-difference update: Z⁺ from the old acceleration, film solved at that
    /// Z, then the new acceleration. Kept to show where it fails (the film's squeeze
    /// damping makes it unstable at the paper's dt; model.md §4).
    Explicit,
}

impl Coupling {
    pub fn is_implicit(&self) -> bool {
        *self == Coupling::Implicit
    }
}

fn yes() -> bool {
    true
}

/// Named fidelity tiers the rest of the product asks for, chosen from the Pareto front of the
/// speed-against-accuracy study (results/speed.md; errors against 2048×128, dt = 1e-4, for
/// Case I and Case III): the cell count along the sliding direction and the time step carry
/// almost all of the error, the cells across (N2) little, so the fast tiers are anisotropic.
/// The time step's error grows with R: for conformal rings see results/speed_finer.md.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Fidelity {
    /// 256×8, dt = 8e-4: screening (errors ≈ 1–2 %, ≈ 1 s a case).
    Draft,
    /// 512×8, dt = 4e-4: studies and optimisation (errors ≈ 1 %: ≤ 1.11 % against 2048×128
    /// on Case I and Case III; ≈ 1–2 s a case).
    Fast,
    /// 512×32, dt = 4e-4: the paper's fidelity (model.md §3), for reproducing it.
    Paper,
    /// 1024×16, dt = 2e-4: checks.
    Fine,
}

impl Fidelity {
    pub const ALL: [Fidelity; 4] = [
        Fidelity::Draft,
        Fidelity::Fast,
        Fidelity::Paper,
        Fidelity::Fine,
    ];

    pub fn name(self) -> &'static str {
        match self {
            Fidelity::Draft => "draft",
            Fidelity::Fast => "fast",
            Fidelity::Paper => "paper",
            Fidelity::Fine => "fine",
        }
    }

    /// The measured relative error of f̄ at this tier: the larger of Case I and Case III
    /// against 2048×128, dt = 1e-4 (results/speed.md, rounded up; `tests/study.rs` checks it
    /// against results/speed.csv). Differences below it are not resolved.
    pub fn f_error(self) -> f64 {
        match self {
            Fidelity::Draft => 0.0183,
            Fidelity::Fast => 0.0112,
            Fidelity::Paper => 0.0074,
            Fidelity::Fine => 0.0047,
        }
    }

    /// The measured relative error of C_min at this tier (as `f_error`).
    pub fn c_error(self) -> f64 {
        match self {
            Fidelity::Draft => 0.0186,
            Fidelity::Fast => 0.0080,
            Fidelity::Paper => 0.0067,
            Fidelity::Fine => 0.0009,
        }
    }

    /// The numerics of this tier (other settings at their defaults). The screening tiers
    /// stop at a periodic tolerance of 1e-4 (the speed study: it moves f̄ by < 1e-5 relative
    /// on Case I, far under their mesh error, and saves ≈ 30 % of the periods).
    pub fn numerics(self) -> Numerics {
        let (n1, n2, dt, periodic_tol) = match self {
            Fidelity::Draft => (256, 8, 8e-4, 1e-4),
            Fidelity::Fast => (512, 8, 4e-4, 1e-4),
            Fidelity::Paper => (512, 32, 4e-4, 1e-5),
            Fidelity::Fine => (1024, 16, 2e-4, 1e-5),
        };
        Numerics {
            n1,
            n2,
            dt,
            periodic_tol,
            // The wide band of the paper tier makes the ring's transient its dearest part
            // (≈ 80 % of Case III from the paper's start); at N2 = 8 the band LU is ≈ 50×
            // cheaper.
            approach_n2: (n2 > APPROACH_N2).then_some(APPROACH_N2),
            ..Numerics::default()
        }
    }

    /// The numerics of this tier for one case: the tier's N2 is raised where the pocket
    /// would span fewer than `POCKET_CELLS` cells across (small pockets in a wide cell, e.g.
    /// l2 = 0.0025 in width 0.06 needs N2 = 24), so every texture is resolved alike.
    pub fn numerics_for(self, case: &CaseSpec) -> Numerics {
        let mut num = self.numerics();
        num.resolve_pockets(case, self.pocket_cells());
        num
    }

    /// Fewest cells across a pocket (along x2) the tier accepts before raising N2: 4, and 2
    /// for the screening tier `draft` (small pockets in wide cells would otherwise cost it
    /// N2 ≈ 24 and a band LU 20× dearer).
    pub fn pocket_cells(self) -> f64 {
        match self {
            Fidelity::Draft => 2.0,
            _ => POCKET_CELLS,
        }
    }
}

impl Numerics {
    /// Raises N2 where the pocket would span fewer than `cells` cells across.
    pub fn resolve_pockets(&mut self, case: &CaseSpec, cells: f64) {
        if let Some(t) = &case.texture {
            let half = 0.5 * t.width;
            let need = (cells * half / (2.0 * t.l2) - 1e-9).ceil();
            if need.is_finite() && need > self.n2 as f64 {
                self.n2 = need as usize;
            }
        }
    }
}

/// x2 cells of the coarse approach of the tiers with more (`paper`, `fine`): the `fast` tier's N2.
pub const APPROACH_N2: usize = 8;

/// Fewest cells across a pocket (along x2) the tiers above `draft` accept before raising N2.
pub const POCKET_CELLS: f64 = 4.0;

/// Where a transient run starts (the periodic regime it reaches does not depend on it).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize, clap::ValueEnum)]
#[serde(rename_all = "lowercase")]
pub enum Start {
    /// The paper's initial state (model.md §4): Z = z0, Z' = v0, flooded upstream gap.
    Paper,
    /// The untextured force balance (steady 1D film at its Z, at rest): the texture only
    /// perturbs an already balanced ring, so the periodic regime comes sooner.
    #[default]
    Equilibrium,
}

fn default_solve_tol() -> f64 {
    Tolerance::default().residual
}

fn default_cycles() -> usize {
    Tolerance::default().cycles
}

impl Numerics {
    /// The film-solver settings these numerics ask for.
    pub fn film_tolerance(&self) -> Tolerance {
        Tolerance {
            residual: self.solve_tol,
            cycles: self.cycles,
            ..Tolerance::default()
        }
    }
}

impl Default for Numerics {
    /// The paper's fidelity: 512×32, dt = 4e-4 (model.md §3).
    fn default() -> Self {
        Numerics {
            n1: 512,
            n2: 32,
            dt: 4e-4,
            periodic_tol: 1e-5,
            t_max: 30.0,
            min_periods: 3,
            solver: Method::default(),
            solve_tol: default_solve_tol(),
            cycles: default_cycles(),
            start: Start::default(),
            extrapolate: true,
            approach_n2: None,
            coupling: Coupling::Implicit,
            cavitation: Cavitation::ElrodAdams,
        }
    }
}

/// An input that breaks a rule: names the parameter, its value and the rule.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{param} = {value}: {rule}")]
pub struct InputError {
    pub param: String,
    pub value: String,
    pub rule: String,
}

fn bad(param: &str, value: impl std::fmt::Display, rule: impl Into<String>) -> InputError {
    InputError {
        param: param.to_string(),
        value: value.to_string(),
        rule: rule.into(),
    }
}

fn positive(param: &str, v: f64) -> Result<(), InputError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(bad(param, v, "must be a finite number > 0"))
    }
}

/// Half the ring width (cm): the smallest radius an arc spanning the ring can have.
pub const RING_HALF_WIDTH: f64 = 0.04;

impl CaseSpec {
    /// Checks model.md §2's rules. `allow_thick` lifts the thin-film rule 10⁴·l ≥ 5·depth.
    /// Parameter names are the CLI flags.
    pub fn validate(&self, allow_thick: bool) -> Result<(), InputError> {
        if self.r.is_nan() || self.r <= RING_HALF_WIDTH {
            return Err(bad(
                "--R",
                self.r,
                format!(
                    "the ring face radius must exceed half the ring width ({RING_HALF_WIDTH} cm); use inf for a flat ring"
                ),
            ));
        }
        positive("--u", self.u)?;
        positive("--w-ps", self.w_ps)?;
        positive("--mass", self.mass)?;
        positive("--d-oil", self.d_oil)?;
        positive("--e", self.e)?;
        positive("--z0", self.z0)?;
        if !self.v0.is_finite() {
            return Err(bad("--v0", self.v0, "must be finite"));
        }
        if !(self.theta_s.is_finite() && (0.0..1.0).contains(&self.theta_s)) {
            return Err(bad("--theta-s", self.theta_s, "must lie in [0, 1)"));
        }
        if let Some(t) = &self.texture {
            positive("--l1", t.l1)?;
            positive("--l2", t.l2)?;
            positive("--per", t.per)?;
            positive("--width", t.width)?;
            positive("--depth", t.depth)?;
            if !t.phase.is_finite() {
                return Err(bad("--phase", t.phase, "must be finite"));
            }
            if 2.0 * t.l1 > t.per * (1.0 + 1e-12) {
                return Err(bad(
                    "--l1",
                    t.l1,
                    format!(
                        "2·l1 must not exceed --per = {} (pockets would overlap)",
                        t.per
                    ),
                ));
            }
            if 2.0 * t.l2 > t.width * (1.0 + 1e-12) {
                return Err(bad(
                    "--l2",
                    t.l2,
                    format!(
                        "2·l2 must not exceed --width = {} (pockets would overlap)",
                        t.width
                    ),
                ));
            }
            if !allow_thick {
                for (name, l) in [("--l1", t.l1), ("--l2", t.l2)] {
                    if 1e4 * l < 5.0 * t.depth * (1.0 - 1e-12) {
                        return Err(bad(
                            name,
                            l,
                            format!(
                                "thin-film validity needs 10⁴·l ≥ 5·depth (depth = {} µm needs l ≥ {} cm); pass --allow-thick-pockets to run anyway",
                                t.depth,
                                5.0 * t.depth * 1e-4
                            ),
                        ));
                    }
                }
            }
        }
        Ok(())
    }
}

impl Numerics {
    /// The numerics of the coarse approach to the periodic regime (`approach_n2`), if it
    /// applies to this case: N2 = approach_n2, raised where a pocket would span fewer than 2
    /// cells (as for `draft`), and still below this N2; periodic tolerance
    /// `run::APPROACH_TOL`; no approach of its own; the direct solver whatever this mesh's
    /// (on a narrow band it is the fastest measured; multigrid can pay only on wide bands,
    /// results/speed.md, and the coarse run is only a start).
    pub fn approach_numerics(&self, case: &CaseSpec) -> Option<Numerics> {
        case.texture.as_ref()?;
        let mut coarse = Numerics {
            n2: self.approach_n2?,
            periodic_tol: crate::run::APPROACH_TOL.max(self.periodic_tol),
            approach_n2: None,
            solver: Method::Direct,
            ..self.clone()
        };
        coarse.resolve_pockets(case, 2.0);
        (coarse.n2 < self.n2).then_some(coarse)
    }

    /// Checks the fidelity against the case (cells across pockets, time step, guards).
    pub fn validate(&self, case: &CaseSpec) -> Result<(), InputError> {
        if self.n1 < 16 {
            return Err(bad("--mesh", self.n1, "needs at least 16 cells along x1"));
        }
        if self.n2 < 1 {
            return Err(bad("--mesh", self.n2, "needs at least 1 cell along x2"));
        }
        if self.approach_n2 == Some(0) {
            return Err(bad(
                "--approach-n2",
                0,
                "needs at least 1 cell along x2 (or `off` for no coarse approach)",
            ));
        }
        positive("--dt", self.dt)?;
        positive("--periodic-tol", self.periodic_tol)?;
        positive("--solve-tol", self.solve_tol)?;
        if self.cycles == 0 {
            return Err(bad(
                "cycles",
                0,
                "needs at least 1 V-cycle per Newton iteration",
            ));
        }
        positive("--t-max", self.t_max)?;
        if let Some(t) = &case.texture {
            // (axis, semiaxis, cell size, extent the cells divide, name of the count)
            let axes = [
                ("l1", t.l1, 0.2 / self.n1 as f64, 0.2, "N1"),
                (
                    "l2",
                    t.l2,
                    0.5 * t.width / self.n2 as f64,
                    0.5 * t.width,
                    "N2",
                ),
            ];
            for (axis, l, d, extent, count) in axes {
                if 2.0 * l < 2.0 * d * (1.0 - 1e-12) {
                    return Err(bad(
                        "--mesh",
                        format!("{}x{}", self.n1, self.n2),
                        format!(
                            "puts {:.2} cells across the pocket axis 2·{axis} = {} cm (need ≥ 2); raise {count} to at least {}",
                            2.0 * l / d,
                            2.0 * l,
                            (extent / l).ceil()
                        ),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// Serialises R with "inf" for a flat ring (JSON has no infinity).
mod radius {
    use serde::{Deserialize, Deserializer, Serializer};

    pub fn serialize<S: Serializer>(r: &f64, s: S) -> Result<S::Ok, S::Error> {
        if r.is_infinite() {
            s.serialize_str("inf")
        } else {
            s.serialize_f64(*r)
        }
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
        #[derive(Deserialize)]
        #[serde(untagged)]
        enum R {
            Num(f64),
            Text(String),
        }
        match R::deserialize(d)? {
            R::Num(v) => Ok(v),
            R::Text(t) if t == "inf" => Ok(f64::INFINITY),
            R::Text(t) => Err(serde::de::Error::custom(format!(
                "R must be a number of cm or \"inf\", not {t:?}"
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_ring_round_trips_through_json() {
        let c = CaseSpec::paper(f64::INFINITY);
        let s = serde_json::to_string(&c).unwrap();
        assert!(s.contains("\"R\":\"inf\""));
        let back: CaseSpec = serde_json::from_str(&s).unwrap();
        assert_eq!(back, c);
    }

    #[test]
    fn the_coarse_approach_runs_on_the_direct_solver_whatever_the_full_mesh_uses() {
        let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 10.0));
        for solver in [
            Method::Direct,
            Method::Multigrid,
            Method::GaussSeidel,
            Method::PtMultigrid,
        ] {
            let num = Numerics {
                solver,
                ..Fidelity::Paper.numerics_for(&case)
            };
            let coarse = num
                .approach_numerics(&case)
                .expect("the paper tier approaches");
            assert_eq!(coarse.solver, Method::Direct);
            assert_eq!((coarse.n1, coarse.n2, coarse.dt), (num.n1, 8, num.dt));
            assert_eq!(coarse.approach_n2, None);
        }
    }

    #[test]
    fn rules_of_model_md_section_2() {
        let ok = CaseSpec::paper(0.8).with_texture(Texture::circular(0.01, 0.06, 5.0));
        assert!(ok.validate(false).is_ok());
        let overlap = CaseSpec::paper(0.8).with_texture(Texture::circular(0.04, 0.06, 5.0));
        assert_eq!(overlap.validate(false).unwrap_err().param, "--l1");
        let thick = CaseSpec::paper(0.8).with_texture(Texture::circular(0.005, 0.06, 20.0));
        assert!(thick.validate(false).is_err());
        assert!(thick.validate(true).is_ok());
        assert_eq!(
            CaseSpec::paper(0.03).validate(false).unwrap_err().param,
            "--R"
        );
    }
}
