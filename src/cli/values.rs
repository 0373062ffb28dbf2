//! The flag values that name the lower layers' enums (`--fidelity`, `--start`,
//! `--time-scheme`): their spellings and the help each value shows, kept here so that clap
//! stays in the command line.

use clap::builder::PossibleValue;
use clap::ValueEnum;

use crate::time::{Fidelity, Start, TimeScheme};

impl ValueEnum for Fidelity {
    fn value_variants<'a>() -> &'a [Self] {
        &Fidelity::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let help = match self {
            Fidelity::Draft => {
                "400×8, characteristic, dt = 1e-3: the optimiser's search (errors ≤ 1.5 % in f̄ \
                 and 0.63 % in C_min, ≈ 0.1–0.2 s a case; a pocket needs only 2 cells across)"
            }
            Fidelity::Fast => {
                "700×8, characteristic, dt = 5.7e-4, going on on 600×24 where pockets end \
                 deeper than 6·C_min (the deep-pocket mesh): studies, the optimiser and \
                 `simulate` (errors ≤ 0.9 % in f̄ and 0.77 % in C_min on Case I, Case III, \
                 R = 51.2 and the deep close-packed array; ≈ 0.4–0.7 s a case, ≈ 2 s with deep \
                 pockets)"
            }
            Fidelity::Paper => {
                "512×32, dt = 4e-4, backward Euler: the paper's numerics (docs/model.md §3), \
                 for reproducing it (4 % off on the conformal R = 51.2, its time step's error)"
            }
            Fidelity::Fine => {
                "1024×16, dt = 2e-4, BDF2: checks (errors ≤ 0.7 %), by a scheme independent of \
                 the characteristic tiers'"
            }
        };
        Some(PossibleValue::new(self.name()).help(help))
    }
}

impl ValueEnum for Start {
    fn value_variants<'a>() -> &'a [Self] {
        &[Start::Paper, Start::Equilibrium]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(match self {
            Start::Paper => PossibleValue::new("paper").help(
                "The paper's initial state (docs/model.md §4): Z = z0, Z' = v0, flooded \
                 upstream gap",
            ),
            Start::Equilibrium => PossibleValue::new("equilibrium").help(
                "The untextured force balance (steady 1D film at its Z, at rest): the texture \
                 only perturbs an already balanced ring, so the periodic regime comes sooner",
            ),
        })
    }
}

impl ValueEnum for TimeScheme {
    fn value_variants<'a>() -> &'a [Self] {
        &[
            TimeScheme::BackwardEuler,
            TimeScheme::Bdf2,
            TimeScheme::Characteristic,
        ]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(match self {
            TimeScheme::BackwardEuler => {
                PossibleValue::new("backward-euler").help("First order: (φⁿ⁺¹ − φⁿ)/dt")
            }
            TimeScheme::Bdf2 => PossibleValue::new("bdf2").help(
                "Second order: (3φⁿ⁺¹ − 4φⁿ + φⁿ⁻¹)/(2dt), with a backward-Euler step where the \
                 two previous levels are not at hand (a start, a jump, a new mesh) or where the \
                 old-level term (4φⁿ − φⁿ⁻¹)/3 would be negative somewhere (a film emptying \
                 within a step)",
            ),
            TimeScheme::Characteristic => PossibleValue::new("characteristic").help(
                "Backward Euler along the Couette characteristics: (φⁿ⁺¹ − φⁿ(x1 − u·dt/2))/dt, \
                 the Couette flux carried by that shift instead of the stencil; exact transport \
                 of the cavitated film at dt = 2·dx1/u (the step the tiers take where the \
                 texture period is a multiple of 2·dx1), interpolated below it, and rejected \
                 above it (docs/solver.md)",
            ),
        })
    }
}
