//! A liner textured zone by zone along the stroke (docs/model.md §10, §12): which texture, if
//! any, lies at each distance from the ring's top-dead-centre position. The engine cycle's
//! film reads the liner's depth at the liner coordinate under each node.

use super::case::Texture;
use super::geometry::Liner;

/// Zones along the liner, each plain or carrying a lattice of pockets. Positions are liner
/// coordinates y (cm): the distance along the liner, towards the crankcase, from where the
/// ring's centre stands at top dead centre. A zone's lattice has a pocket centre at its
/// zone's start (plus the texture's phase); the first and last zones run on past the stroke's
/// ends.
/// It serialises as its boundaries and textures, which determine it (a cache key holds it).
#[derive(Clone, Debug, serde::Serialize)]
pub struct LinerLayout {
    /// Zone boundaries (cm), increasing, from 0 to the stroke.
    bounds_cm: Vec<f64>,
    #[serde(skip)]
    zones: Vec<Liner>,
    textures: Vec<Option<Texture>>,
}

/// Why a layout cannot be simulated.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum LayoutError {
    #[error("{zones} zone boundaries need {} textures (plain or not), got {textures}", zones - 1)]
    Count { zones: usize, textures: usize },
}

impl LinerLayout {
    /// A liner with one texture (or none) over the whole stroke.
    pub fn uniform(stroke_cm: f64, texture: Option<Texture>) -> Self {
        Self::zoned(vec![0.0, stroke_cm], vec![texture]).expect("one zone, one texture")
    }

    /// Zones between `bounds_cm` with one texture (or none) each.
    pub fn zoned(bounds_cm: Vec<f64>, textures: Vec<Option<Texture>>) -> Result<Self, LayoutError> {
        if bounds_cm.len() != textures.len() + 1 {
            return Err(LayoutError::Count {
                zones: bounds_cm.len(),
                textures: textures.len(),
            });
        }
        let zones = textures
            .iter()
            .zip(&bounds_cm)
            .map(|(t, &start)| t.as_ref().map_or_else(Liner::smooth, |t| t.liner(start)))
            .collect();
        Ok(LinerLayout {
            bounds_cm,
            zones,
            textures,
        })
    }

    /// Bands along the stroke, each (start, end, texture) in cm, increasing and apart, on a
    /// plain liner: the zones between them plain, zones of no length left out. A band that
    /// starts at 0 or ends at the stroke runs on past it, as the first and last zones do.
    pub fn banded(stroke_cm: f64, bands: &[(f64, f64, Texture)]) -> Self {
        let (mut bounds, mut textures) = (vec![0.0], Vec::new());
        for (a, b, t) in bands {
            let last = *bounds.last().unwrap_or(&0.0);
            if *a > last {
                bounds.push(*a);
                textures.push(None);
            }
            bounds.push(b.min(stroke_cm));
            textures.push(Some(t.clone()));
        }
        if *bounds.last().unwrap_or(&0.0) < stroke_cm {
            bounds.push(stroke_cm);
            textures.push(None);
        }
        Self::zoned(bounds, textures).expect("one texture per zone by construction")
    }

    /// The zone boundaries (cm).
    pub fn bounds_cm(&self) -> &[f64] {
        &self.bounds_cm
    }

    /// Whether any zone is textured.
    pub fn textured(&self) -> bool {
        self.textures.iter().any(Option::is_some)
    }

    /// The smallest lattice period along the stroke (cm), infinite for a plain liner.
    pub fn finest_period_cm(&self) -> f64 {
        self.textures
            .iter()
            .flatten()
            .map(|t| t.per)
            .fold(f64::INFINITY, f64::min)
    }

    pub fn textures(&self) -> &[Option<Texture>] {
        &self.textures
    }

    /// The lattice width (cm) of the textured zone the film over liner [y_lo, y_hi] should be
    /// simulated across: that of the zone over the stretch's middle if textured, else of the
    /// first textured zone over the stretch; None if the stretch is plain.
    pub fn width_over(&self, y_lo: f64, y_hi: f64) -> Option<f64> {
        let width = |z: usize| self.textures[z].as_ref().map(|t| t.width);
        width(self.zone(0.5 * (y_lo + y_hi)))
            .or_else(|| (self.zone(y_lo)..=self.zone(y_hi)).find_map(width))
    }

    /// The zone over liner coordinate `y_cm` (the first and last run on past the stroke).
    pub fn zone(&self, y_cm: f64) -> usize {
        let b = &self.bounds_cm;
        (1..b.len() - 1)
            .find(|&k| y_cm < b[k])
            .unwrap_or(b.len() - 1)
            - 1
    }

    /// The texture's depth h_L (µm) at liner coordinate `y_cm` and `x2_cm` across.
    pub fn depth_um(&self, y_cm: f64, x2_cm: f64) -> f64 {
        self.zones[self.zone(y_cm)].depth_um(y_cm, x2_cm)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zones_carry_their_own_lattices_anchored_at_their_start() {
        let t = Texture::circular(0.01, 0.05, 5.0);
        let l = LinerLayout::zoned(vec![0.0, 1.0, 8.0], vec![Some(t.clone()), None]).unwrap();
        assert_eq!(
            (l.zone(-1.0), l.zone(0.5), l.zone(1.0), l.zone(9.0)),
            (0, 0, 1, 1)
        );
        // A pocket centre at 0 and every 0.05 cm; none in the plain zone.
        assert!((l.depth_um(0.1, 0.025) - 5.0).abs() < 1e-9);
        assert!((l.depth_um(-0.05, 0.025) - 5.0).abs() < 1e-9);
        assert_eq!(l.depth_um(0.125, 0.025), 0.0);
        assert_eq!(l.depth_um(1.0, 0.025), 0.0);
        assert_eq!(l.width_over(0.5, 1.5), Some(0.05));
        assert_eq!(l.width_over(1.5, 2.5), None);
        assert_eq!(l.finest_period_cm(), 0.05);
        let e = LinerLayout::zoned(vec![0.0, 1.0, 8.0], vec![Some(t)]).unwrap_err();
        assert!(matches!(e, LayoutError::Count { zones: 3, .. }), "{e}");
    }

    #[test]
    fn bands_lie_where_they_are_put_and_the_rest_is_plain() {
        let t = Texture::circular(0.01, 0.05, 5.0);
        // One band at top dead centre, one before the stroke's end.
        let l = LinerLayout::banded(8.0, &[(0.0, 1.0, t.clone()), (6.0, 7.5, t.clone())]);
        assert_eq!(l.bounds_cm(), &[0.0, 1.0, 6.0, 7.5, 8.0]);
        assert_eq!(
            l.textures(),
            &[Some(t.clone()), None, Some(t.clone()), None]
        );
        // The first band runs on past top dead centre; mid-stroke is plain.
        assert!((l.depth_um(-0.05, 0.025) - 5.0).abs() < 1e-9);
        assert_eq!(l.depth_um(3.0, 0.025), 0.0);
        // The second band's lattice starts at its own start.
        assert!((l.depth_um(6.0, 0.025) - 5.0).abs() < 1e-9);
        let one = LinerLayout::banded(8.0, &[(2.0, 8.0, t.clone())]);
        assert_eq!(one.bounds_cm(), &[0.0, 2.0, 8.0]);
        assert_eq!(one.textures(), &[None, Some(t)]);
    }
}
