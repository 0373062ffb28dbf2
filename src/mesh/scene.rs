//! The discretised contact: mesh, gap and texture depth at a given time (docs/model.md §2–3).

use super::{sample_across, Gap, Grid, RimModel, Rows};
use crate::model::case::CaseSpec;
use crate::model::flow_factors::FlowFactors;
use crate::model::geometry::Contact;

/// Mesh plus the fields the geometry imposes on it.
#[derive(Debug)]
pub struct Scene {
    pub contact: Contact,
    pub grid: Grid,
    /// h = gap.base (+ Z under the ring), at the time of the last `place`.
    pub gap: Gap,
    /// Texture depth h_L per node (µm), at the time of the last `place`.
    pub hl: Vec<f64>,
    /// Liner speed u.
    pub u: f64,
    /// How the film sees the gap across a cell ([`Rows`]).
    pub rim: RimModel,
}

impl Scene {
    /// The 2D half-cell scene of a case: n1 × n2 over the contact's domain along x1 (0.2 cm
    /// for the paper's ring) × [0, width/2]; an untextured liner has no x2 structure, so its
    /// width is nominal (1 cm).
    pub fn new(case: &CaseSpec, n1: usize, n2: usize) -> Self {
        let contact = case.contact();
        let width = case.texture.as_ref().map_or(1.0, |t| 0.5 * t.width);
        let length = contact.length_cm;
        Self::with_grid(contact, Grid::new(n1, n2, length, width), case.u, case.flow)
    }

    /// The scene of `contact` on `grid`, the liner at speed `u`, its film's flow factors
    /// `flow` (None: smooth surfaces).
    pub fn with_grid(contact: Contact, grid: Grid, u: f64, flow: Option<FlowFactors>) -> Self {
        let ring = (0..=grid.n1)
            .map(|i| contact.under_ring(grid.x(i)))
            .collect();
        let n = grid.nodes();
        let mut s = Scene {
            contact,
            grid,
            gap: Gap {
                base: vec![0.0; n],
                ring,
                flow,
                rows: Rows::nodal(),
                fitted: None,
                fitted_x2: None,
            },
            hl: vec![0.0; n],
            u,
            rim: RimModel::Nodal,
        };
        s.place(0.0);
        s
    }

    /// This scene with the gap across its cells seen as `rim` sees it, the texture placed
    /// again at t = 0.
    pub fn with_rim(mut self, rim: RimModel) -> Self {
        if rim != self.rim {
            self.rim = rim;
            self.place(0.0);
        }
        self
    }

    /// Moves the texture to time t: h_L(x1 − u·t, x2) and the gap without Z, h_L plus the
    /// ring's part (`Contact::ring_part_um`, eq. 15).
    pub fn place(&mut self, t: f64) {
        let g = &self.grid;
        let liner = &self.contact.liner;
        let rim = match liner.pocket {
            Some(_) => self.rim,
            None => RimModel::Nodal,
        };
        self.gap.rows.reset(g.nodes(), rim);
        let ns = rim.samples();
        let mut depths = Vec::with_capacity(ns);
        for i in 0..=g.n1 {
            let x = g.x(i);
            let ring_part = self.contact.ring_part_um(x);
            let xl = x - self.u * t;
            for j in 0..g.n2 {
                let k = g.idx(i, j);
                let hl = if ns > 1 {
                    sample_across(g.y(j), g.dy, ns, |y| liner.depth_um(xl, y), &mut depths);
                    self.gap.rows.set(k, &depths)
                } else {
                    liner.depth_um(xl, g.y(j))
                };
                self.hl[k] = hl;
                self.gap.base[k] = hl + ring_part;
            }
        }
    }
}

/// Field by field; `clone_from` keeps the arrays' allocations (a cycle run saves its scene
/// before every crank step it may take again in halves).
impl Clone for Scene {
    fn clone(&self) -> Self {
        Scene {
            contact: self.contact.clone(),
            grid: self.grid.clone(),
            gap: self.gap.clone(),
            hl: self.hl.clone(),
            u: self.u,
            rim: self.rim,
        }
    }

    fn clone_from(&mut self, s: &Self) {
        self.contact = s.contact.clone();
        self.grid = s.grid.clone();
        self.gap.clone_from(&s.gap);
        self.hl.clone_from(&s.hl);
        self.u = s.u;
        self.rim = s.rim;
    }
}
