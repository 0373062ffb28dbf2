//! Faces fitted to the gap between their nodes (docs/solver.md, "Deep pockets"): where a
//! face is given the gap at `m` points between its two nodes on each of `ns` strips across
//! it, the film's one-dimensional flux between the nodes is taken exactly on each strip
//! (docs/model.md §3 integrated along the strip at a constant flux): the strip's conductance
//! 1/mean(h⁻³), an x1 face's full film Couette content mean(h⁻²)/mean(h⁻³), and the strips
//! in parallel. A face without samples keeps the face of [`super::face_conductances`].

/// A face without samples.
const UNFITTED: u32 = u32::MAX;

/// The gap's samples along the fitted faces (x1 or x2), and whether each takes Z (under the
/// ring).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FittedFaces {
    /// Points along a face per strip.
    m: usize,
    /// Strips across a face.
    ns: usize,
    /// Per face (the index of its conductance, [`crate::model::film::Faces::cx`] or `cy`):
    /// the first of its samples, or [`UNFITTED`].
    at: Vec<u32>,
    /// Gap without Z (µm), strip after strip, `ns·m` a face.
    base: Vec<f64>,
    /// Whether each sample lies under the ring (its gap is base + Z).
    under: Vec<bool>,
}

/// A fitted face at one Z, per unit of its geometry factor (dy/dx or dx/dy).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FaceFit {
    /// The strips' mean of 1/mean(h⁻³).
    pub conductance: f64,
    /// The strips' mean of mean(h⁻²)/mean(h⁻³) (µm): the gap a full film's Couette flux
    /// carries through the face.
    pub content: f64,
    /// d(conductance)/dZ.
    pub slope: f64,
}

impl FittedFaces {
    /// No face fitted yet, of `faces` faces with `ns` strips of `m` points each.
    pub fn new(faces: usize, ns: usize, m: usize) -> Self {
        FittedFaces {
            m,
            ns,
            at: vec![UNFITTED; faces],
            base: Vec::new(),
            under: Vec::new(),
        }
    }

    /// Samples per face.
    pub fn samples(&self) -> usize {
        self.ns * self.m
    }

    /// Fits `face` to `base` and `under` (`ns·m` each, strip after strip).
    pub fn set(&mut self, face: usize, base: &[f64], under: &[bool]) {
        debug_assert_eq!(base.len(), self.samples());
        self.at[face] = self.base.len() as u32;
        self.base.extend_from_slice(base);
        self.under.extend_from_slice(under);
    }

    /// Whether any face is fitted.
    pub fn any(&self) -> bool {
        !self.base.is_empty()
    }

    /// A fitted face's samples: the gap without Z and whether each takes Z, strip after
    /// strip (None: the face is nodal).
    pub fn samples_of(&self, face: usize) -> Option<(&[f64], &[bool])> {
        let a = *self.at.get(face)?;
        (a != UNFITTED).then(|| {
            let span = a as usize..a as usize + self.samples();
            (&self.base[span.clone()], &self.under[span])
        })
    }

    /// Strips across a face, points along a strip.
    pub fn shape(&self) -> (usize, usize) {
        (self.ns, self.m)
    }

    /// The fitted face at ring position `z` (None: the face is nodal).
    #[inline]
    pub fn face(&self, face: usize, z: f64) -> Option<FaceFit> {
        let a = *self.at.get(face)?;
        if a == UNFITTED {
            return None;
        }
        let n = self.samples();
        let (base, under) = (
            &self.base[a as usize..][..n],
            &self.under[a as usize..][..n],
        );
        let (mut c, mut content, mut slope) = (0.0, 0.0, 0.0);
        for (b, u) in base.chunks_exact(self.m).zip(under.chunks_exact(self.m)) {
            let (mut s2, mut s3, mut s4) = (0.0, 0.0, 0.0);
            for (&b, &u) in b.iter().zip(u) {
                let h = if u { b + z } else { b };
                let r = 1.0 / h;
                let r2 = r * r;
                s2 += r2;
                s3 += r2 * r;
                if u {
                    s4 += r2 * r2;
                }
            }
            // Means over the m points: the 1/m factors cancel in the ratios but not here.
            let m = self.m as f64;
            c += m / s3;
            content += s2 / s3;
            slope += 3.0 * m * s4 / (s3 * s3);
        }
        let ns = self.ns as f64;
        Some(FaceFit {
            conductance: c / ns,
            content: content / ns,
            slope: slope / ns,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn a_uniform_face_is_the_nodal_one_and_a_step_its_series() {
        let mut f = FittedFaces::new(3, 1, 4);
        f.set(1, &[2.0; 4], &[true; 4]);
        f.set(2, &[1.0, 1.0, 3.0, 3.0], &[false; 4]);
        assert_eq!(f.face(0, 0.5), None);
        let u = f.face(1, 0.5).unwrap();
        assert!((u.conductance - 2.5f64.powi(3)).abs() < 1e-12);
        assert!((u.content - 2.5).abs() < 1e-12);
        assert!((u.slope - 3.0 * 2.5f64.powi(2)).abs() < 1e-12);
        // Half the face at h = 1, half at 3: the two resistances in series.
        let s = f.face(2, 7.0).unwrap();
        let r3 = 0.5 * (1.0 + 1.0 / 27.0);
        assert!((s.conductance - 1.0 / r3).abs() < 1e-12);
        assert!((s.content - 0.5 * (1.0 + 1.0 / 9.0) / r3).abs() < 1e-12);
        assert_eq!(s.slope, 0.0);
    }

    #[test]
    fn the_slope_is_the_conductance_derivative_in_z() {
        let mut f = FittedFaces::new(1, 2, 3);
        let base = [1.0, 4.0, 9.0, 2.0, 2.5, 0.7];
        f.set(0, &base, &[true, true, false, true, false, true]);
        let (z, dz) = (0.4, 1e-6);
        let d = (f.face(0, z + dz).unwrap().conductance - f.face(0, z - dz).unwrap().conductance)
            / (2.0 * dz);
        assert!(
            (f.face(0, z).unwrap().slope - d).abs() < 1e-6 * d.abs(),
            "{d}"
        );
    }
}
