//! A liner textured in bands (docs/model.md §13): one band next to each dead centre, each
//! with its distance from the dead centre, its length and its own texture, the liner plain
//! elsewhere. The band space maps the unit cube onto such liners, as [`Space`] maps it onto
//! textures, so that every search runs on it unchanged.

use serde::{Deserialize, Serialize};

use crate::model::case::Texture;
use crate::model::liner_layout::LinerLayout;
use crate::optimise::space::Space;

/// Which dead centre a band lies next to.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DeadCentre {
    Top,
    Bottom,
}

impl DeadCentre {
    pub fn name(self) -> &'static str {
        match self {
            DeadCentre::Top => "top dead centre",
            DeadCentre::Bottom => "bottom dead centre",
        }
    }
}

/// One band: where it lies along the stroke (mm from the ring's top-dead-centre position)
/// and its texture.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Band {
    pub at: DeadCentre,
    pub start_mm: f64,
    pub end_mm: f64,
    pub texture: Texture,
}

/// A banded liner: its bands, top dead centre's first.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Banded {
    pub bands: Vec<Band>,
}

impl Banded {
    /// The liner along a stroke of `stroke_mm`.
    pub fn layout(&self, stroke_mm: f64) -> LinerLayout {
        let bands: Vec<(f64, f64, Texture)> = self
            .bands
            .iter()
            .map(|b| (0.1 * b.start_mm, 0.1 * b.end_mm, b.texture.clone()))
            .collect();
        LinerLayout::banded(0.1 * stroke_mm, &bands)
    }

    /// One line: each band's span and texture.
    pub fn label(&self) -> String {
        self.bands
            .iter()
            .map(|b| {
                format!(
                    "{:.1}–{:.1} mm {}",
                    b.start_mm,
                    b.end_mm,
                    b.texture.rounded_label()
                )
            })
            .collect::<Vec<_>>()
            .join("; ")
    }
}

/// Why a band space cannot be searched.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BandSpaceError {
    #[error("the least band length {min_mm} mm must lie in (0, {half_mm}] mm (half the stroke: a band each side)")]
    MinLength { min_mm: f64, half_mm: f64 },
}

/// The banded liners of a stroke: per band (top dead centre's, then bottom's) its distance
/// from the dead centre, its length, both within its half of the stroke and the length at
/// least `min_len_mm`, then its texture in `texture`.
#[derive(Clone, Debug)]
pub struct BandSpace {
    pub texture: Space,
    pub stroke_mm: f64,
    pub min_len_mm: f64,
}

/// Cube coordinates of a band before its texture's: distance from the dead centre, length.
const PLACE: usize = 2;

impl BandSpace {
    pub fn new(texture: Space, stroke_mm: f64, min_len_mm: f64) -> Result<Self, BandSpaceError> {
        let half_mm = 0.5 * stroke_mm;
        if !(min_len_mm.is_finite() && min_len_mm > 0.0 && min_len_mm <= half_mm) {
            return Err(BandSpaceError::MinLength {
                min_mm: min_len_mm,
                half_mm,
            });
        }
        Ok(BandSpace {
            texture,
            stroke_mm,
            min_len_mm,
        })
    }

    fn per_band(&self) -> usize {
        PLACE + self.texture.dim()
    }

    pub fn dim(&self) -> usize {
        2 * self.per_band()
    }

    /// The liner at cube point `u`: band k from u[k·m..(k + 1)·m], m = 2 + the texture's
    /// dimension. Distance g = u₀·(half − least), length least + u₁·(half − g − least).
    pub fn decode(&self, u: &[f64]) -> Banded {
        let (m, half, least) = (self.per_band(), 0.5 * self.stroke_mm, self.min_len_mm);
        let bands = [DeadCentre::Top, DeadCentre::Bottom]
            .into_iter()
            .enumerate()
            .map(|(k, at)| {
                let v = &u[k * m..(k + 1) * m];
                let g = v[0].clamp(0.0, 1.0) * (half - least);
                let len = least + v[1].clamp(0.0, 1.0) * (half - g - least);
                let (start_mm, end_mm) = match at {
                    DeadCentre::Top => (g, g + len),
                    DeadCentre::Bottom => (self.stroke_mm - g - len, self.stroke_mm - g),
                };
                Band {
                    at,
                    start_mm,
                    end_mm,
                    texture: self.texture.decode(&v[PLACE..]),
                }
            })
            .collect();
        Banded { bands }
    }

    /// The cube point of the least bands at both dead centres, each with the texture at the
    /// middle of the design space's cube.
    pub fn at_dead_centres(&self) -> Vec<f64> {
        let m = self.per_band();
        (0..self.dim())
            .map(|k| if k % m < PLACE { 0.0 } else { 0.5 })
            .collect()
    }

    /// The cube point of a liner of this space: `decode(encode(b)) ≈ b`.
    pub fn encode(&self, b: &Banded) -> Vec<f64> {
        let (half, least) = (0.5 * self.stroke_mm, self.min_len_mm);
        let mut u = Vec::with_capacity(self.dim());
        for band in &b.bands {
            let g = match band.at {
                DeadCentre::Top => band.start_mm,
                DeadCentre::Bottom => self.stroke_mm - band.end_mm,
            };
            let len = band.end_mm - band.start_mm;
            let ratio = |a: f64, b: f64| {
                if b > 0.0 {
                    (a / b).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            };
            u.push(ratio(g, half - least));
            u.push(ratio(len - least, half - g - least));
            u.extend(self.texture.encode(&band.texture));
        }
        u
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn space() -> BandSpace {
        BandSpace::new(
            Space {
                bounds: Default::default(),
                cons: Default::default(),
            },
            80.0,
            4.0,
        )
        .unwrap()
    }

    #[test]
    fn the_cube_maps_onto_bands_in_their_halves_at_least_the_least_length() {
        let s = space();
        let mut u = vec![0.0; s.dim()];
        // Top band: at its dead centre, least length; bottom band: 10 mm off it, longest.
        let m = s.dim() / 2;
        u[m] = 10.0 / 36.0;
        u[m + 1] = 1.0;
        let b = s.decode(&u);
        assert_eq!((b.bands[0].start_mm, b.bands[0].end_mm), (0.0, 4.0));
        let (a, e) = (b.bands[1].start_mm, b.bands[1].end_mm);
        assert!(
            (a - 40.0).abs() < 1e-12 && (e - 70.0).abs() < 1e-12,
            "{a} {e}"
        );
        for v in [0.0, 0.3, 1.0] {
            let b = s.decode(&vec![v; s.dim()]);
            let (t, bt) = (&b.bands[0], &b.bands[1]);
            assert!(t.end_mm - t.start_mm >= 4.0 - 1e-12 && t.end_mm <= 40.0 + 1e-12);
            assert!(bt.end_mm - bt.start_mm >= 4.0 - 1e-12 && bt.start_mm >= 40.0 - 1e-12);
            let back = s.decode(&s.encode(&b));
            assert!((back.bands[1].start_mm - bt.start_mm).abs() < 1e-9);
            assert!((back.bands[0].end_mm - t.end_mm).abs() < 1e-9);
        }
    }

    #[test]
    fn the_start_at_the_dead_centres_is_the_least_bands_there() {
        let s = space();
        let b = s.decode(&s.at_dead_centres());
        assert_eq!((b.bands[0].start_mm, b.bands[0].end_mm), (0.0, 4.0));
        assert_eq!((b.bands[1].start_mm, b.bands[1].end_mm), (76.0, 80.0));
    }

    #[test]
    fn a_least_length_beyond_half_the_stroke_is_refused() {
        let e = BandSpace::new(
            Space {
                bounds: Default::default(),
                cons: Default::default(),
            },
            80.0,
            41.0,
        )
        .unwrap_err();
        assert!(e.to_string().contains("41"), "{e}");
        assert!(BandSpace::new(
            Space {
                bounds: Default::default(),
                cons: Default::default()
            },
            80.0,
            0.0
        )
        .is_err());
    }

    #[test]
    fn a_banded_liner_is_plain_between_its_bands() {
        let s = space();
        let b = s.decode(&vec![0.0; s.dim()]);
        let l = b.layout(80.0);
        let want = [0.0, 0.4, 7.6, 8.0];
        assert_eq!(l.bounds_cm().len(), 4);
        for (b, w) in l.bounds_cm().iter().zip(want) {
            assert!((b - w).abs() < 1e-12, "{:?}", l.bounds_cm());
        }
        assert_eq!(l.textures()[1], None);
        assert!(l.textures()[0].is_some() && l.textures()[2].is_some());
    }
}
