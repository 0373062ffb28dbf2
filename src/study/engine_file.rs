//! Engine files (TOML, docs/model.md §10): the engine's sections read and checked into a
//! `model::engine::Engine`, and the `[design]` section into the caller's design settings.
//!
//! ```toml
//! [engine]                    # the crank train
//! name = "gasoline"           # names the report's files
//! bore_mm = 80
//! stroke_mm = 86
//! rod_mm = 140
//! rpm = 2000
//! [ring]
//! R_cm = 5
//! width_mm = 1.2
//! mass_kg_per_m = 0.02
//! elastic_load_n_per_m = 100
//! [gas]                       # gauge pressure behind and above the ring against crank angle
//! crank_deg = [0, 30, 180, 360, 690]
//! pressure_bar = [30, 50, 2, 0, 10]
//! below_crank_deg = [0, 360]  # optional: below the ring (ambient without)
//! below_pressure_bar = [1, 1]
//! [oil]
//! viscosity_pa_s = 0.006
//! d_oil_um = 20               # or a table against position_mm
//! [zones]
//! count = 4                   # or boundaries_mm = [0, …, stroke]
//! [[operating]]               # optional, repeated: the operating map (docs/model.md §13)
//! name = "idle"               # and weight (time share); rpm, gas_scale, viscosity_pa_s
//! weight = 0.3                #   change the engine's own where given
//! [contact]                   # optional: the asperities (docs/model.md §11)
//! eta_beta_sigma = 0.04       # and sigma_over_beta, e_star_gpa, tau0_mpa, varsigma; off = true
//! [design]                    # the design's settings (`texopt cycle`)
//! ```

use serde::de::DeserializeOwned;
use serde::Deserialize;

use crate::model::case::one_line;
use crate::model::engine::MapPointFile;
use crate::model::engine::{
    ContactFile, Crank, Engine, EngineError, EngineFile, Gas, LinerZones, Oil, RingFile, Zones,
};

/// An engine file that cannot be used.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum EngineFileError {
    /// Not TOML, or a section of the wrong shape: the parser's message on one line (it
    /// names the line and column).
    #[error("{0}")]
    Syntax(String),
    /// A value that breaks the engine's rules.
    #[error(transparent)]
    Engine(#[from] EngineError),
    /// The `[design]` section does not fit the design settings: the parser's message.
    #[error("[design] {0}")]
    Design(String),
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileToml {
    engine: Crank,
    ring: RingFile,
    gas: Gas,
    oil: Oil,
    zones: Zones,
    #[serde(default)]
    contact: ContactFile,
    #[serde(default)]
    operating: Vec<MapPointFile>,
    #[serde(default)]
    design: toml::Table,
}

/// Reads and checks an engine file's text: the engine, the liner's zones, then its `[design]`
/// section as `D`.
pub fn parse<D: DeserializeOwned>(text: &str) -> Result<(Engine, LinerZones, D), EngineFileError> {
    let raw: FileToml =
        toml::from_str(text).map_err(|e| EngineFileError::Syntax(one_line(&e.to_string())))?;
    let engine = Engine::new(EngineFile {
        engine: raw.engine,
        ring: raw.ring,
        gas: raw.gas,
        oil: raw.oil,
        zones: raw.zones,
        contact: raw.contact,
        operating: raw.operating,
    })?;
    let zones = LinerZones::new(&engine)?;
    let design = toml::Value::Table(raw.design)
        .try_into()
        .map_err(|e: toml::de::Error| EngineFileError::Design(one_line(&e.to_string())))?;
    Ok((engine, zones, design))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn engine(text: &str) -> Result<Engine, EngineFileError> {
        parse::<serde::de::IgnoredAny>(text).map(|(e, _, _)| e)
    }

    /// The key an error names (`file` for a syntax error).
    fn key_of(e: &EngineFileError) -> &str {
        match e {
            EngineFileError::Syntax(_) => "file",
            EngineFileError::Engine(e) => &e.key,
            EngineFileError::Design(_) => "[design]",
        }
    }

    const EXAMPLE: &str = r#"
        [engine]
        name = "test"
        bore_mm = 80
        stroke_mm = 86
        rod_mm = 140
        rpm = 2000
        [ring]
        R_cm = 5
        width_mm = 1.2
        mass_kg_per_m = 0.02
        elastic_load_n_per_m = 100
        [gas]
        crank_deg = [0, 30, 180, 360, 690]
        pressure_bar = [30, 50, 2, 0, 10]
        [oil]
        viscosity_pa_s = 0.006
        d_oil_um = 20
        [zones]
        count = 4
    "#;

    #[test]
    fn bad_engine_files_name_the_key() {
        for (from, to, key) in [
            ("rod_mm = 140", "rod_mm = 40", "[engine] rod_mm"),
            ("rpm = 2000", "rpm = -5", "[engine] rpm"),
            (
                "crank_deg = [0, 30, 180, 360, 690]",
                "crank_deg = [0, 30, 20, 360, 690]",
                "[gas] crank_deg",
            ),
            (
                "pressure_bar = [30, 50, 2, 0, 10]",
                "pressure_bar = [30, 50, 2]",
                "[gas] crank_deg",
            ),
            (
                "count = 4",
                "boundaries_mm = [0, 40, 100]",
                "[zones] boundaries_mm",
            ),
            ("count = 4", "count = 0", "[zones] count"),
            ("width_mm = 1.2", "width_mm = 120", "[ring] width_mm"),
            ("d_oil_um = 20", "d_oil_um = -1", "[oil] d_oil_um"),
            ("R_cm = 5", "", "file"),
            ("R_cm = 5", "R_cm = 0.05", "[ring] R_cm"),
            ("count = 4", "count = 51", "[zones] count"),
        ] {
            let text = EXAMPLE.replace(from, to);
            let e = engine(&text).unwrap_err();
            assert_eq!(key_of(&e), key, "{to}: {e}");
        }
    }

    #[test]
    fn every_physical_input_has_a_range_and_absurd_values_print_short() {
        for (from, to, key, says) in [
            (
                "bore_mm = 80",
                "bore_mm = 1e300",
                "[engine] bore_mm",
                "1e300",
            ),
            (
                "bore_mm = 80",
                "bore_mm = 1e-300",
                "[engine] bore_mm",
                "1e-300",
            ),
            (
                "stroke_mm = 86",
                "stroke_mm = 1e300",
                "[engine] stroke_mm",
                "1e300",
            ),
            ("rod_mm = 140", "rod_mm = 1e300", "[engine] rod_mm", "1e300"),
            ("rpm = 2000", "rpm = 1e9", "[engine] rpm", "1e9"),
            ("rpm = 2000", "rpm = 0.001", "[engine] rpm", "0.001"),
            ("R_cm = 5", "R_cm = 1e300", "[ring] R_cm", "1e300"),
            (
                "width_mm = 1.2",
                "width_mm = 1e-300",
                "[ring] width_mm",
                "1e-300",
            ),
            (
                "mass_kg_per_m = 0.02",
                "mass_kg_per_m = 1e300",
                "[ring] mass_kg_per_m",
                "1e300",
            ),
            (
                "elastic_load_n_per_m = 100",
                "elastic_load_n_per_m = 1e-300",
                "[ring] elastic_load_n_per_m",
                "1e-300",
            ),
            (
                "viscosity_pa_s = 0.006",
                "viscosity_pa_s = 1e300",
                "[oil] viscosity_pa_s",
                "1e300",
            ),
            (
                "d_oil_um = 20",
                "d_oil_um = 1e300",
                "[oil] d_oil_um",
                "1e300",
            ),
        ] {
            let text = EXAMPLE.replace(from, to);
            let e = engine(&text).unwrap_err();
            let m = e.to_string();
            assert_eq!(key_of(&e), key, "{to}: {m}");
            assert!(m.contains(says) && m.len() < 120, "{to}: {m}");
        }
    }
}
