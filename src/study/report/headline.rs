//! The headline figures and Table 1: the largest gains against the plain liner, the R below
//! which no texture beats it, the best textures for small and large R.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use super::{curve_key, texture_label, Row};
use crate::model::case::Texture;
use crate::study::file::Study;

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

/// (f̄/f̄_plain, C_min/C_min,plain, outside the model) of one texture by R (as f64 bits).
type RatiosByR = BTreeMap<u64, (f64, f64, bool)>;

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
        "Ranking rule: for each texture, the mean over the rings of a class of the ratio of its outcome to the untextured liner's on the same ring — f̄/f̄_plain (lower is better) for friction, C_min/C_min,plain (higher is better) for clearance. Small R: R ≤ {small} cm; large R: R ≥ {large} cm. A texture enters a class only if every ring of the class has a result for it. Fidelity `{}` (see {}.csv for the mesh of each case). Ratios below 1 (friction) or above 1 (clearance) beat the plain liner.\n",
        study.fidelity.name(),
        study.name
    );
    let classes: [(&str, Vec<f64>); 2] = [
        (
            "Small R",
            radii.iter().copied().filter(|&r| r <= small).collect(),
        ),
        (
            "Large R",
            radii.iter().copied().filter(|&r| r >= large).collect(),
        ),
    ];
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

/// The ratios to the plain liner of each textured row that has both.
fn ratios_by_texture(rows: &[&Row]) -> ByTexture {
    let mut by_tex = ByTexture::new();
    for r in rows {
        let (Some(t), Some(fr), Some(cr)) = (&r.job.case.texture, r.f_ratio(), r.c_ratio()) else {
            continue;
        };
        by_tex
            .entry(curve_key(&r.job.case))
            .or_insert_with(|| (t.clone(), BTreeMap::new()))
            .1
            .insert(r.job.case.r.to_bits(), (fr, cr, r.outside.is_some()));
    }
    by_tex
}

/// One class of Table 1: its five best textures by the mean ratio over the class's radii
/// `rs` (friction: lowest first; clearance: highest first).
fn class_ranking(by_tex: &ByTexture, class: &str, rs: &[f64], friction: bool) -> String {
    let mut md = String::new();
    let mut ranked: Vec<(f64, &Texture, bool)> = by_tex
        .values()
        .filter_map(|(t, m)| {
            let v: Option<Vec<&(f64, f64, bool)>> =
                rs.iter().map(|r| m.get(&r.to_bits())).collect();
            let v = v?;
            let x = v.iter().map(|p| if friction { p.0 } else { p.1 });
            let flagged = v.iter().any(|p| p.2);
            Some((x.sum::<f64>() / v.len() as f64, t, flagged))
        })
        .collect();
    if friction {
        ranked.sort_by(|a, b| a.0.total_cmp(&b.0));
    } else {
        ranked.sort_by(|a, b| b.0.total_cmp(&a.0));
    }
    let rlist: Vec<String> = rs.iter().map(|r| format!("{r}")).collect();
    let _ = writeln!(
        md,
        "{class} (R = {}; {} textures ranked)\n\n| # | l1 = l2 | per | depth | mean ratio |\n|---|---|---|---|---|",
        rlist.join(", "),
        ranked.len()
    );
    for (i, (m, t, flagged)) in ranked.iter().take(5).enumerate() {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {} | {:.4}{} |",
            i + 1,
            t.l1,
            t.per,
            t.depth,
            m,
            if *flagged { " ‡" } else { "" }
        );
    }
    let _ = writeln!(md);
    md
}

/// The last part of Table 1: the least-friction and the largest-clearance texture at each R.
fn best_at_each_r(by_tex: &ByTexture, radii: &[f64]) -> String {
    let mut md = String::new();
    let _ = writeln!(
        md,
        "## Best texture at each R\n\n| R | least friction | f̄/f̄_plain | largest clearance | C_min/C_min,plain |\n|---|---|---|---|---|"
    );
    for &rr in radii {
        let at: Vec<(&Texture, &(f64, f64, bool))> = by_tex
            .values()
            .filter_map(|(t, m)| m.get(&rr.to_bits()).map(|p| (t, p)))
            .collect();
        let bf = at.iter().min_by(|a, b| a.1 .0.total_cmp(&b.1 .0));
        let bc = at.iter().max_by(|a, b| a.1 .1.total_cmp(&b.1 .1));
        let mark = |p: &(f64, f64, bool)| if p.2 { " ‡" } else { "" };
        if let (Some(bf), Some(bc)) = (bf, bc) {
            let _ = writeln!(
                md,
                "| {rr} | {} | {:.4}{} | {} | {:.4}{} |",
                texture_label(bf.0),
                bf.1 .0,
                mark(bf.1),
                texture_label(bc.0),
                bc.1 .1,
                mark(bc.1)
            );
        }
    }
    md
}
