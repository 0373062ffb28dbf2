//! What the engine imposes on the ring over its cycle, in the run's scaled units
//! (docs/model.md §1, §12): the liner's speed under the ring, the ring's load, the gas
//! pressures on its two sides and where the ring is along the stroke, as functions of the
//! crank angle; and the crank angles a cycle run steps through.

use super::oil::Ahead;
use crate::model::case::CaseSpec;
use crate::model::engine::Engine;
use crate::model::operating::{Scales, COMPOSITE_ROUGHNESS_UM};

/// The engine's cycle as the ring's film sees it. Scales: the mean piston speed
/// U = 2·stroke·rpm/60 and the oil's viscosity (docs/model.md §12): the speed scale stays
/// finite where the piston stops.
#[derive(Clone, Debug)]
pub struct Drive {
    engine: Engine,
    scales: Scales,
    /// Crank speed in radians per time unit L/U.
    omega: f64,
    motion: Motion,
}

/// How the ring moves along the liner.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Motion {
    /// The engine's slider-crank, its gas pressures and elastic load.
    Engine,
    /// The liner at a constant speed u (units of U) under a constant load w, no gas: a
    /// periodic regime's scene, run as a cycle (the crank angle only counts time).
    Steady { u: f64, w: f64 },
}

/// The engine's state at one crank angle, scaled.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrivePoint {
    /// Crank angle from firing top dead centre (degrees, not reduced to [0, 720)).
    pub crank_deg: f64,
    /// The liner's velocity under the ring along x1 (units of U; x1 points from the
    /// combustion chamber to the crankcase): −(the piston's velocity).
    pub u: f64,
    /// The ring's load per unit circumferential length: elastic load plus the gas pressure
    /// behind the ring over its width (units of docs/model.md §1).
    pub w: f64,
    /// Gas pressures above the ring (the cylinder's) and below it (units of 6μUL/H²).
    pub p_above: f64,
    pub p_below: f64,
    /// The ring's distance from its top-dead-centre position (cm).
    pub position_cm: f64,
}

impl Drive {
    /// The drive of `engine` in the scales of its mean piston speed and oil viscosity.
    pub fn new(engine: &Engine) -> Drive {
        let e = &engine.file.engine;
        let speed_ms = 2.0 * e.stroke_mm * 1e-3 * e.rpm / 60.0;
        let scales = Scales {
            speed_ms,
            viscosity_pas: engine.file.oil.viscosity_pa_s,
        };
        let omega = engine.omega_rad_s() * 1e-3 * scales.time_ms();
        Drive {
            engine: engine.clone(),
            scales,
            omega,
            motion: Motion::Engine,
        }
    }

    /// The liner sliding at a constant `speed_ms` (m/s, towards the crankcase) under a constant
    /// `load_n_per_m` without gas pressures, in `engine`'s scales: the scene of a periodic
    /// regime (docs/model.md §6) run as a cycle of `cycle` time units (the crank angle only
    /// counts time).
    pub fn steady(engine: &Engine, speed_ms: f64, load_n_per_m: f64, cycle: f64) -> Drive {
        let mut d = Drive::new(engine);
        d.omega = 4.0 * std::f64::consts::PI / cycle;
        d.motion = Motion::Steady {
            u: speed_ms / d.scales.speed_ms,
            w: load_n_per_m / d.scales.load_n_per_m(),
        };
        d
    }

    /// The engine's ring as a case in the drive's scales (docs/model.md §1, §12): its face
    /// radius, width and mass, the engine file's asperity contact and film (flow factors) at
    /// composite roughness `sigma_um` (µm); the operating point is the drive's at each step.
    pub fn ring_case_at(&self, sigma_um: f64) -> CaseSpec {
        let ring = &self.engine.file.ring;
        let contact = &self.engine.file.contact;
        let s = self.scales;
        CaseSpec {
            ring_width: ring.width_mm / 10.0,
            mass: ring.mass_kg_per_m / s.mass_kg_per_m(),
            scales: s,
            contact: contact.asperity(sigma_um),
            flow: contact.flow_factors(sigma_um),
            ..CaseSpec::paper(ring.r_cm)
        }
    }

    /// [`Drive::ring_case_at`] the default composite roughness (docs/model.md §9).
    pub fn ring_case(&self) -> CaseSpec {
        self.ring_case_at(COMPOSITE_ROUGHNESS_UM)
    }

    pub fn engine(&self) -> &Engine {
        &self.engine
    }

    pub fn scales(&self) -> Scales {
        self.scales
    }

    /// The time the crank takes to turn `deg` degrees (units of L/U).
    pub fn time_of(&self, deg: f64) -> f64 {
        deg.to_radians() / self.omega
    }

    /// The four-stroke cycle's duration, two crank revolutions (units of L/U).
    pub fn cycle_time(&self) -> f64 {
        self.time_of(720.0)
    }

    /// What the ring's leading edge meets on the liner (docs/model.md §12): moving towards
    /// the crankcase it follows the rings below, which leave the supply; moving back it meets
    /// its own oil. A steady slide always meets the supply.
    pub fn ahead(&self, towards_crankcase: bool) -> Ahead {
        match self.motion {
            Motion::Steady { .. } => Ahead::Supply,
            Motion::Engine if towards_crankcase => Ahead::Supply,
            Motion::Engine => Ahead::Map,
        }
    }

    /// Whether the oil the trailing edge leaves stays on the liner for a later pass: an
    /// engine's ring comes back over it; a steady slide never does (its oil leaves the scene,
    /// counted as thrown off).
    pub fn keeps_trail(&self) -> bool {
        self.motion == Motion::Engine
    }

    /// The engine's state at crank angle `deg`.
    pub fn at(&self, deg: f64) -> DrivePoint {
        if let Motion::Steady { u, w } = self.motion {
            return DrivePoint {
                crank_deg: deg,
                u,
                w,
                p_above: 0.0,
                p_below: 0.0,
                // The ring's displacement along the liner is −(the liner's under it).
                position_cm: -u * self.time_of(deg),
            };
        }
        let e = &self.engine;
        let p_unit = self.scales.pressure_pa();
        let p_above = e.gas_bar(deg) * 1e5;
        let load = e.load_n_per_m(deg);
        DrivePoint {
            crank_deg: deg,
            u: -e.velocity_ms(deg) / self.scales.speed_ms,
            w: load / self.scales.load_n_per_m(),
            p_above: p_above / p_unit,
            p_below: e.below_bar(deg) * 1e5 / p_unit,
            position_cm: 0.1 * e.position_mm(deg),
        }
    }
}

/// The crank angles a cycle run steps through over one cycle from `start_deg`: a step of
/// `step_deg` where the piston runs at its mean speed or faster, shortened in proportion to
/// the speed below it down to `step_deg·refine` near the dead centres (where the film is
/// squeezed and its direction turns), further where the texture would move more than
/// `texture_step` cm in one step where `textured(position_cm)` says pockets pass under the
/// ring, and placed so that every dead centre is a step's end (the liner's speed changes sign
/// there, and nowhere inside a step).
pub fn crank_steps(
    drive: &Drive,
    start_deg: f64,
    rule: &StepRule,
    textured: &dyn Fn(f64) -> bool,
) -> Vec<f64> {
    let mut out = vec![start_deg];
    if let Motion::Steady { .. } = drive.motion {
        stroke_steps(
            drive,
            (start_deg, start_deg + 720.0),
            rule,
            textured,
            &mut out,
        );
        return out;
    }
    let dead: Vec<f64> = (0..=4)
        .map(|k| 180.0 * k as f64)
        .map(|d| d + 180.0 * (start_deg / 180.0).floor())
        .filter(|&d| d > start_deg && d < start_deg + 720.0)
        .chain([start_deg + 720.0])
        .collect();
    let mut from = start_deg;
    for to in dead {
        stroke_steps(drive, (from, to), rule, textured, &mut out);
        from = to;
    }
    out
}

/// How a cycle run's crank steps follow the motion ([`crank_steps`]).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct StepRule {
    /// Crank step where the piston runs at the mean piston speed or faster (degrees).
    pub step_deg: f64,
    /// Least fraction of `step_deg` taken near a dead centre.
    pub refine: f64,
    /// Largest distance the liner may move under the ring in one step (cm): a texture's
    /// period over the steps it needs per period; infinite for a plain liner.
    pub texture_step: f64,
    /// Largest change of the asperities' share of the load over one step: a step over which
    /// the contact takes on or sheds more is taken in halves ([`super::CycleRun::advance`]).
    pub contact_share: f64,
}

/// Steps from `from` to `to` (no dead centre strictly between), appended to `out`: the
/// local step size s(θ) is integrated as n = ⌈∫dθ/s⌉ and the ends placed at equal parts of
/// that integral.
fn stroke_steps(
    drive: &Drive,
    (from, to): (f64, f64),
    rule: &StepRule,
    textured: &dyn Fn(f64) -> bool,
    out: &mut Vec<f64>,
) {
    const TABLE: usize = 4096;
    let size = |deg: f64| {
        let p = drive.at(deg);
        let speed = p.u.abs();
        let by_speed = rule.step_deg * speed.clamp(rule.refine, 1.0);
        if !textured(p.position_cm) {
            return by_speed;
        }
        // The liner moves |u|·dt = |u|·time_of(step) cm in one step.
        let by_texture = rule.texture_step / (speed * drive.time_of(1.0)).max(1e-300);
        by_speed.min(by_texture)
    };
    // The integral of 1/s over [from, to] by the midpoint rule on a fine table.
    let d = (to - from) / TABLE as f64;
    let mut cum = vec![0.0; TABLE + 1];
    for k in 0..TABLE {
        cum[k + 1] = cum[k] + d / size(from + (k as f64 + 0.5) * d);
    }
    let n = cum[TABLE].ceil().max(1.0) as usize;
    let mut k = 0;
    for m in 1..n {
        let target = cum[TABLE] * m as f64 / n as f64;
        while cum[k + 1] < target {
            k += 1;
        }
        let s = (target - cum[k]) / (cum[k + 1] - cum[k]);
        out.push(from + (k as f64 + s) * d);
    }
    out.push(to);
}
