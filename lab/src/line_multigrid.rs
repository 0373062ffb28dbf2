//! Line multigrid for the film matrix of a fixed active set.
//!
//! The film matrix couples each node to its four neighbours (a 5-point pattern, [`Stencil5`]),
//! whatever the unknown of the node is (p on the pressurised set, φ on the cavitated set).
//! Along x1 a line of nodes is a tridiagonal system; across x2 the lines couple only through
//! their neighbours. Anisotropy goes either way in this product (x1 dominates for wide texture
//! cells, x2 for narrow ones), and the gap jumps by orders of magnitude along x1 (ring film
//! against the gap e). The classic robust pair for that is used here: zebra line relaxation
//! along x1 (each line solved exactly, so every jump and any x1 anisotropy is handled) and
//! semicoarsening across x2 (pairs of lines aggregated, Galerkin coarse operators), down to a
//! single line, which is solved exactly (Dendy; Trottenberg, Oosterlee & Schüller §5.1).
//!
//! The hierarchy is rebuilt for every matrix (cost about one relaxation sweep); a V-cycle costs
//! about four fine relaxation sweeps.

use texopt::solve::Stencil5;

/// The Galerkin coarse operator of line pairs (see [`coarsen`]).
trait Coarsen {
    fn coarsen(&self, active: &[bool], coarse: &mut Stencil5, coarse_active: &mut Vec<bool>);
}

impl Coarsen for Stencil5 {
    /// The Galerkin operator Pᵀ A P for P the aggregation of line pairs (2J, 2J+1) (a last odd
    /// line stays alone), restricted to the `active` unknowns: the coarse space corrects
    /// only those (in the film, the pressures; the film contents φ of cavitated nodes follow
    /// from them by upwind transport, which the line relaxation solves exactly). An aggregate
    /// without active unknowns gets an identity row. Returns the coarse activity.
    fn coarsen(&self, active: &[bool], coarse: &mut Stencil5, coarse_active: &mut Vec<bool>) {
        let (m1, n2) = (self.m1, self.n2);
        let nc = n2.div_ceil(2);
        coarse.reset(m1, nc);
        coarse_active.clear();
        coarse_active.resize(m1 * nc, false);
        let act = |k: usize| active[k];
        for i in 0..m1 {
            for jc in 0..nc {
                let k0 = i * n2 + 2 * jc;
                let kc = i * nc + jc;
                let members: &[usize] = if 2 * jc + 1 < n2 {
                    &[k0, k0 + 1]
                } else {
                    &[k0]
                };
                let (mut c, mut w, mut e, mut s, mut n) = (0.0, 0.0, 0.0, 0.0, 0.0);
                let mut any = false;
                for &k in members.iter().filter(|&&k| act(k)) {
                    any = true;
                    c += self.c[k];
                    if i > 0 && act(k - n2) {
                        w += self.w[k];
                    }
                    if i + 1 < m1 && act(k + n2) {
                        e += self.e[k];
                    }
                    let j = k % n2;
                    // x2 couplings inside the aggregate add to the diagonal, outside it they
                    // couple to the neighbouring aggregate.
                    if j > 0 && act(k - 1) {
                        if k > k0 {
                            c += self.s[k];
                        } else {
                            s += self.s[k];
                        }
                    }
                    if j + 1 < n2 && act(k + 1) {
                        if members.contains(&(k + 1)) {
                            c += self.n[k];
                        } else {
                            n += self.n[k];
                        }
                    }
                }
                if !any {
                    coarse.c[kc] = 1.0;
                    continue;
                }
                coarse_active[kc] = true;
                // Piecewise-constant aggregation makes the coarse x2 couplings twice those of
                // a rediscretisation on the doubled spacing, which halves the correction of
                // smooth modes (V-cycle factor ≈ 0.57 on the Laplacian). Where the row is a
                // diffusion row (diagonally dominant), use the rediscretised strength instead.
                let off = w.abs() + e.abs() + s.abs() + n.abs();
                if c >= off && s <= 0.0 && n <= 0.0 {
                    c += 0.5 * (s + n);
                    s *= 0.5;
                    n *= 0.5;
                }
                coarse.c[kc] = c;
                coarse.w[kc] = w;
                coarse.e[kc] = e;
                coarse.s[kc] = s;
                coarse.n[kc] = n;
            }
        }
    }
}

/// One level: its operator, the Thomas factors of its x1 lines, and work vectors.
#[derive(Clone, Debug, Default)]
struct Level {
    a: Stencil5,
    /// Unknowns the coarse space corrects.
    active: Vec<bool>,
    /// 1/(pivot) of the line elimination at each node.
    inv: Vec<f64>,
    /// Upper multiplier e_k/pivot_k of the line elimination.
    up: Vec<f64>,
    x: Vec<f64>,
    b: Vec<f64>,
    r: Vec<f64>,
    d: Vec<f64>,
}

/// A zero or non-finite pivot in a line elimination: the matrix is singular.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SingularLine {
    pub node: usize,
    pub value: f64,
}

impl Level {
    /// Thomas factors of every x1 line (no pivoting: lines of an M-matrix are M-matrices).
    fn factor_lines(&mut self) -> Result<(), SingularLine> {
        let a = &self.a;
        let (m1, n2) = (a.m1, a.n2);
        self.inv.clear();
        self.inv.resize(m1 * n2, 0.0);
        self.up.clear();
        self.up.resize(m1 * n2, 0.0);
        for k in 0..m1 * n2 {
            let piv = if k >= n2 {
                a.c[k] - a.w[k] * self.up[k - n2]
            } else {
                a.c[k]
            };
            if !(piv.is_finite() && piv != 0.0) {
                return Err(SingularLine {
                    node: k,
                    value: piv,
                });
            }
            self.inv[k] = 1.0 / piv;
            self.up[k] = a.e[k] * self.inv[k];
        }
        Ok(())
    }

    /// One zebra line Gauss–Seidel sweep on x (even lines, then odd ones; reversed order when
    /// `backward`, so a pre/post pair is symmetric).
    fn relax(&mut self, backward: bool) {
        let (m1, n2) = (self.a.m1, self.a.n2);
        let colours: [usize; 2] = if backward { [1, 0] } else { [0, 1] };
        for colour in colours {
            if colour >= n2 {
                continue;
            }
            let a = &self.a;
            // Forward elimination, all lines of this colour at once (inner loop over j).
            for i in 0..m1 {
                let row = i * n2;
                for j in (colour..n2).step_by(2) {
                    let k = row + j;
                    let mut rhs = self.b[k];
                    if j > 0 {
                        rhs -= a.s[k] * self.x[k - 1];
                    }
                    if j + 1 < n2 {
                        rhs -= a.n[k] * self.x[k + 1];
                    }
                    if i > 0 {
                        rhs -= a.w[k] * self.d[k - n2];
                    }
                    self.d[k] = rhs * self.inv[k];
                }
            }
            // Back substitution.
            for i in (0..m1).rev() {
                let row = i * n2;
                for j in (colour..n2).step_by(2) {
                    let k = row + j;
                    self.x[k] = if i + 1 < m1 {
                        self.d[k] - self.up[k] * self.x[k + n2]
                    } else {
                        self.d[k]
                    };
                }
            }
        }
    }
}

/// The multigrid hierarchy of one matrix.
#[derive(Clone, Debug, Default)]
pub struct LineMultigrid {
    levels: Vec<Level>,
    /// Number of levels in use (the vector keeps allocations of deeper ones).
    depth: usize,
}

impl LineMultigrid {
    /// The fine operator, to be assembled by the caller and then passed to [`Self::setup`].
    pub fn fine_mut(&mut self) -> &mut Stencil5 {
        if self.levels.is_empty() {
            self.levels.push(Level::default());
        }
        &mut self.levels[0].a
    }

    pub fn fine(&self) -> &Stencil5 {
        &self.levels[0].a
    }

    /// Which fine unknowns the coarse levels correct (default: all); length = fine size.
    pub fn fine_active_mut(&mut self) -> &mut Vec<bool> {
        if self.levels.is_empty() {
            self.levels.push(Level::default());
        }
        &mut self.levels[0].active
    }

    /// Builds the coarse levels and line factors for the operator in [`Self::fine_mut`].
    pub fn setup(&mut self) -> Result<(), SingularLine> {
        let mut l = 0;
        loop {
            let len = self.levels[l].a.len();
            let lv = &mut self.levels[l];
            for v in [&mut lv.x, &mut lv.b, &mut lv.r, &mut lv.d] {
                v.clear();
                v.resize(len, 0.0);
            }
            lv.factor_lines()?;
            if self.levels[l].a.n2 == 1 {
                break;
            }
            if self.levels.len() == l + 1 {
                self.levels.push(Level::default());
            }
            let (fine, coarse) = self.levels.split_at_mut(l + 1);
            let (f, c) = (&mut fine[l], &mut coarse[0]);
            if f.active.len() != f.a.len() {
                f.active.clear();
                f.active.resize(f.a.len(), true);
            }
            f.a.coarsen(&f.active, &mut c.a, &mut c.active);
            l += 1;
        }
        self.depth = l + 1;
        Ok(())
    }

    /// One V(1,1)-cycle on A x = b, improving x in place. Returns nothing: callers measure
    /// the residual they care about.
    pub fn vcycle(&mut self, x: &mut [f64], b: &[f64]) {
        let lv = &mut self.levels[0];
        lv.x.copy_from_slice(x);
        lv.b.copy_from_slice(b);
        self.cycle(0);
        x.copy_from_slice(&self.levels[0].x);
    }

    /// Right-preconditioned restarted GMRES on A x = b with one V-cycle as the
    /// preconditioner: the V-cycle alone leaves a few slow modes (the flooded gap e, whose
    /// conductances exceed the ring film's by 10⁷), which a short Krylov space removes.
    /// Stops when ‖b − A x‖₂ ≤ rel·‖b − A x₀‖₂ or after `max_it` V-cycles. Returns the V-cycles
    /// used.
    pub fn gmres(&mut self, x: &mut [f64], b: &[f64], rel: f64, max_it: usize) -> usize {
        const M: usize = 8;
        let n = b.len();
        let dot = |a: &[f64], c: &[f64]| a.iter().zip(c).map(|(u, v)| u * v).sum::<f64>();
        let mut r = vec![0.0; n];
        self.levels[0].a.residual(x, b, &mut r);
        let mut r0 = dot(&r, &r).sqrt();
        let b0 = dot(b, b).sqrt();
        if r0 > b0 {
            // The guess is worse than none.
            x.iter_mut().for_each(|v| *v = 0.0);
            r.copy_from_slice(b);
            r0 = b0;
        }
        let mut used = 0;
        let mut beta = r0;
        while used < max_it && beta > rel * r0 && beta > 0.0 {
            let mut v: Vec<Vec<f64>> = vec![r.iter().map(|a| a / beta).collect()];
            let mut zs: Vec<Vec<f64>> = Vec::new();
            let mut h = [[0.0f64; M]; M + 1];
            let (mut cs, mut sn) = ([0.0f64; M], [0.0f64; M]);
            let mut gvec = [0.0f64; M + 1];
            gvec[0] = beta;
            let mut k = 0;
            while k < M && used < max_it {
                // z = M⁻¹ v_k (one V-cycle from zero), w = A z.
                let mut z = vec![0.0; n];
                {
                    let lv = &mut self.levels[0];
                    lv.x.iter_mut().for_each(|a| *a = 0.0);
                    lv.b.copy_from_slice(&v[k]);
                }
                self.cycle(0);
                z.copy_from_slice(&self.levels[0].x);
                used += 1;
                let mut w = vec![0.0; n];
                self.levels[0].a.apply(&z, &mut w);
                for (i, vi) in v.iter().enumerate() {
                    h[i][k] = dot(&w, vi);
                    for (wq, vq) in w.iter_mut().zip(vi) {
                        *wq -= h[i][k] * vq;
                    }
                }
                h[k + 1][k] = dot(&w, &w).sqrt();
                for i in 0..k {
                    let t = cs[i] * h[i][k] + sn[i] * h[i + 1][k];
                    h[i + 1][k] = -sn[i] * h[i][k] + cs[i] * h[i + 1][k];
                    h[i][k] = t;
                }
                let d = (h[k][k] * h[k][k] + h[k + 1][k] * h[k + 1][k]).sqrt();
                if d == 0.0 {
                    zs.push(z);
                    k += 1;
                    break;
                }
                cs[k] = h[k][k] / d;
                sn[k] = h[k + 1][k] / d;
                h[k][k] = d;
                h[k + 1][k] = 0.0;
                gvec[k + 1] = -sn[k] * gvec[k];
                gvec[k] *= cs[k];
                let norm_w = dot(&w, &w).sqrt();
                zs.push(z);
                k += 1;
                if gvec[k].abs() <= rel * r0 || norm_w == 0.0 {
                    break;
                }
                v.push(w.iter().map(|a| a / norm_w).collect());
            }
            // Back substitution for the Krylov coefficients, then x += Σ y_i z_i.
            let mut y = [0.0f64; M];
            for i in (0..k).rev() {
                let mut t = gvec[i];
                for j in i + 1..k {
                    t -= h[i][j] * y[j];
                }
                y[i] = t / h[i][i];
            }
            for (yi, zi) in y.iter().zip(&zs).take(k) {
                for (xq, zq) in x.iter_mut().zip(zi) {
                    *xq += yi * zq;
                }
            }
            self.levels[0].a.residual(x, b, &mut r);
            beta = dot(&r, &r).sqrt();
        }
        used
    }

    fn cycle(&mut self, l: usize) {
        if l + 1 == self.depth {
            // A single line: one relaxation is the exact solve.
            self.levels[l].relax(false);
            return;
        }
        {
            let lv = &mut self.levels[l];
            lv.relax(false);
            lv.a.residual(&lv.x, &lv.b, &mut lv.r);
        }
        let (fine, coarse) = self.levels.split_at_mut(l + 1);
        let (f, c) = (&fine[l], &mut coarse[0]);
        let (m1, n2, nc) = (f.a.m1, f.a.n2, c.a.n2);
        // Restriction: sum over the aggregate (Pᵀ).
        for i in 0..m1 {
            for jc in 0..nc {
                let k0 = i * n2 + 2 * jc;
                let mut v = if f.active[k0] { f.r[k0] } else { 0.0 };
                if 2 * jc + 1 < n2 && f.active[k0 + 1] {
                    v += f.r[k0 + 1];
                }
                c.b[i * nc + jc] = v;
            }
        }
        c.x.iter_mut().for_each(|v| *v = 0.0);
        self.cycle(l + 1);
        let (fine, coarse) = self.levels.split_at_mut(l + 1);
        let (f, c) = (&mut fine[l], &coarse[0]);
        // Prolongation: the aggregate's correction to each of its lines (P).
        for i in 0..m1 {
            for jc in 0..nc {
                let k0 = i * n2 + 2 * jc;
                let v = c.x[i * nc + jc];
                if f.active[k0] {
                    f.x[k0] += v;
                }
                if 2 * jc + 1 < n2 && f.active[k0 + 1] {
                    f.x[k0 + 1] += v;
                }
            }
        }
        f.relax(true);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Variable-coefficient anisotropic diffusion with a jump, plus a diagonal shift.
    fn problem(m1: usize, n2: usize, ax: f64, ay: f64) -> Stencil5 {
        let mut a = Stencil5::default();
        a.reset(m1, n2);
        for i in 0..m1 {
            for j in 0..n2 {
                let k = i * n2 + j;
                let kx = if i < m1 / 3 { 1e6 } else { 1.0 } * ax;
                let mut diag = 2.0 * kx + 1e-3;
                a.w[k] = if i > 0 { -kx } else { 0.0 };
                a.e[k] = if i + 1 < m1 { -kx } else { 0.0 };
                if j > 0 {
                    a.s[k] = -ay;
                    diag += ay;
                }
                if j + 1 < n2 {
                    a.n[k] = -ay;
                    diag += ay;
                }
                a.c[k] = diag;
            }
        }
        a
    }

    fn rate(ax: f64, ay: f64) -> f64 {
        let (m1, n2) = (200, 32);
        let mut mg = LineMultigrid::default();
        *mg.fine_mut() = problem(m1, n2, ax, ay);
        mg.setup().unwrap();
        let b: Vec<f64> = (0..m1 * n2)
            .map(|k| ((k * 7919) % 101) as f64 - 50.0)
            .collect();
        let mut x = vec![0.0; m1 * n2];
        let mut r = vec![0.0; m1 * n2];
        let norm = |r: &[f64]| r.iter().map(|v| v * v).sum::<f64>().sqrt();
        let r0 = norm(&b);
        for _ in 0..10 {
            mg.vcycle(&mut x, &b);
        }
        mg.fine().residual(&x, &b, &mut r);
        (norm(&r) / r0).powf(0.1)
    }

    #[test]
    fn v_cycles_converge_fast_for_either_anisotropy() {
        for (ax, ay) in [(1.0, 1.0), (10.0, 1.0), (1.0, 30.0), (1.0, 0.01)] {
            let q = rate(ax, ay);
            assert!(q < 0.35, "convergence factor {q} for ax = {ax}, ay = {ay}");
        }
    }
}
