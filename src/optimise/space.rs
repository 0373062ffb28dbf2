//! The design space: pocket semiaxes, period and depth within bounds, mapped feasibly from the
//! unit cube, so that no design that breaks a manufacturing or validity constraint
//! (docs/model.md §2) is ever simulated.

use serde::Serialize;

use crate::model::case::{bad, short, InputError, Texture};

/// Bounds of the design variables. Lengths in cm, depth in µm. Defaults: the paper's ranges
/// (docs/model.md §7).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Bounds {
    pub l1: (f64, f64),
    pub l2: (f64, f64),
    pub per: (f64, f64),
    /// None: width = per (square lattice); Some: width is a free variable.
    pub width: Option<(f64, f64)>,
    pub depth: (f64, f64),
}

impl Default for Bounds {
    fn default() -> Self {
        Bounds {
            l1: (0.0025, 0.03),
            l2: (0.0025, 0.03),
            per: (0.005, 0.06),
            width: None,
            depth: (2.0, 30.0),
        }
    }
}

/// Manufacturability and validity constraints (docs/model.md §2).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Constraints {
    /// Least wall between neighbouring pockets, per − 2·l1 and width − 2·l2 (cm).
    pub w_min: f64,
    /// Largest textured area fraction π·l1·l2/(per·width), if any.
    pub max_area: Option<f64>,
    /// Largest depth-to-diameter ratio depth/(2·l) over both axes (µm/µm), if any.
    pub max_depth_ratio: Option<f64>,
    /// Lift the thin-film rule 10⁴·l ≥ 5·depth.
    pub allow_thick: bool,
}

/// Default least wall thickness: 10 µm.
pub const DEFAULT_W_MIN_CM: f64 = 0.001;

impl Default for Constraints {
    fn default() -> Self {
        Constraints {
            w_min: DEFAULT_W_MIN_CM,
            max_area: None,
            max_depth_ratio: None,
            allow_thick: false,
        }
    }
}

/// The design space: the unit cube mapped onto designs that satisfy every constraint.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Space {
    pub bounds: Bounds,
    pub cons: Constraints,
}

fn lerp((lo, hi): (f64, f64), u: f64) -> f64 {
    lo + u.clamp(0.0, 1.0) * (hi - lo)
}

/// Relative slack under which a constraint counts as active.
const ACTIVE: f64 = 1e-3;

impl Space {
    /// Dimensions: u = (per, l1, l2, depth[, width]).
    pub fn dim(&self) -> usize {
        if self.bounds.width.is_some() {
            5
        } else {
            4
        }
    }

    /// Least semiaxis any depth in range allows (thin film, depth ratio).
    fn l_floor(&self) -> f64 {
        let d = self.bounds.depth.0;
        let mut l = 0.0f64;
        if !self.cons.allow_thick {
            l = l.max(5.0 * d * 1e-4);
        }
        if let Some(r) = self.cons.max_depth_ratio {
            l = l.max(d / (2.0 * r * 1e4));
        }
        l
    }

    /// The design at u ∈ [0, 1]^dim. Each variable's interval depends on those before it, so
    /// that every u gives a feasible design (when `validate` passed).
    pub fn decode(&self, u: &[f64]) -> Texture {
        self.walk(&mut |k, iv| lerp(iv, u[k]))
    }

    /// The unit-cube point of a feasible design: `decode(encode(t)) ≈ t` (a design outside
    /// the space lands on its nearest face).
    pub fn encode(&self, t: &Texture) -> Vec<f64> {
        let mut u = vec![0.0; self.dim()];
        let value = [t.per, t.l1, t.l2, t.depth, t.width];
        self.walk(&mut |k, (lo, hi)| {
            u[k] = if hi > lo {
                ((value[k] - lo) / (hi - lo)).clamp(0.0, 1.0)
            } else {
                0.0
            };
            lerp((lo, hi), u[k])
        });
        u
    }

    /// Chooses the variables in order (per, [width], l1, l2, depth), each by `pick(k, interval)`
    /// with k its index in u, within the interval the earlier choices leave.
    fn walk(&self, pick: &mut dyn FnMut(usize, (f64, f64)) -> f64) -> Texture {
        let b = &self.bounds;
        let c = &self.cons;
        let floor = self.l_floor();
        let l1_min = b.l1.0.max(floor);
        let l2_min = b.l2.0.max(floor);
        let per_lo = b.per.0.max(2.0 * l1_min + c.w_min);
        // Least cell area the smallest pockets need under an area-fraction limit.
        let min_cell = c
            .max_area
            .map_or(0.0, |a| std::f64::consts::PI * l1_min * l2_min / a);
        let (per, width) = match b.width {
            None => {
                let lo = per_lo.max(2.0 * l2_min + c.w_min).max(min_cell.sqrt());
                let p = pick(0, (lo, b.per.1));
                (p, p)
            }
            Some(w) => {
                let p = pick(0, (per_lo.max(min_cell / w.1), b.per.1));
                let wlo = w.0.max(2.0 * l2_min + c.w_min).max(min_cell / p);
                (p, pick(4, (wlo, w.1)))
            }
        };
        let area_cap = |other: f64| {
            c.max_area.map_or(f64::INFINITY, |a| {
                a * per * width / (std::f64::consts::PI * other)
            })
        };
        let l1_hi = b.l1.1.min(0.5 * (per - c.w_min)).min(area_cap(l2_min));
        let l1 = pick(1, (l1_min, l1_hi.max(l1_min)));
        let l2_hi = b.l2.1.min(0.5 * (width - c.w_min)).min(area_cap(l1));
        let l2 = pick(2, (l2_min, l2_hi.max(l2_min)));
        let lmin = l1.min(l2);
        let mut d_hi = b.depth.1;
        if !c.allow_thick {
            d_hi = d_hi.min(lmin * 1e4 / 5.0);
        }
        if let Some(r) = c.max_depth_ratio {
            d_hi = d_hi.min(r * 2.0 * lmin * 1e4);
        }
        let depth = pick(3, (b.depth.0, d_hi.max(b.depth.0)));
        Texture {
            l1,
            l2,
            per,
            width,
            depth,
            phase: 0.0,
        }
    }

    /// Every constraint and bound the design breaks (empty: feasible).
    pub fn violations(&self, t: &Texture) -> Vec<String> {
        let b = &self.bounds;
        let c = &self.cons;
        let tol = 1e-9;
        let mut v = Vec::new();
        let mut within = |name: &str, x: f64, (lo, hi): (f64, f64)| {
            if x < lo * (1.0 - tol) || x > hi * (1.0 + tol) {
                v.push(format!(
                    "{name} = {} outside [{}, {}]",
                    short(x),
                    short(lo),
                    short(hi)
                ));
            }
        };
        within("l1", t.l1, b.l1);
        within("l2", t.l2, b.l2);
        within("per", t.per, b.per);
        within("width", t.width, b.width.unwrap_or(b.per));
        within("depth", t.depth, b.depth);
        if b.width.is_none() && t.width != t.per {
            v.push("width ≠ per on a square lattice".into());
        }
        let (w1, w2) = wall(t);
        if w1 < c.w_min - tol || w2 < c.w_min - tol {
            v.push(format!(
                "wall thickness ({w1:.6}, {w2:.6}) cm below w_min = {}",
                short(c.w_min)
            ));
        }
        if !c.allow_thick && 1e4 * t.l1.min(t.l2) < 5.0 * t.depth * (1.0 - tol) {
            v.push("thin-film validity 10⁴·l ≥ 5·depth broken".into());
        }
        if let Some(a) = c.max_area {
            if t.area_fraction() > a * (1.0 + tol) {
                v.push(format!("area fraction {:.4} above {a}", t.area_fraction()));
            }
        }
        if let Some(r) = c.max_depth_ratio {
            if depth_ratio(t) > r * (1.0 + tol) {
                v.push(format!("depth/diameter {:.4} above {r}", depth_ratio(t)));
            }
        }
        v
    }

    /// The constraints (not plain bounds) the design sits on.
    pub fn active(&self, t: &Texture) -> Vec<&'static str> {
        let c = &self.cons;
        let mut a = Vec::new();
        let (w1, w2) = wall(t);
        if w1 <= c.w_min + ACTIVE * t.per {
            a.push("wall x1");
        }
        if w2 <= c.w_min + ACTIVE * t.width {
            a.push("wall x2");
        }
        if !c.allow_thick && 5.0 * t.depth >= 1e4 * t.l1.min(t.l2) * (1.0 - ACTIVE) {
            a.push("thin film");
        }
        if c.max_area
            .is_some_and(|m| t.area_fraction() >= m * (1.0 - ACTIVE))
        {
            a.push("area");
        }
        if c.max_depth_ratio
            .is_some_and(|m| depth_ratio(t) >= m * (1.0 - ACTIVE))
        {
            a.push("depth ratio");
        }
        a
    }

    /// Refuses empty or inverted ranges and constraint sets no design satisfies (checked at
    /// every corner of the cube, where the intervals are tightest).
    pub fn validate(&self) -> Result<(), InputError> {
        let b = &self.bounds;
        let mut ranges = vec![
            ("l1", b.l1),
            ("l2", b.l2),
            ("per", b.per),
            ("depth", b.depth),
        ];
        if let Some(w) = b.width {
            ranges.push(("width", w));
        }
        for (name, (lo, hi)) in ranges {
            if !(lo.is_finite() && hi.is_finite() && lo > 0.0 && lo <= hi) {
                return Err(bad(
                    name,
                    range((lo, hi)),
                    "a range LO..HI needs 0 < LO ≤ HI",
                ));
            }
            // A pocket or period beyond 100 cm, or a depth beyond 1000 µm, is not a texture
            // of a liner.
            let (most, what) = match name {
                "depth" => (1e3, "a depth range ends at most at 1000 µm"),
                _ => (1e2, "a length range ends at most at 100 cm"),
            };
            if hi > most {
                return Err(bad(name, range((lo, hi)), what));
            }
        }
        let c = &self.cons;
        if !(c.w_min.is_finite() && c.w_min >= 0.0) {
            return Err(bad(
                "w_min",
                c.w_min,
                "the least wall thickness must be ≥ 0 (cm)",
            ));
        }
        if let Some(a) = c.max_area {
            if !(a > 0.0 && a <= std::f64::consts::FRAC_PI_4) {
                return Err(bad(
                    "max_area",
                    a,
                    "an area fraction must lie in (0, π/4] (π/4: touching circular pockets)",
                ));
            }
        }
        if let Some(r) = c.max_depth_ratio {
            if !(r.is_finite() && r > 0.0) {
                return Err(bad("max_depth_ratio", r, "must be a finite number > 0"));
            }
        }
        let n = self.dim();
        for corner in 0..(1usize << n) {
            let u: Vec<f64> = (0..n).map(|k| ((corner >> k) & 1) as f64).collect();
            let t = self.decode(&u);
            if let Some(v) = self.violations(&t).first() {
                return Err(bad(
                    "constraints",
                    format!(
                        "w_min = {} cm, l1 {}, l2 {}, per {}, depth {}",
                        short(c.w_min),
                        range(b.l1),
                        range(b.l2),
                        range(b.per),
                        range(b.depth)
                    ),
                    format!(
                        "no feasible texture in part of the space ({v}); widen the ranges or relax the constraints"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// A range for a message, `LO..HI` in short numbers.
fn range((lo, hi): (f64, f64)) -> String {
    format!("{}..{}", short(lo), short(hi))
}

/// Wall thickness between neighbouring pockets along x1 and x2 (cm).
pub fn wall(t: &Texture) -> (f64, f64) {
    (t.per - 2.0 * t.l1, t.width - 2.0 * t.l2)
}

/// Depth over the smaller pocket diameter (µm/µm).
pub fn depth_ratio(t: &Texture) -> f64 {
    t.depth / (2.0 * t.l1.min(t.l2) * 1e4)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_point_of_the_cube_decodes_to_a_feasible_design() {
        let spaces = [
            Space {
                bounds: Bounds::default(),
                cons: Constraints::default(),
            },
            Space {
                bounds: Bounds {
                    width: Some((0.01, 0.08)),
                    ..Bounds::default()
                },
                cons: Constraints {
                    w_min: 0.003,
                    max_area: Some(0.3),
                    max_depth_ratio: Some(0.02),
                    allow_thick: false,
                },
            },
        ];
        for s in &spaces {
            s.validate().unwrap();
            let n = s.dim();
            // A deterministic low-discrepancy-ish walk over the cube.
            for k in 0..5000u64 {
                let u: Vec<f64> = (0..n)
                    .map(|d| {
                        ((k as f64 + 0.5) * [0.618034, 0.414214, 0.732051, 0.236068, 0.123106][d])
                            .fract()
                    })
                    .collect();
                let t = s.decode(&u);
                assert!(
                    s.violations(&t).is_empty(),
                    "{u:?} → {t:?}: {:?}",
                    s.violations(&t)
                );
                // encode inverts decode: D(E(D(u))) = D(u).
                let back = s.decode(&s.encode(&t));
                for (a, b) in [
                    (back.per, t.per),
                    (back.width, t.width),
                    (back.l1, t.l1),
                    (back.l2, t.l2),
                    (back.depth, t.depth),
                ] {
                    assert!((a - b).abs() <= 1e-12 * b.abs(), "{t:?} → {back:?}");
                }
            }
        }
    }

    #[test]
    fn impossible_constraint_sets_are_refused() {
        let s = Space {
            bounds: Bounds {
                per: (0.005, 0.006),
                ..Bounds::default()
            },
            cons: Constraints {
                w_min: 0.002,
                ..Constraints::default()
            },
        };
        assert_eq!(s.validate().unwrap_err().param, "constraints");
    }
}
