//! The mesh (docs/model.md §3): vertex-centred along the sliding direction x1, cell-centred
//! across it (x2), over the domain and half a texture cell.

/// The mesh: n1 cells along x1 over [0, length] (vertex-centred, n1 + 1 nodes) and n2 cells
/// along x2 over [0, half_width] (cell-centred). Node (i, j) is stored at i·n2 + j.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    pub n1: usize,
    pub n2: usize,
    /// Domain length along x1 (cm).
    pub length: f64,
    /// Simulated width B along x2 (cm): half a texture cell (docs/model.md §2).
    pub width: f64,
    pub dx: f64,
    pub dy: f64,
}

impl Grid {
    pub fn new(n1: usize, n2: usize, length: f64, width: f64) -> Self {
        Grid {
            n1,
            n2,
            length,
            width,
            dx: length / n1 as f64,
            dy: width / n2 as f64,
        }
    }
    /// Number of nodes, boundary nodes included.
    pub fn nodes(&self) -> usize {
        (self.n1 + 1) * self.n2
    }
    #[inline]
    pub fn idx(&self, i: usize, j: usize) -> usize {
        i * self.n2 + j
    }
    /// x1 of node column i (cm).
    pub fn x(&self, i: usize) -> f64 {
        i as f64 * self.dx
    }
    /// x2 of node row j (cm).
    pub fn y(&self, j: usize) -> f64 {
        (j as f64 + 0.5) * self.dy
    }

    /// The neighbours of node k among the interior columns 1..n1 − 1 (x1 − 1, x1 + 1, x2 − 1,
    /// x2 + 1, in that order): where a cavity can spread or a film meet one.
    #[inline]
    pub fn interior_neighbours(&self, k: usize) -> impl Iterator<Item = usize> {
        let (n1, n2) = (self.n1, self.n2);
        let (i, j) = (k / n2, k % n2);
        [
            (i > 1).then(|| k - n2),
            (i + 1 < n1).then(|| k + n2),
            (j > 0).then(|| k - 1),
            (j + 1 < n2).then(|| k + 1),
        ]
        .into_iter()
        .flatten()
    }
}
