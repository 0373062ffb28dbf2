//! An engine's operating map (docs/model.md §13): the points the engine spends its life at,
//! each the engine file's own point with its speed, gas pressure or oil viscosity changed,
//! and the share of the running time spent there. A liner is textured once and runs at all
//! of them, so a design is judged by the time-weighted friction work over the map.

use super::rules::EngineError;
use super::sections::{EngineFile, MapPointFile};
use super::Engine;
use crate::model::case::short;

/// One point of the map, ready to run: its name, its share of the time (the shares sum to
/// 1) and the engine as it runs there (with no map of its own).
#[derive(Clone, Debug)]
pub struct MapPoint {
    pub name: String,
    pub share: f64,
    pub engine: Engine,
}

/// The most points a map may hold (each is a transient cycle per candidate design).
pub const MAX_POINTS: usize = 12;

/// The largest factor on the gas pressures.
const MAX_GAS_SCALE: f64 = 10.0;

/// The map of `file`: its `[[operating]]` points (none where it lists none: the engine's
/// own point is then the map, [`Engine::operating_points`]). Each point is checked as an
/// engine of its own; an error names the point and the key.
pub fn operating_map(file: &EngineFile) -> Result<Vec<MapPoint>, EngineError> {
    let listed = &file.operating;
    if listed.len() > MAX_POINTS {
        return Err(map_err(
            "",
            format!("{} points", listed.len()),
            format!("list at most {MAX_POINTS} (each costs a cycle per design)"),
        ));
    }
    let total: f64 = listed.iter().map(|p| p.weight).sum();
    let mut points: Vec<MapPoint> = Vec::with_capacity(listed.len());
    for p in listed {
        check_point(p, &points)?;
        points.push(MapPoint {
            name: p.name.clone(),
            share: p.weight / total,
            engine: engine_at(file, p)?,
        });
    }
    Ok(points)
}

fn map_err(key: &str, value: impl std::fmt::Display, rule: impl Into<String>) -> EngineError {
    EngineError {
        key: format!("[[operating]]{}", if key.is_empty() { "" } else { " " }) + key,
        value: value.to_string(),
        rule: rule.into(),
    }
}

/// A point's own rules: a plain, new name, a positive weight, a gas factor in range.
fn check_point(p: &MapPointFile, before: &[MapPoint]) -> Result<(), EngineError> {
    let plain_name = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    if p.name.is_empty() || !p.name.chars().all(plain_name) {
        return Err(map_err(
            "name",
            format!("{:?}", p.name),
            "use letters, digits, '-' or '_' (it names the point in the reports)",
        ));
    }
    if before.iter().any(|q| q.name == p.name) {
        return Err(map_err(
            "name",
            format!("{:?}", p.name),
            "names another point too; give each its own",
        ));
    }
    let key = |k: &str| format!("{} {k}", p.name);
    if !(p.weight.is_finite() && p.weight > 0.0 && p.weight <= 1e6) {
        return Err(map_err(
            &key("weight"),
            short(p.weight),
            "must be a positive share of the running time (they are normalised over the map)",
        ));
    }
    if let Some(g) = p.gas_scale {
        if !(g.is_finite() && (0.0..=MAX_GAS_SCALE).contains(&g)) {
            return Err(map_err(
                &key("gas_scale"),
                short(g),
                format!("must lie in [0, {MAX_GAS_SCALE}] (a factor on [gas]'s pressures)"),
            ));
        }
    }
    Ok(())
}

/// The engine as it runs at point `p`: the file's with `p`'s speed, gas factor and
/// viscosity, checked by the engine's own rules (an error names `p` and the key).
fn engine_at(file: &EngineFile, p: &MapPointFile) -> Result<Engine, EngineError> {
    let mut f = file.clone();
    f.operating.clear();
    if let Some(rpm) = p.rpm {
        f.engine.rpm = rpm;
    }
    if let Some(v) = p.viscosity_pa_s {
        f.oil.viscosity_pa_s = v;
    }
    if let Some(g) = p.gas_scale {
        for v in f
            .gas
            .pressure_bar
            .iter_mut()
            .chain(f.gas.below_pressure_bar.iter_mut())
        {
            *v *= g;
        }
    }
    let renamed = |key: &str| match key {
        "[engine] rpm" => Some("rpm"),
        "[oil] viscosity_pa_s" => Some("viscosity_pa_s"),
        "[gas] pressure_bar" | "[gas] below_pressure_bar" => Some("gas_scale"),
        _ => None,
    };
    Engine::new(f).map_err(|e| match renamed(&e.key) {
        Some(k) => EngineError {
            key: format!("[[operating]] {} {k}", p.name),
            rule: format!("{} (as {})", e.rule, e.key),
            ..e
        },
        None => e,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::engine::tests::example;
    use crate::model::engine::Zones;

    fn point(name: &str, weight: f64) -> MapPointFile {
        MapPointFile {
            name: name.into(),
            weight,
            rpm: None,
            gas_scale: None,
            viscosity_pa_s: None,
        }
    }

    fn four_zones() -> EngineFile {
        example(Zones {
            count: Some(4),
            boundaries_mm: None,
        })
    }

    #[test]
    fn without_a_map_the_engine_is_its_own_point() {
        let f = four_zones();
        assert!(operating_map(&f).unwrap().is_empty());
        let m = Engine::new(f.clone()).unwrap().operating_points();
        assert_eq!(m.len(), 1);
        assert_eq!(
            (m[0].share, m[0].engine.file.engine.rpm),
            (1.0, f.engine.rpm)
        );
    }

    #[test]
    fn points_change_what_they_name_and_shares_sum_to_one() {
        let mut f = four_zones();
        let idle = MapPointFile {
            rpm: Some(800.0),
            gas_scale: Some(0.5),
            viscosity_pa_s: Some(0.03),
            ..point("idle", 1.0)
        };
        f.operating = vec![idle, point("cruise", 3.0)];
        let m = operating_map(&f).unwrap();
        assert_eq!((m[0].share, m[1].share), (0.25, 0.75));
        let e = &m[0].engine;
        assert_eq!(e.file.engine.rpm, 800.0);
        assert_eq!(e.file.oil.viscosity_pa_s, 0.03);
        assert_eq!(e.gas_bar(15.0), 0.5 * m[1].engine.gas_bar(15.0));
        assert!(e.file.operating.is_empty());
        assert_eq!(m[1].engine.file.engine.rpm, f.engine.rpm);
    }

    #[test]
    fn bad_points_name_themselves_and_the_key() {
        let cases = [
            (point("idle", 0.0), "[[operating]] idle weight"),
            (point("i dle", 1.0), "[[operating]] name"),
            (
                MapPointFile {
                    rpm: Some(1e9),
                    ..point("idle", 1.0)
                },
                "[[operating]] idle rpm",
            ),
            (
                MapPointFile {
                    gas_scale: Some(-1.0),
                    ..point("idle", 1.0)
                },
                "[[operating]] idle gas_scale",
            ),
            (
                MapPointFile {
                    viscosity_pa_s: Some(50.0),
                    ..point("idle", 1.0)
                },
                "[[operating]] idle viscosity_pa_s",
            ),
        ];
        for (p, key) in cases {
            let mut f = four_zones();
            f.operating = vec![point("full", 1.0), p];
            let e = operating_map(&f).unwrap_err();
            assert_eq!(e.key, key, "{e}");
        }
        let mut f = four_zones();
        f.operating = vec![point("a", 1.0), point("a", 1.0)];
        assert_eq!(operating_map(&f).unwrap_err().key, "[[operating]] name");
    }
}
