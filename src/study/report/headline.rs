//! The headline figures and Table 1: the largest gains against the plain liner, the R below
//! which no texture beats it, the best textures for small and large R.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::{curve_key, texture_label, Row};
use crate::model::case::Texture;
use crate::study::file::Study;
use crate::time::{ErrorSource, DEEP_POCKET_RATIO};

/// The largest friction reduction and clearance gain against the plain liner, and the R
/// below which no texture beats it.
pub(super) fn headline(
    rows: &[&Row],
    theta_s: f64,
    fidelity: crate::time::Fidelity,
) -> Vec<String> {
    // Nothing to weigh (every textured case or its plain liner failed or was not run): no
    // conclusion, rather than "no texture beats it".
    if !rows
        .iter()
        .any(|r| r.job.case.texture.is_some() && r.f_ratio().is_some())
    {
        return vec![
            "no textured case has a result beside its untextured liner's (they failed or were not run): nothing to compare"
                .into(),
        ];
    }
    let mut out = best_against_plain(rows);
    let mut radii: Vec<f64> = rows.iter().map(|r| r.job.case.r).collect();
    radii.sort_by(f64::total_cmp);
    radii.dedup();
    type Gain<'a> = &'a dyn Fn(&Row) -> Option<f64>;
    let f_gain: Gain = &|r: &Row| r.f_ratio().map(|x| 1.0 - x);
    let c_gain: Gain = &|r: &Row| r.c_ratio().map(|x| x - 1.0);
    for (what, gain, err) in [
        ("friction", f_gain, fidelity.f_error()),
        ("clearance", c_gain, fidelity.c_error()),
    ] {
        out.push(first_r_beating(rows, &radii, what, gain, err, fidelity));
    }
    out.push(format!(
        "(friction per eq. 11 with θs = {theta_s}; the paper prints f/10)"
    ));
    out
}

/// The headline's largest friction reduction and clearance gain against the plain liner
/// (or, when no texture gains, the least loss).
fn best_against_plain(rows: &[&Row]) -> Vec<String> {
    let mut out = Vec::new();
    // The best within the hydrodynamic model: a flagged case is not a prediction.
    let best = |ratio: &dyn Fn(&Row) -> Option<f64>, lower: bool| {
        rows.iter()
            .filter(|r| r.job.case.texture.is_some() && r.outside.is_none() && !r.plain_outside)
            .filter_map(|r| Some((ratio(r)?, *r)))
            .filter(|(x, _)| x.is_finite())
            .min_by(|a, b| {
                if lower {
                    a.0.total_cmp(&b.0)
                } else {
                    b.0.total_cmp(&a.0)
                }
            })
    };
    if let Some((x, r)) = best(&|r: &Row| r.f_ratio(), true) {
        out.push(format!(
            "{}: {:.1} % ({}, f = {:.5} vs {:.5})",
            if x < 1.0 {
                "largest friction reduction against the untextured liner (within the hydrodynamic model)"
            } else {
                "no texture lowers friction; the least increase"
            },
            100.0 * (1.0 - x).abs(),
            r.job.case.label(),
            r.out.map_or(f64::NAN, |o| o.f_mean),
            r.plain.map_or(f64::NAN, |o| o.f_mean)
        ));
    }
    if let Some((x, r)) = best(&|r: &Row| r.c_ratio(), false) {
        out.push(format!(
            "{}: {:.1} % ({}, C_min = {:.4} vs {:.4} µm)",
            if x > 1.0 {
                "largest minimum-clearance increase against the untextured liner (within the hydrodynamic model)"
            } else {
                "no texture raises the minimum clearance; the least decrease"
            },
            100.0 * (x - 1.0).abs(),
            r.job.case.label(),
            r.out.map_or(f64::NAN, |o| o.c_min),
            r.plain.map_or(f64::NAN, |o| o.c_min)
        ));
    }
    out
}

/// The headline's line on the first R (of `radii`, ascending) where some texture beats the
/// plain liner in `what`. "Beats" means a `gain` over the fidelity's measured error `err`;
/// smaller gains are reported but not counted (they are not resolved).
fn first_r_beating(
    rows: &[&Row],
    radii: &[f64],
    what: &str,
    gain: &dyn Fn(&Row) -> Option<f64>,
    err: f64,
    fidelity: crate::time::Fidelity,
) -> String {
    let textured = || rows.iter().filter(|r| r.job.case.texture.is_some());
    let first = radii
        .iter()
        .copied()
        .find(|&rr| textured().any(|r| r.job.case.r == rr && gain(r).is_some_and(|g| g > err)));
    let best_below = textured()
        .filter(|r| first.is_none_or(|f| r.job.case.r < f))
        .filter_map(|r| Some((gain(r)?, r)))
        .max_by(|a, b| a.0.total_cmp(&b.0));
    let margin = format!(
        "by more than the {} tier's error ({:.2} %)",
        fidelity.name(),
        100.0 * err
    );
    let mut line = match first {
        Some(rr) if rr == radii[0] => format!(
            "{what}: some texture beats the untextured liner {margin} already at the smallest R = {rr}"
        ),
        Some(rr) => format!(
            "{what}: no texture beats the untextured liner {margin} below R = {rr} (the first R where one does)"
        ),
        None => format!("{what}: no texture beats the untextured liner {margin} at any R"),
    };
    if let (Some((g, r)), true) = (best_below, first != Some(radii[0])) {
        line += &format!(
            "; {} the largest gain is {:+.2} % ({})",
            if first.is_some() {
                "below it"
            } else {
                "at best"
            },
            100.0 * g,
            r.job.case.label()
        );
    }
    line
}

/// One texture's ratios to the plain liner on one ring.
#[derive(Clone, Copy, Debug)]
struct Ratio {
    /// f̄/f̄_plain and C_min/C_min,plain.
    f: f64,
    c: f64,
    /// Their deep-pocket mesh uncertainties (relative; 0 where the pockets end within
    /// `DEEP_POCKET_RATIO`·C_min, whose tier error the textures of a ring share).
    uf: f64,
    uc: f64,
    /// Outside the model (either run).
    outside: bool,
}

/// A texture's ratios by R (as f64 bits).
type RatiosByR = BTreeMap<u64, Ratio>;

/// Each texture (by curve key) with its ratios to the plain liner by R.
type ByTexture = BTreeMap<String, (Texture, RatiosByR)>;

/// Table 1: the best textures for small and large R, ranked by the class mean of the ratio
/// to the plain liner; and the best texture at each R.
pub(super) fn table1(study: &Study, rows: &[&Row], radii: &[f64]) -> String {
    let (small, large) = (study.report.small_r_max, study.report.large_r_min);
    let mut md = String::new();
    let _ = writeln!(
        md,
        "# Best textures of study `{}` (Table 1 of the paper)\n",
        study.name
    );
    let _ = writeln!(
        md,
        "Ranking rule: for each texture, the mean over the rings of a class of the ratio of its outcome to the untextured liner's on the same ring — f̄/f̄_plain (lower is better) for friction, C_min/C_min,plain (higher is better) for clearance. Small R: R ≤ {small} cm; large R: R ≥ {large} cm. A texture enters a class only if every ring of the class has a result for it. Fidelity `{}` (see {}.csv for the mesh of each case). Ratios below 1 (friction) or above 1 (clearance) beat the plain liner. Where pockets end deeper than {DEEP_POCKET_RATIO}·C_min the ratio carries its answer's mesh uncertainty (docs/validation.md, \"Deep pockets: the measured uncertainty\"); the ± column is the mean of the class's, and a row whose mean ratio is within the larger ± of its own and the row above's is tied with it (= after its place), not ordered; rows tied with the fifth are shown too. The whole ranking is in {}_ranking.csv.\n",
        study.fidelity.name(),
        study.name,
        study.name
    );
    let classes = classes(study, radii);
    let by_tex = ratios_by_texture(rows);
    for (title, friction) in [
        ("(a) Best textures in terms of friction", true),
        ("(b) Best textures in terms of clearance", false),
    ] {
        let _ = writeln!(md, "## {title}\n");
        for (class, rs) in &classes {
            if !rs.is_empty() {
                md += &class_ranking(&by_tex, class, rs, friction);
            }
        }
    }
    md += &best_at_each_r(&by_tex, radii);
    if !md.contains(" ‡") {
        return md;
    }
    let _ = writeln!(
        md,
        "\n‡ at least one case behind the value is outside the hydrodynamic model: its minimum clearance is below {:.2} µm ({} × a composite roughness of {} µm, docs/model.md §9), where the surfaces touch; such values are not predictions. The CSV says which case and why (column outside_model).",
        study.validity.clearance_limit_um(),
        crate::model::operating::FULL_FILM_LAMBDA,
        study.validity.roughness_um
    );
    md
}

/// Table 1's classes: the small and the large rings among `radii`.
fn classes(study: &Study, radii: &[f64]) -> [(&'static str, Vec<f64>); 2] {
    let (small, large) = (study.report.small_r_max, study.report.large_r_min);
    [
        (
            "Small R",
            radii.iter().copied().filter(|&r| r <= small).collect(),
        ),
        (
            "Large R",
            radii.iter().copied().filter(|&r| r >= large).collect(),
        ),
    ]
}

/// The ratios to the plain liner of each textured row that has both.
fn ratios_by_texture(rows: &[&Row]) -> ByTexture {
    let mut by_tex = ByTexture::new();
    for r in rows {
        let (Some(t), Some(f), Some(c)) = (&r.job.case.texture, r.f_ratio(), r.c_ratio()) else {
            continue;
        };
        let deep = r.error.filter(|e| e.source == ErrorSource::DeepMesh);
        let ratio = Ratio {
            f,
            c,
            uf: deep.map_or(0.0, |e| e.f_mean),
            uc: deep.map_or(0.0, |e| e.c_min),
            outside: r.outside.is_some(),
        };
        by_tex
            .entry(curve_key(&r.job.case))
            .or_insert_with(|| (t.clone(), BTreeMap::new()))
            .1
            .insert(r.job.case.r.to_bits(), ratio);
    }
    by_tex
}

/// A texture's place in a class of Table 1: its mean ratio over the class's radii, that
/// mean's deep-pocket uncertainty (absolute), whether it is tied with the texture ranked
/// above it, and whether a value behind it is outside the model.
struct Ranked<'t> {
    mean: f64,
    uncertainty: f64,
    tied: bool,
    texture: &'t Texture,
    flagged: bool,
}

/// Every texture of a class ranked by its mean ratio over the class's radii `rs` (friction:
/// lowest first; clearance: highest first). A texture whose mean differs from the one ranked
/// above by less than the larger of their uncertainties is tied with it: the ratios'
/// deep-pocket uncertainties, taken as fully correlated over the radii (docs/validation.md,
/// "Deep pockets: the measured uncertainty").
fn ranking<'t>(by_tex: &'t ByTexture, rs: &[f64], friction: bool) -> Vec<Ranked<'t>> {
    let mut ranked: Vec<Ranked> = by_tex
        .values()
        .filter_map(|(t, m)| {
            let v: Option<Vec<&Ratio>> = rs.iter().map(|r| m.get(&r.to_bits())).collect();
            let v = v?;
            let n = v.len() as f64;
            let (x, u): (Vec<f64>, Vec<f64>) = v
                .iter()
                .map(|p| {
                    if friction {
                        (p.f, p.f * p.uf)
                    } else {
                        (p.c, p.c * p.uc)
                    }
                })
                .unzip();
            Some(Ranked {
                mean: x.iter().sum::<f64>() / n,
                uncertainty: u.iter().sum::<f64>() / n,
                tied: false,
                texture: t,
                flagged: v.iter().any(|p| p.outside),
            })
        })
        .collect();
    if friction {
        ranked.sort_by(|a, b| a.mean.total_cmp(&b.mean));
    } else {
        ranked.sort_by(|a, b| b.mean.total_cmp(&a.mean));
    }
    for i in 1..ranked.len() {
        let (above, this) = (&ranked[i - 1], &ranked[i]);
        ranked[i].tied = (this.mean - above.mean).abs() < this.uncertainty.max(above.uncertainty);
    }
    ranked
}

/// Rows Table 1 shows of a class: the five best, and after them those tied with the fifth.
const SHOWN: usize = 5;

/// One class of Table 1: its best textures ([`ranking`], [`SHOWN`]), "=" after the place of a
/// texture tied with the one above.
fn class_ranking(by_tex: &ByTexture, class: &str, rs: &[f64], friction: bool) -> String {
    let mut md = String::new();
    let ranked = ranking(by_tex, rs, friction);
    let rlist: Vec<String> = rs.iter().map(|r| format!("{r}")).collect();
    let _ = writeln!(
        md,
        "{class} (R = {}; {} textures ranked)\n\n| # | l1 = l2 | per | depth | mean ratio | ± (deep pockets) |\n|---|---|---|---|---|---|",
        rlist.join(", "),
        ranked.len()
    );
    let shown = (SHOWN..ranked.len())
        .find(|&i| !ranked[i].tied)
        .unwrap_or(ranked.len());
    for (i, r) in ranked.iter().take(shown).enumerate() {
        let _ = writeln!(
            md,
            "| {}{} | {} | {} | {} | {:.4}{} | {} |",
            i + 1,
            if r.tied { " =" } else { "" },
            r.texture.l1,
            r.texture.per,
            r.texture.depth,
            r.mean,
            if r.flagged { " ‡" } else { "" },
            if r.uncertainty > 0.0 {
                format!("{:.4}", r.uncertainty)
            } else {
                "–".into()
            }
        );
    }
    let _ = writeln!(md);
    md
}

/// The whole ranking behind Table 1 as CSV: each class and criterion, every texture ranked,
/// whether it is tied with the one above, its mean ratio and that mean's uncertainty.
pub(super) fn ranking_csv(study: &Study, rows: &[&Row], radii: &[f64]) -> String {
    let by_tex = ratios_by_texture(rows);
    let mut csv = String::from(
        "criterion,class,rank,tied_with_above,l1,l2,per,width,depth,mean_ratio,uncertainty,outside_model\n",
    );
    for (criterion, friction) in [("friction", true), ("clearance", false)] {
        for (class, rs) in classes(study, radii) {
            if rs.is_empty() {
                continue;
            }
            for (i, r) in ranking(&by_tex, &rs, friction).iter().enumerate() {
                let t = r.texture;
                let _ = writeln!(
                    csv,
                    "{criterion},{class},{},{},{},{},{},{},{},{},{},{}",
                    i + 1,
                    r.tied,
                    t.l1,
                    t.l2,
                    t.per,
                    t.width,
                    t.depth,
                    r.mean,
                    r.uncertainty,
                    r.flagged
                );
            }
        }
    }
    csv
}

/// The last part of Table 1: the least-friction and the largest-clearance texture at each R.
fn best_at_each_r(by_tex: &ByTexture, radii: &[f64]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Best texture at each R\n\n| R | least friction | f̄/f̄_plain | largest clearance | C_min/C_min,plain |\n|---|---|---|---|---|"
    );
    for &rr in radii {
        let at: Vec<(&Texture, &Ratio)> = by_tex
            .values()
            .filter_map(|(t, m)| m.get(&rr.to_bits()).map(|p| (t, p)))
            .collect();
        let bf = at.iter().min_by(|a, b| a.1.f.total_cmp(&b.1.f));
        let bc = at.iter().max_by(|a, b| a.1.c.total_cmp(&b.1.c));
        let mark = |p: &Ratio| if p.outside { " ‡" } else { "" };
        if let (Some(bf), Some(bc)) = (bf, bc) {
            let _ = writeln!(
                md,
                "| {rr} | {} | {:.4}{} | {} | {:.4}{} |",
                texture_label(bf.0),
                bf.1.f,
                mark(bf.1),
                texture_label(bc.0),
                bc.1.c,
                mark(bc.1)
            );
        }
    }
    md
}
