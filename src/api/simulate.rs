//! One case from named inputs, and its answer: what `texopt simulate` and `texopt.simulate`
//! share. The inputs are read into a [`CaseSpec`] and [`Numerics`] by one function
//! ([`SimulateInputs::case`]), so that both front ends refuse the same inputs with the same
//! rule, and run the same case to the bit; the answer is one JSON object ([`answer`]).

use std::io::Write;

use serde_json::{json, Value};

use crate::model::asperity::{self, Asperity};
use crate::model::case::{bad, short, CaseSpec, InputError, Texture};
use crate::model::operating::{regime, Operating, Physical, Validity};
use crate::model::units::H_M;
use crate::time::{
    resolve, AnswerError, Approach, Fidelity, MissingUncertainty, Numerics, Outcome, Overrides,
    Progress, Start, TimeScheme,
};

/// The operating point, each setting the paper's where absent (docs/model.md §1, §4).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct OperatingInputs {
    /// Sliding speed (m/s).
    pub speed: Option<f64>,
    /// Ring load per unit circumferential length (N/m).
    pub load: Option<f64>,
    /// Oil viscosity (Pa·s).
    pub viscosity: Option<f64>,
    /// Ring face width (mm).
    pub ring_width: Option<f64>,
    /// Ring mass per unit circumferential length (kg/m).
    pub ring_mass: Option<f64>,
    /// Inlet oil film (µm).
    pub d_oil: Option<f64>,
    /// Composite RMS roughness (µm).
    pub roughness: Option<f64>,
}

impl OperatingInputs {
    /// Each setting from these inputs, else from `other`.
    pub fn or(self, other: OperatingInputs) -> OperatingInputs {
        OperatingInputs {
            speed: self.speed.or(other.speed),
            load: self.load.or(other.load),
            viscosity: self.viscosity.or(other.viscosity),
            ring_width: self.ring_width.or(other.ring_width),
            ring_mass: self.ring_mass.or(other.ring_mass),
            d_oil: self.d_oil.or(other.d_oil),
            roughness: self.roughness.or(other.roughness),
        }
    }

    /// The operating point and the validity limit these inputs set (the paper's where
    /// absent), checked: errors name the input, the value and the rule.
    pub fn resolve(&self) -> Result<(Operating, Validity), InputError> {
        let p = Operating::paper();
        let o = Operating {
            speed_ms: self.speed.unwrap_or(p.speed_ms),
            load_n_per_m: self.load.unwrap_or(p.load_n_per_m),
            viscosity_pas: self.viscosity.unwrap_or(p.viscosity_pas),
            ring_width_mm: self.ring_width.unwrap_or(p.ring_width_mm),
            ring_mass_kg_per_m: self.ring_mass.unwrap_or(p.ring_mass_kg_per_m),
            d_oil_um: self.d_oil.unwrap_or(p.d_oil_um),
        };
        o.check()?;
        let v = Validity {
            roughness_um: self.roughness.unwrap_or(Validity::default().roughness_um),
        };
        if !(v.roughness_um.is_finite() && v.roughness_um > 0.0 && v.roughness_um <= 10.0) {
            return Err(bad(
                "roughness",
                v.roughness_um,
                "must be a composite RMS roughness in (0, 10] µm",
            ));
        }
        Ok((o, v))
    }
}

/// The asperity contact (docs/model.md §11): the defaults where absent, none when `off`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ContactInputs {
    /// No asperity contact: the film alone carries the ring.
    pub off: bool,
    pub eta_beta_sigma: Option<f64>,
    pub sigma_over_beta: Option<f64>,
    /// Composite contact modulus E* (GPa).
    pub e_star: Option<f64>,
    /// Boundary shear strength τ₀ (MPa).
    pub tau0: Option<f64>,
    pub varsigma: Option<f64>,
}

/// Each contact input's field of [`Asperity`], its unit and that unit in SI (σ is the
/// operating point's `roughness`, in µm).
const CONTACT_UNITS: [(&str, &str, &str, f64); 6] = [
    ("sigma", "roughness", "µm", 1e-6),
    ("eta_beta_sigma", "eta_beta_sigma", "", 1.0),
    ("sigma_over_beta", "sigma_over_beta", "", 1.0),
    ("e_star", "e_star", "GPa", 1e9),
    ("tau0", "tau0", "MPa", 1e6),
    ("varsigma", "varsigma", "", 1.0),
];

impl ContactInputs {
    /// The asperity contact these inputs give (σ the validity's roughness), None when off;
    /// a constant out of its range is refused in its own unit.
    pub fn resolve(&self, validity: &Validity) -> Result<Option<Asperity>, InputError> {
        if self.off {
            return Ok(None);
        }
        let d = Asperity::default();
        let a = Asperity {
            sigma: validity.roughness_um * H_M,
            eta_beta_sigma: self.eta_beta_sigma.unwrap_or(d.eta_beta_sigma),
            sigma_over_beta: self.sigma_over_beta.unwrap_or(d.sigma_over_beta),
            e_star: self.e_star.map_or(d.e_star, |gpa| gpa * 1e9),
            tau0: self.tau0.map_or(d.tau0, |mpa| mpa * 1e6),
            varsigma: self.varsigma.unwrap_or(d.varsigma),
        };
        let values = [
            a.sigma,
            a.eta_beta_sigma,
            a.sigma_over_beta,
            a.e_star,
            a.tau0,
            a.varsigma,
        ];
        for ((field, lo, hi), (v, (of, name, unit, si))) in asperity::RANGES
            .into_iter()
            .zip(values.into_iter().zip(CONTACT_UNITS))
        {
            debug_assert_eq!(field, of);
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                let unit = if unit.is_empty() {
                    String::new()
                } else {
                    format!(" {unit}")
                };
                return Err(InputError {
                    waiver: Some(crate::model::case::Waiver::NoContact),
                    ..bad(
                        name,
                        v / si,
                        format!(
                            "must lie in {} to {}{unit} (docs/model.md §11)",
                            short(lo / si),
                            short(hi / si),
                        ),
                    )
                });
            }
        }
        Ok(Some(a))
    }
}

/// One case as named inputs: the ring, the texture, the operating point, the contact and the
/// numerics beside the tier.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulateInputs {
    /// Ring face radius (cm; infinite: a flat ring).
    pub r: f64,
    /// Pocket semiaxes (cm), lattice periods (cm), depth (µm; absent or 0: untextured) and
    /// the x1 position of a pocket centre at t = 0 (cm).
    pub l1: Option<f64>,
    pub l2: Option<f64>,
    pub per: Option<f64>,
    pub width: Option<f64>,
    pub depth: Option<f64>,
    pub phase: f64,
    /// Shear threshold θ_s of the Couette friction switch.
    pub theta_s: f64,
    pub operating: OperatingInputs,
    pub contact: ContactInputs,
    pub fidelity: Fidelity,
    /// N1 × N2 (cells).
    pub mesh: Option<(usize, usize)>,
    pub dt: Option<f64>,
    pub time_scheme: Option<TimeScheme>,
    pub periodic_tol: Option<f64>,
    pub t_max: f64,
    pub start: Start,
    pub accelerate: bool,
    /// The coarse approach; `Some(None)`: none.
    pub approach: Option<Option<Approach>>,
    /// Accept pockets that break thin-film validity (10⁴·l < 5·depth).
    pub allow_thick_pockets: bool,
}

impl SimulateInputs {
    /// The paper's case at ring radius `r` with every other input at its default.
    pub fn new(r: f64) -> Self {
        SimulateInputs {
            r,
            l1: None,
            l2: None,
            per: None,
            width: None,
            depth: None,
            phase: 0.0,
            theta_s: 0.95,
            operating: OperatingInputs::default(),
            contact: ContactInputs::default(),
            fidelity: Fidelity::Fast,
            mesh: None,
            dt: None,
            time_scheme: None,
            periodic_tol: None,
            t_max: 30.0,
            start: Start::Equilibrium,
            accelerate: true,
            approach: None,
            allow_thick_pockets: false,
        }
    }

    /// The case these inputs describe and its numerics ([`crate::time::resolve`]),
    /// validated: an error names the input, the value and the rule.
    pub fn case(&self) -> Result<(CaseSpec, Numerics), InputError> {
        let mut case = CaseSpec::paper(self.r);
        case.theta_s = self.theta_s;
        let (op, validity) = self.operating.resolve()?;
        op.apply(&mut case);
        case.contact = self.contact.resolve(&validity)?;
        case.texture = self.texture()?;
        let num = resolve(self.fidelity, &self.overrides(), &case);
        case.validate(self.allow_thick_pockets)?;
        num.validate(&case)?;
        Ok((case, num))
    }

    /// The texture, None for an untextured liner (no depth, or 0).
    fn texture(&self) -> Result<Option<Texture>, InputError> {
        let depth = self.depth.unwrap_or(0.0);
        if !depth.is_finite() || depth < 0.0 {
            return Err(bad(
                "depth",
                depth,
                "must be a finite depth ≥ 0 µm (0 or absent: untextured)",
            ));
        }
        if depth == 0.0 {
            return Ok(None);
        }
        let need = |name: &str, v: Option<f64>| {
            v.ok_or_else(|| bad(name, "missing", "a textured liner (a depth > 0) needs it"))
        };
        let l1 = need("l1", self.l1)?;
        let per = need("per", self.per)?;
        Ok(Some(Texture {
            l1,
            l2: self.l2.unwrap_or(l1),
            per,
            width: self.width.unwrap_or(per),
            depth,
            phase: self.phase,
        }))
    }

    /// The numerics given beside the tier.
    fn overrides(&self) -> Overrides {
        Overrides {
            n1: self.mesh.map(|m| m.0),
            n2: self.mesh.map(|m| m.1),
            dt: self.dt,
            scheme: self.time_scheme,
            periodic_tol: self.periodic_tol,
            t_max: Some(self.t_max),
            solver: None,
            start: Some(self.start),
            accelerate: Some(self.accelerate),
            approach: self.approach,
        }
    }
}

/// A run's answer: its JSON object (the inputs, the physical values, the model's validity,
/// how well it is known and every outcome), and the error stated beside it.
#[derive(Clone, Debug)]
pub struct Answered {
    pub json: Value,
    pub error: AnswerError,
    pub physical: Physical,
}

/// Why an answer cannot be given.
#[derive(Debug, thiserror::Error)]
pub enum AnswerFailure {
    #[error(transparent)]
    Uncertainty(#[from] MissingUncertainty),
    /// A number of the answer is not finite (crate::finite): nothing is answered.
    #[error("the report's {0} is not a finite number; nothing printed or written")]
    NotFinite(String),
}

/// What `simulate` answers, as the guard over reports sees it.
#[derive(serde::Serialize)]
struct Guarded<'a> {
    physical: &'a Physical,
    lambda_min: f64,
    #[serde(flatten)]
    outcome: &'a Outcome,
}

/// The answer of a run of `case` on `num` at tier `fidelity`: one JSON object, checked
/// finite, the same for every front end.
pub fn answer(
    case: &CaseSpec,
    num: &Numerics,
    (op, validity): (&Operating, &Validity),
    fidelity: Fidelity,
    outcome: &Outcome,
) -> Result<Answered, AnswerFailure> {
    let physical = op.scales().physical(case, outcome.f_mean, outcome.c_min);
    let outside = validity.outside(case, outcome.c_min);
    let lambda = outcome.c_min / validity.roughness_um;
    let error = outcome.error(case, (fidelity.f_error(), fidelity.c_error()))?;
    crate::finite::check(&Guarded {
        physical: &physical,
        lambda_min: lambda,
        outcome,
    })
    .map_err(|bad| AnswerFailure::NotFinite(bad.to_string()))?;
    let (n1, n2) = outcome.mesh((num.n1, num.n2));
    let report = json!({
        "inputs": { "case": case, "numerics": num, "mesh": format!("{n1}x{n2}"),
                    "operating": op, "roughness_um": validity.roughness_um },
        "physical": physical,
        "outside_model": outside,
        "contact": case.contact.is_some(),
        "lambda_min": lambda,
        "regime": regime(lambda),
        "asperity_share": outcome.asperity_share,
        "f_boundary": outcome.f_boundary,
        "error": error,
    });
    let mut obj = report.as_object().cloned().unwrap_or_default();
    if let Value::Object(o) = serde_json::to_value(outcome).unwrap_or_default() {
        obj.extend(o);
    }
    Ok(Answered {
        json: Value::Object(obj),
        error,
        physical,
    })
}

/// The progress line of each averaging window: redrawn in place when `redraw` (a terminal),
/// else printed at most every `every_s` seconds. `ms_per_t`: the time scale L/U in ms.
pub fn progress(redraw: bool, every_s: f64, ms_per_t: f64) -> impl FnMut(&Progress) {
    // Beyond what a Duration holds (1e300 s): never, as far as a run can tell.
    let every = std::time::Duration::try_from_secs_f64(every_s).unwrap_or(std::time::Duration::MAX);
    let began = std::time::Instant::now();
    let mut last_line = began;
    move |p: &Progress| {
        let line = format!(
            "  period {:4}  t = {:7.3} ms  f̄ = {:.5}  Z̄ = {:.4} µm  est. periodic error {:.1e}",
            p.period,
            p.t * ms_per_t,
            p.f_mean,
            p.z_mean,
            p.periodic_error
        );
        if redraw {
            eprint!("\r{line}   ");
            let _ = std::io::stderr().flush();
        } else if last_line.elapsed() >= every {
            last_line = std::time::Instant::now();
            eprintln!("{line}  ({:.0} s)", began.elapsed().as_secs_f64());
        }
    }
}
