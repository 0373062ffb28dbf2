//! The oil on the liner (docs/model.md §12): a liner-fixed map along the stroke of the oil
//! layer the ring's trailing edge leaves, which its leading edge meets on its next pass. On
//! its way towards the crankcase the ring follows the rings below it, which have just left
//! the engine's supply on the liner (and scraped off what was there); on its way back it leads
//! and meets its own oil. Every exchange is counted, so that the oil of film and liner
//! together changes only by what the supply adds and what is scraped or thrown off.

/// Oil layer thickness (µm) on the liner in cells of a fixed length over the liner
/// coordinates the ring's film domain can reach. A layer d carried at the liner's speed u
/// brings the flux u·d, which the film takes as its inlet content φ = 2d (the Couette flux is
/// (u/2)·φ, docs/model.md §3).
#[derive(Clone, Debug, PartialEq)]
pub struct OilMap {
    /// Liner coordinate of the first cell's start (cm) and the cells' length (cm).
    y0: f64,
    cell: f64,
    layer: Vec<f64>,
    /// The supply's layer per cell (µm): what the liner carries at least when the ring meets
    /// it.
    supply: Vec<f64>,
}

/// The oil a pass of the ring's leading edge over a stretch of liner met.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Taken {
    /// The stretch's mean layer (µm).
    pub layer: f64,
    /// Oil the supply laid on the stretch (µm·cm per unit circumferential length).
    pub supplied: f64,
    /// Oil the rings below scraped off the stretch before (µm·cm).
    pub scraped: f64,
}

/// What lies on the liner ahead of the ring's leading edge.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ahead {
    /// The engine's supply, laid by the rings below in place of what was there (the ring
    /// moves towards the crankcase).
    Supply,
    /// The ring's own oil of its last pass (it moves towards the combustion chamber).
    Map,
}

impl OilMap {
    /// A map of cells of about `cell` cm over [y_lo, y_hi], laid with the supply's layer
    /// `supply(y)` (µm) at each cell's centre.
    pub fn new(y_lo: f64, y_hi: f64, cell: f64, supply: impl Fn(f64) -> f64) -> OilMap {
        let n = ((y_hi - y_lo) / cell).ceil().max(1.0) as usize;
        let cell = (y_hi - y_lo) / n as f64;
        let supply: Vec<f64> = (0..n)
            .map(|k| supply(y_lo + (k as f64 + 0.5) * cell))
            .collect();
        OilMap {
            y0: y_lo,
            cell,
            layer: supply.clone(),
            supply,
        }
    }

    /// The layer per cell (µm).
    pub fn layer(&self) -> &[f64] {
        &self.layer
    }

    /// Liner coordinate of cell k's centre (cm).
    pub fn y(&self, k: usize) -> f64 {
        self.y0 + (k as f64 + 0.5) * self.cell
    }

    /// The oil on the liner, Σ layer·cell (µm·cm per unit circumferential length).
    pub fn total(&self) -> f64 {
        self.layer.iter().sum::<f64>() * self.cell
    }

    /// The cells overlapping [a, b] (either order) and each overlap's length (cm), and the
    /// length of [a, b] outside the map, before its first cell and after its last.
    fn overlaps(&self, a: f64, b: f64) -> (Vec<(usize, f64)>, f64, f64) {
        let (lo, hi) = (a.min(b), a.max(b));
        let n = self.layer.len();
        let end = self.y0 + n as f64 * self.cell;
        let (before, after) = ((self.y0.min(hi) - lo).max(0.0), (hi - end.max(lo)).max(0.0));
        let (lo, hi) = (lo.clamp(self.y0, end), hi.clamp(self.y0, end));
        let first = (((lo - self.y0) / self.cell).floor() as usize).min(n - 1);
        let last = (((hi - self.y0) / self.cell).floor() as usize).min(n - 1);
        let cells = (first..=last)
            .map(|k| {
                let c0 = self.y0 + k as f64 * self.cell;
                (k, hi.min(c0 + self.cell) - lo.max(c0))
            })
            .filter(|c| c.1 > 0.0)
            .collect();
        (cells, before, after)
    }

    /// What the leading edge sweeping liner [a, b] with `ahead` on it meets, the map left as
    /// it is ([`OilMap::take`] takes it). Beyond the map the liner carries the supply of the
    /// nearest cell, or nothing of the ring's own (it has not been there).
    pub fn meet(&self, a: f64, b: f64, ahead: Ahead) -> Taken {
        let len = (b - a).abs();
        let (cells, before, after) = self.overlaps(a, b);
        let (mut supplied, mut scraped, mut oil) = (0.0, 0.0, 0.0);
        if ahead == Ahead::Supply {
            let n = self.supply.len();
            let beyond = before * self.supply[0] + after * self.supply[n - 1];
            supplied += beyond;
            oil += beyond;
        }
        for (k, part) in cells {
            let d = match ahead {
                Ahead::Map => self.layer[k],
                Ahead::Supply => {
                    supplied += self.supply[k] * part;
                    scraped += self.layer[k] * part;
                    self.supply[k]
                }
            };
            oil += d * part;
        }
        Taken {
            layer: if len > 0.0 { oil / len } else { 0.0 },
            supplied,
            scraped,
        }
    }

    /// The leading edge sweeps liner [a, b] with `ahead` on it: what it meets
    /// ([`OilMap::meet`]) is taken off the liner into the film; the swept part of each cell
    /// leaves it, the rest stays, spread over the cell.
    pub fn take(&mut self, a: f64, b: f64, ahead: Ahead) -> Taken {
        let met = self.meet(a, b, ahead);
        for (k, part) in self.overlaps(a, b).0 {
            self.layer[k] *= 1.0 - part / self.cell;
        }
        met
    }

    /// The trailing edge leaves `volume` (µm·cm) on liner [a, b], spread evenly; on the cell
    /// at `a` when the stretch has no length (the liner at rest). Returns the part left
    /// beyond the map, which the ring never meets again.
    pub fn put(&mut self, a: f64, b: f64, volume: f64) -> f64 {
        let len = (b - a).abs();
        if len <= 0.0 {
            let n = self.layer.len();
            let k = (a - self.y0) / self.cell;
            if !(0.0..=n as f64).contains(&k) {
                return volume;
            }
            self.layer[(k as usize).min(n - 1)] += volume / self.cell;
            return 0.0;
        }
        let (cells, before, after) = self.overlaps(a, b);
        for (k, part) in cells {
            self.layer[k] += volume * (part / len) / self.cell;
        }
        volume * (before + after) / len
    }

    /// The change of the layer against `other` (same cells): Σ|Δd| over Σ|d|, the share of
    /// the oil on the liner that is not where it was: the oil map's cycle-to-cycle change.
    pub fn change_from(&self, other: &OilMap) -> f64 {
        let total: f64 = self.layer.iter().map(|d| d.abs()).sum();
        let diff: f64 = self
            .layer
            .iter()
            .zip(&other.layer)
            .map(|(a, b)| (a - b).abs())
            .sum();
        if total > 0.0 {
            diff / total
        } else {
            diff
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn taking_and_putting_back_conserves_the_oil() {
        let mut m = OilMap::new(-0.1, 1.0, 0.01, |y| if y < 0.5 { 2.0 } else { 1.0 });
        let before = m.total();
        // Sweep 0.3 cm across the supply step: a mean layer between the two.
        let t = m.take(0.35, 0.65, Ahead::Map);
        assert!(t.layer > 1.0 && t.layer < 2.0, "{t:?}");
        assert_eq!((t.supplied, t.scraped), (0.0, 0.0));
        let taken = t.layer * 0.3;
        assert!((m.total() - (before - taken)).abs() < 1e-12 * before);
        assert_eq!(m.put(0.9, 0.6, taken), 0.0);
        assert!((m.total() - before).abs() < 1e-12 * before);
        // A swept stretch is empty: met again it gives nothing, unless the supply is laid.
        assert!(m.take(0.35, 0.45, Ahead::Map).layer < 1e-9);
        let m0 = m.total();
        let s = m.take(0.3, 0.45, Ahead::Supply);
        // 0.05 cm of 2 µm was still there (0.30–0.35): scraped; 0.15 cm of supply laid.
        assert!(
            (s.scraped - 0.1).abs() < 1e-9 && (s.supplied - 0.3).abs() < 1e-9,
            "{s:?}"
        );
        assert!((s.layer - 2.0).abs() < 1e-9);
        let taken = s.layer * 0.15;
        assert!((m.total() - (m0 - s.scraped)).abs() < 1e-12, "{}", taken);
        // At rest the oil goes into one cell.
        let k = 55;
        let y = m.y(k);
        let d = m.layer()[k];
        assert_eq!(m.put(y, y, 0.01), 0.0);
        assert!((m.layer()[k] - d - 1.0).abs() < 1e-9);
        // Beyond the map: the supply of the edge comes in, what is left there is gone.
        let t = m.take(-0.3, -0.2, Ahead::Supply);
        assert!((t.layer - 2.0).abs() < 1e-12 && (t.supplied - 0.2).abs() < 1e-12);
        assert_eq!(m.take(1.2, 1.3, Ahead::Map).layer, 0.0);
        assert!((m.put(0.95, 1.05, 1.0) - 0.5).abs() < 1e-12);
    }
}
