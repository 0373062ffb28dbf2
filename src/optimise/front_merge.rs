//! Merging reported designs the report's fidelity cannot tell apart.
//!
//! Two textured designs are the same result when their f̄ differ by less than the tier's f̄
//! error and their C_min by less than its C_min error (both relative to the smaller of the
//! two values, so that the rule never merges more than either side's error allows). Of such
//! designs the one with the thickest walls is kept, being the easiest to make and the least
//! worn: walls compare by the thinner of the two (along x1, across x2) first, then by the
//! thicker. The plain liner is never merged, neither away nor into.
//!
//! Labels stay truthful: a kept design takes over every label of the designs merged into it
//! ("best friction" and "best clearance" first, then "balanced"), so a merged-away best design
//! still has its row, carried by a design within the error of it.

use super::design::{Label, Merged, Row};

/// Walls of a row as (thinner, thicker) in cm; the plain liner has none.
fn walls(r: &Row) -> (f64, f64) {
    (
        r.wall_x1_cm.min(r.wall_x2_cm),
        r.wall_x1_cm.max(r.wall_x2_cm),
    )
}

/// Whether two values differ by less than `err` relative to the smaller.
fn within(a: f64, b: f64, err: f64) -> bool {
    (a - b).abs() < err * a.abs().min(b.abs())
}

/// Merges the rows within `f_err` in f̄ and `c_err` in C_min of a thicker-walled row into
/// it (or within the larger of the two rows' own errors, where pockets deeper than the tiers
/// resolve give a row a larger one): the kept rows in their input order, and the merged-away ones. Each row merges into
/// the thickest-walled kept row it is within the errors of.
pub fn merge(rows: Vec<Row>, f_err: f64, c_err: f64) -> (Vec<Row>, Vec<Merged>) {
    let mut order: Vec<usize> = (0..rows.len()).collect();
    // Thickest walls first, so that every row meets the thicker candidates before itself.
    order.sort_by(|&a, &b| {
        let (wa, wb) = (walls(&rows[a]), walls(&rows[b]));
        wb.0.total_cmp(&wa.0).then(wb.1.total_cmp(&wa.1))
    });
    let mut kept: Vec<usize> = Vec::new();
    let mut into: Vec<Option<usize>> = vec![None; rows.len()];
    for &i in &order {
        let r = &rows[i];
        let twin = if r.texture.is_some() {
            kept.iter().copied().find(|&k| {
                let k = &rows[k];
                k.texture.is_some()
                    && within(k.f_mean, r.f_mean, f_err.max(k.f_error).max(r.f_error))
                    && within(
                        k.c_min,
                        r.c_min,
                        c_err.max(k.c_min_error).max(r.c_min_error),
                    )
            })
        } else {
            None
        };
        match twin {
            Some(k) => into[i] = Some(k),
            None => kept.push(i),
        }
    }
    let mut labels: Vec<Vec<Label>> = rows.iter().map(|r| vec![r.label.clone()]).collect();
    let mut merged = Vec::new();
    for (i, k) in into.iter().enumerate() {
        let Some(k) = *k else { continue };
        labels[k].push(rows[i].label.clone());
        merged.push(Merged {
            label: rows[i].label.clone(),
            texture: rows[i].texture.clone().expect("only textures merge"),
            f_mean: rows[i].f_mean,
            c_min: rows[i].c_min,
            into: rows[k].texture.clone().expect("only into textures"),
        });
    }
    let out = rows
        .into_iter()
        .enumerate()
        .filter(|(i, _)| into[*i].is_none())
        .map(|(i, mut r)| {
            r.label = Label::joined(&labels[i]);
            r
        })
        .collect();
    (out, merged)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::case::Texture;
    use crate::optimise::design::Role;
    use crate::time::ErrorSource;

    /// A textured row with the given f̄, C_min and walls (µm).
    fn row(label: Role, f: f64, c: f64, w1_um: f64, w2_um: f64) -> Row {
        let (per, width) = (0.06, 0.06);
        let t = Texture {
            l1: (per - w1_um * 1e-4) / 2.0,
            l2: (width - w2_um * 1e-4) / 2.0,
            per,
            width,
            depth: 5.0,
            phase: 0.0,
        };
        Row {
            label: Label::of(label),
            texture: Some(t),
            f_mean: f,
            c_min: c,
            z_mean: 0.0,
            f_change_pct: 0.0,
            c_min_change_pct: 0.0,
            area_fraction: 0.5,
            wall_x1_cm: w1_um * 1e-4,
            wall_x2_cm: w2_um * 1e-4,
            depth_ratio: 0.0,
            active_constraints: Vec::new(),
            on_front: true,
            friction_n_per_m: 0.0,
            power_w_per_m: 0.0,
            outside_model: None,
            f_error: F_ERR,
            c_min_error: C_ERR,
            error_source: ErrorSource::Tier,
        }
    }

    fn plain(f: f64, c: f64) -> Row {
        Row {
            texture: None,
            wall_x1_cm: f64::NAN,
            wall_x2_cm: f64::NAN,
            ..row(Role::PlainLiner, f, c, 0.0, 0.0)
        }
    }

    const F_ERR: f64 = 0.015;
    const C_ERR: f64 = 0.007;

    /// Rows 2 % apart in f̄ are told apart by the tier's 1.5 %, not where one carries a deep
    /// pocket's 3 % mesh uncertainty: then they merge into the thicker-walled one.
    #[test]
    fn a_deep_design_s_uncertainty_widens_the_merge() {
        let apart = || {
            vec![
                row(Role::BestFriction, 0.0900, 4.50, 10.0, 10.0),
                row(Role::Balanced, 0.0918, 4.50, 40.0, 10.0),
            ]
        };
        assert_eq!(merge(apart(), F_ERR, C_ERR).0.len(), 2);
        let mut deep = apart();
        deep[0].f_error = 0.03;
        deep[0].error_source = ErrorSource::DeepMesh;
        let (kept, merged) = merge(deep, F_ERR, C_ERR);
        assert_eq!(kept.len(), 1);
        assert_eq!(kept[0].f_mean, 0.0918, "kept: the thicker walls");
        assert_eq!(merged.len(), 1);
    }

    #[test]
    fn designs_apart_beyond_either_error_are_all_kept() {
        let rows = vec![
            row(Role::BestFriction, 0.0900, 4.50, 10.0, 10.0),
            // f̄ apart by 2 % (beyond 1.5 %), C_min equal.
            row(Role::Balanced, 0.0918, 4.50, 40.0, 10.0),
            // C_min apart by 1 % (beyond 0.7 %), f̄ equal.
            row(Role::Balanced, 0.0900, 4.545, 60.0, 20.0),
            // Both apart.
            row(Role::BestClearance, 0.0950, 5.00, 100.0, 10.0),
            plain(0.1177, 5.18),
        ];
        let (kept, merged) = merge(rows.clone(), F_ERR, C_ERR);
        assert!(merged.is_empty(), "{merged:?}");
        let labels: Vec<String> = kept.iter().map(|r| r.label.to_string()).collect();
        assert_eq!(
            labels,
            rows.iter().map(|r| r.label.to_string()).collect::<Vec<_>>()
        );
    }

    #[test]
    fn designs_within_both_errors_merge_into_the_thickest_walled_one() {
        let rows = vec![
            row(Role::BestFriction, 0.08858, 4.800, 10.0, 10.0),
            // Within both errors of best friction, thicker walls: kept, takes its label.
            row(Role::Balanced, 0.08862, 4.810, 43.8, 10.0),
            // Within both, thinnest wall thicker still (20 > 10): the one kept of the three.
            row(Role::Balanced, 0.08870, 4.805, 20.0, 20.0),
            // Beyond the C_min error of all three.
            row(Role::BestClearance, 0.0936, 5.19, 145.0, 10.0),
            // A texture within the errors of the plain liner stays, and so does the liner.
            row(Role::Balanced, 0.11780, 5.180, 200.0, 10.0),
            plain(0.11774, 5.178),
        ];
        let (kept, merged) = merge(rows, F_ERR, C_ERR);
        assert_eq!(merged.len(), 2, "{merged:?}");
        let labels: Vec<String> = kept.iter().map(|r| r.label.to_string()).collect();
        assert_eq!(
            labels,
            ["best friction", "best clearance", "balanced", "plain liner"]
        );
        // The kept twin has the thickest walls of the three (20/20 µm).
        assert!((kept[0].wall_x1_cm - 20e-4).abs() < 1e-12);
        assert!((kept[0].wall_x2_cm - 20e-4).abs() < 1e-12);
        let into = kept[0].texture.clone().unwrap();
        assert!(merged.iter().all(|m| m.into == into));
        let mut gone: Vec<String> = merged.iter().map(|m| m.label.to_string()).collect();
        gone.sort();
        assert_eq!(gone, ["balanced", "best friction"]);
    }

    #[test]
    fn a_row_merging_both_best_designs_carries_both_labels() {
        let rows = vec![
            row(Role::BestFriction, 0.0900, 4.80, 10.0, 10.0),
            row(Role::BestClearance, 0.0901, 4.81, 30.0, 10.0),
            row(Role::Balanced, 0.0902, 4.805, 40.0, 20.0),
        ];
        let (kept, merged) = merge(rows, F_ERR, C_ERR);
        assert_eq!(merged.len(), 2);
        assert_eq!(kept.len(), 1);
        assert_eq!(kept[0].label.to_string(), "best friction + best clearance");
    }
}
