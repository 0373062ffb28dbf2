//! The product's one stencil ([`texopt::model::film::Column`]) node by node, as the lab's
//! node-wise smoothers read it.

use texopt::mesh::Grid;
use texopt::model::film::{Column, Faces};

/// The stencil at interior node (i, j) ([`Column::balance`]).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
pub fn balance(
    g: &Grid,
    f: &Faces,
    adv: f64,
    at: f64,
    p: &[f64],
    phi: &[f64],
    phi_old: Option<&[f64]>,
    i: usize,
    j: usize,
) -> f64 {
    Column::new(g.n2, f, p, phi, phi_old, i).balance(adv, at, j)
}

/// Sum of the four face conductances of node (i, j): ∂(balance)/∂p_ij.
#[inline]
pub fn conductance_sum(g: &Grid, f: &Faces, i: usize, j: usize) -> f64 {
    let (n2, k) = (g.n2, i * g.n2 + j);
    let mut c = f.cx[k - n2] + f.cx[k];
    if j > 0 {
        c += f.cy[i * (n2 - 1) + j - 1];
    }
    if j + 1 < n2 {
        c += f.cy[i * (n2 - 1) + j];
    }
    c
}
