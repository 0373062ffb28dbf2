//! The engine's tables against crank angle and stroke (docs/model.md §10): the gas
//! pressures above and below the ring, periodic over the four strokes, and the oil supply
//! along the liner; each checked as the file gives it.

use super::rules::{err, increasing, EngineError};
use super::sections::{Gas, Oil, OilSupply};
use super::Engine;
use crate::model::case::short;

/// A pressure table against crank angle (`keys`: its angles' and its pressures' keys): at
/// least two points, as many pressures as angles, angles increasing within 0–720°, gauge
/// pressures in [0, 500] bar.
fn check_table(keys: (&str, &str), deg: &[f64], bar: &[f64]) -> Result<(), EngineError> {
    let (deg_key, bar_key) = keys;
    if deg.len() < 2 || deg.len() != bar.len() {
        return Err(err(
            deg_key,
            format!("{} values", deg.len()),
            format!(
                "needs at least 2 values, as many as {} ({})",
                bar_key.trim_start_matches("[gas] "),
                bar.len()
            ),
        ));
    }
    increasing(deg_key, deg)?;
    let (lo, hi) = (deg[0], deg[deg.len() - 1]);
    if lo < 0.0 || hi > 720.0 {
        return Err(err(
            deg_key,
            format!("{}..{}", short(lo), short(hi)),
            "must lie within 0–720° (a four-stroke cycle from firing top dead centre)",
        ));
    }
    if let Some(p) = bar
        .iter()
        .find(|p| !(p.is_finite() && **p >= 0.0 && **p <= 500.0))
    {
        return Err(err(
            bar_key,
            short(*p),
            "must be a gauge pressure in [0, 500] bar",
        ));
    }
    Ok(())
}

/// The value at `deg` of a table linear between its points and periodic over 720° (the
/// last point joins the first one 720° later).
fn periodic_table(deg: &[f64], val: &[f64], at_deg: f64) -> f64 {
    let n = deg.len();
    let xs: Vec<f64> = deg.iter().copied().chain([deg[0] + 720.0]).collect();
    let ys: Vec<f64> = val.iter().copied().chain([val[0]]).collect();
    let x = at_deg.rem_euclid(720.0);
    let x = if x < xs[0] { x + 720.0 } else { x };
    let k = (0..n).find(|&k| x <= xs[k + 1]).unwrap_or(n - 1);
    let s = (x - xs[k]) / (xs[k + 1] - xs[k]);
    ys[k] + s * (ys[k + 1] - ys[k])
}

impl Engine {
    pub(super) fn check_gas(g: &Gas) -> Result<(), EngineError> {
        check_table(
            ("[gas] crank_deg", "[gas] pressure_bar"),
            &g.crank_deg,
            &g.pressure_bar,
        )?;
        if !(g.below_crank_deg.is_empty() && g.below_pressure_bar.is_empty()) {
            check_table(
                ("[gas] below_crank_deg", "[gas] below_pressure_bar"),
                &g.below_crank_deg,
                &g.below_pressure_bar,
            )?;
        }
        Ok(())
    }

    pub(super) fn check_oil(o: &Oil, stroke: f64) -> Result<(), EngineError> {
        let ok = |v: f64| v.is_finite() && v > 0.0 && v <= 1000.0;
        match &o.d_oil_um {
            OilSupply::Everywhere(v) if ok(*v) => Ok(()),
            OilSupply::Everywhere(v) => {
                Err(err("[oil] d_oil_um", short(*v), "must lie in (0, 1000] µm"))
            }
            OilSupply::Table(t) => {
                if t.len() != o.position_mm.len() || t.len() < 2 {
                    return Err(err(
                        "[oil] position_mm",
                        format!("{} values", o.position_mm.len()),
                        format!(
                            "a table of d_oil_um needs as many positions ({}), at least 2",
                            t.len()
                        ),
                    ));
                }
                increasing("[oil] position_mm", &o.position_mm)?;
                // The value named is the one outside (positions are increasing).
                let (first, last) = (o.position_mm[0], o.position_mm[t.len() - 1]);
                if first < 0.0 || last > stroke {
                    return Err(err(
                        "[oil] position_mm",
                        short(if first < 0.0 { first } else { last }),
                        format!("must lie within the stroke (0–{} mm)", short(stroke)),
                    ));
                }
                match t.iter().find(|v| !ok(**v)) {
                    Some(v) => Err(err("[oil] d_oil_um", short(*v), "must lie in (0, 1000] µm")),
                    None => Ok(()),
                }
            }
        }
    }

    /// The gas pressure behind and above the ring (bar), linear in the table, periodic over
    /// 720°.
    pub fn gas_bar(&self, crank_deg: f64) -> f64 {
        let g = &self.file.gas;
        periodic_table(&g.crank_deg, &g.pressure_bar, crank_deg)
    }

    /// The ring's load per unit circumferential length at a crank angle (N/m): its elastic
    /// load and the gas pressure behind it over its width, 1 bar giving 1e5 Pa × width (m)
    /// per metre (docs/model.md §10).
    pub fn load_n_per_m(&self, crank_deg: f64) -> f64 {
        let ring = &self.file.ring;
        ring.elastic_load_n_per_m + self.gas_bar(crank_deg) * 1e5 * ring.width_mm * 1e-3
    }

    /// The gas pressure below the ring (bar): its table, or ambient (0) without one.
    pub fn below_bar(&self, crank_deg: f64) -> f64 {
        let g = &self.file.gas;
        if g.below_crank_deg.is_empty() {
            0.0
        } else {
            periodic_table(&g.below_crank_deg, &g.below_pressure_bar, crank_deg)
        }
    }

    /// The oil film ahead of the ring at `position_mm` (µm).
    pub fn d_oil_um(&self, position_mm: f64) -> f64 {
        match &self.file.oil.d_oil_um {
            OilSupply::Everywhere(v) => *v,
            OilSupply::Table(t) => {
                let xs = &self.file.oil.position_mm;
                let x = position_mm.clamp(xs[0], xs[xs.len() - 1]);
                let k = (0..xs.len() - 1)
                    .find(|&k| x <= xs[k + 1])
                    .unwrap_or(xs.len() - 2);
                let s = (x - xs[k]) / (xs[k + 1] - xs[k]);
                t[k] + s * (t[k + 1] - t[k])
            }
        }
    }
}
