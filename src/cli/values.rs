//! The flag values that name the lower layers' enums (`--fidelity`, `--start`,
//! `--time-scheme`): their spellings, kept here so that clap stays in the command line; the
//! help each value shows is the enum's own summary.

use clap::builder::PossibleValue;
use clap::ValueEnum;

use crate::time::{Fidelity, Start, TimeScheme};

impl ValueEnum for Fidelity {
    fn value_variants<'a>() -> &'a [Self] {
        &Fidelity::ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.name()).help(self.summary()))
    }
}

impl ValueEnum for Start {
    fn value_variants<'a>() -> &'a [Self] {
        &[Start::Paper, Start::Equilibrium]
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        let name = match self {
            Start::Paper => "paper",
            Start::Equilibrium => "equilibrium",
        };
        Some(PossibleValue::new(name).help(self.summary()))
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
        let name = match self {
            TimeScheme::BackwardEuler => "backward-euler",
            TimeScheme::Bdf2 => "bdf2",
            TimeScheme::Characteristic => "characteristic",
        };
        Some(PossibleValue::new(name).help(self.summary()))
    }
}
