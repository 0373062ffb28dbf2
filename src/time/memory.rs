//! What a transient keeps from one texture period to the next: the texture placed at each
//! phase, the solved states and factors of the period (the next period's initial guesses),
//! and how a step's guess from the previous state follows the texture.

use crate::mesh::{FilmState, Grid, Rows, Scene};
use crate::model::case::CaseSpec;
use crate::solve::{FilmMethod, KeptFactors};

/// The texture depth, the gap without Z and its rows ([`Rows`]) at each phase of the texture
/// period, as [`Scene::place`] set them at that phase the first time (the same bits every
/// period, since the texture is placed by its phase). Why: placing evaluates the pocket shape at every
/// node, ≈ 3.5 % of a `fast` run, for fields that repeat every period.
#[derive(Clone, Default)]
pub(super) struct PlacedTexture {
    /// Slot k: h_L, the gap base and its rows at phase k·dt; empty when disabled. The slot
    /// lent to the scene holds the scene's spare arrays meanwhile.
    pub(super) slots: Vec<Option<Placed>>,
    /// The slot whose arrays the scene holds (exchanged, not copied: at 512×32 a copy is
    /// 260 kB a step).
    lent: Option<usize>,
}

/// Most memory the placed texture of a period may take (bytes): 512×32 with 150 steps a
/// period needs ≈ 40 MB; longer periods or finer meshes place the texture every step.
pub(crate) const PLACED_TEXTURE_MEMORY: usize = 128 << 20;

/// One phase's placed texture: h_L, the gap base and its rows.
pub(super) type Placed = (Vec<f64>, Vec<f64>, Rows);

impl PlacedTexture {
    /// `row_samples`: the scene's samples across a cell ([`Scene::rim`]), which may
    /// each be kept.
    pub(super) fn new(
        textured: bool,
        steps_per_period: usize,
        nodes: usize,
        row_samples: usize,
    ) -> Self {
        let per_node = 2 + if row_samples > 1 { row_samples + 1 } else { 0 };
        let bytes = steps_per_period * nodes * per_node * std::mem::size_of::<f64>();
        let on = textured && steps_per_period > 1 && bytes <= PLACED_TEXTURE_MEMORY;
        PlacedTexture {
            slots: if on {
                vec![None; steps_per_period]
            } else {
                Vec::new()
            },
            lent: None,
        }
    }

    /// Places the texture of `scene` at phase `phase` (slot `slot` of the period).
    pub(super) fn place(&mut self, scene: &mut Scene, slot: usize, phase: f64) {
        let exchange = |(hl, base, rows): &mut Placed, scene: &mut Scene| {
            std::mem::swap(hl, &mut scene.hl);
            std::mem::swap(base, &mut scene.gap.base);
            std::mem::swap(rows, &mut scene.gap.rows);
        };
        // The arrays the scene holds go back to their slot, the scene's own come back.
        if let Some(Some(pair)) = self.lent.take().and_then(|j| self.slots.get_mut(j)) {
            exchange(pair, scene);
        }
        match self.slots.get_mut(slot) {
            Some(Some(pair)) => {
                exchange(pair, scene);
                self.lent = Some(slot);
            }
            Some(empty) => {
                scene.place(phase);
                *empty = Some((
                    scene.hl.clone(),
                    scene.gap.base.clone(),
                    scene.gap.rows.clone(),
                ));
            }
            None => scene.place(phase),
        }
    }
}

/// Initial guesses for the film iteration from one texture period earlier.
///
/// Why: the texture moves one or two cells per step (the ring-frame schemes, the
/// characteristic step), so the previous time level's active set
/// is wrong along every pocket edge (≈ 20–90 nodes switch in the first Newton iteration of
/// a step), while the state one period earlier has the texture in the same place and
/// differs only by the ring's drift over the period. Near the periodic regime the iteration
/// then needs one solve and one confirming solve per step instead of about four (Case III:
/// 4.9 → 2.0 iterations per step). It is only a starting point: the iteration converges
/// to the same solution (the film problem of a step has one solution), so outcomes change
/// at round-off only.
#[derive(Clone, Default)]
pub(super) struct PeriodGuess {
    /// Slot n mod len: the solved state of time level n and its Z; empty when disabled.
    pub(super) slots: Vec<Option<(FilmState, f64)>>,
    /// Slot n mod len: the film-matrix factors of time level n's last iteration (direct
    /// method), lent to the solve one period later; empty when disabled.
    factors: Vec<Option<KeptFactors>>,
    /// Memory the kept factors take (bytes, as measured when each slot was filled).
    pub(super) factor_bytes: usize,
    /// Slot n mod (len + 1): Z of time level n, one level further back than the states, for
    /// the ring's step of one period ago.
    pub(super) z: Vec<Option<f64>>,
    /// For the last stored level n: how many nodes' active-set flags differ from level
    /// n − period's and from level n − 1's carried with the texture ([`TextureShift`], the
    /// other guess; see [`PeriodGuess::guess`]).
    switched: Option<(usize, usize)>,
}

/// Most memory the kept factors of a period may take (bytes): 512×32 needs ≈ 0.55 GB for
/// per = 0.06 (150 steps of ≈ 3.7 MB: the band in single precision and the stencil it is of),
/// 512×8 ≈ 50 MB (double); beyond it the later steps of a period go without. Why 1.5 GiB:
/// measured with double factors at 512×32, at 1 GiB Case III at `paper` kept factors for only
/// ≈ 90 % of its steps, and the others factored every step of the settled
/// windows (0.11 factorisations a step, 1160 rows eliminated); at 1.5 GiB 0.00–0.02 (0–10
/// rows), and the whole 512×32 stage eliminated 11 % fewer rows. Finer meshes (1024×64:
/// ≈ 37 MB a step) keep what fits.
pub(crate) const PERIOD_FACTORS_MEMORY: usize = 3 << 29;

/// Most memory the period's states may take (bytes); longer periods go without.
pub(crate) const PERIOD_GUESS_MEMORY: usize = 256 << 20;

impl PeriodGuess {
    pub(super) fn new(textured: bool, steps_per_period: usize, nodes: usize) -> Self {
        let bytes = steps_per_period * nodes * (2 * std::mem::size_of::<f64>() + 1);
        let on = textured && steps_per_period > 1 && bytes <= PERIOD_GUESS_MEMORY;
        PeriodGuess {
            slots: if on {
                vec![None; steps_per_period]
            } else {
                Vec::new()
            },
            factors: if on {
                vec![None; steps_per_period]
            } else {
                Vec::new()
            },
            factor_bytes: 0,
            switched: None,
            z: if on {
                vec![None; steps_per_period + 1]
            } else {
                Vec::new()
            },
        }
    }

    /// Lends the solver the factors kept from time level `level − period` (same texture
    /// phase), if any: near the periodic regime they serve the step's first iteration as a
    /// chord step, and their rows the texture alone sets are reused bit for bit.
    pub(super) fn lend_factors(&mut self, level: usize, solver: &mut dyn FilmMethod) {
        let n = self.factors.len();
        if let Some(Some(f)) = level.checked_rem(n).map(|k| &mut self.factors[k]) {
            solver.inherit_factors(f);
        }
    }

    /// Keeps the solver's factors of time level `level` for one period (within
    /// [`PERIOD_FACTORS_MEMORY`]), leaving the solver the slot's old ones.
    pub(super) fn keep_factors(&mut self, level: usize, solver: &mut dyn FilmMethod) {
        if !solver.keeps_factors() {
            return;
        }
        let n = self.factors.len();
        let Some(slot) = level.checked_rem(n).map(|k| &mut self.factors[k]) else {
            return;
        };
        match slot {
            Some(f) => solver.keep_factors(f),
            None if self.factor_bytes <= PERIOD_FACTORS_MEMORY => {
                let mut f = KeptFactors::default();
                solver.keep_factors(&mut f);
                self.factor_bytes += f.bytes();
                *slot = Some(f);
            }
            None => {}
        }
    }

    /// The state of time level `level − period`, if stored and the better guess: when the
    /// active set of the last solved level (`level − 1`) differs from the one a period
    /// before it in no more nodes than from the one a step before it (carried with the
    /// texture, as that guess is: [`TextureShift`]). With it a guess of Z:
    /// the ring's step of one period ago repeated from `z_now`, i.e. the drift over the last
    /// period carried forward by one step (near the periodic regime far closer than the
    /// velocity extrapolation, which lets the direct method settle the step by one chord
    /// solve).
    ///
    /// Why the active sets decide: how many nodes the first Newton iteration must switch is
    /// what a guess costs (about one iteration and one factorisation per sweep of switches),
    /// and the last level's switches over a period and over a step are known for free. The
    /// ring's drift alone (the rule before, |Z_guess − Z_then| ≤ 10·|Z_guess − Z_now|) is
    /// no measure of it: while a creeping ring drifts by 0.5–1 % a period the period-old
    /// set is still far the better guess (R = 51.2, `fast`: 3.0 against 4–11 iterations a
    /// step), and in the first periods after a start, with the ring nearly still, the
    /// film's own transient makes it the worse (14–50 against 4–11). Measured (`fast`,
    /// tolerance 1e-4, iterations a step and wall time): R = 51.2, 0.01/0.02/2 µm 4.93 →
    /// 3.38, 9.95 → 7.18 s; R = 6.4, 0.0025/0.005/5 µm 4.37 → 2.44, 8.4 → 5.0 s; Case III
    /// 3.48 → 3.21; outcomes equal to round-off (the guess only starts the iteration).
    pub(super) fn guess(&self, level: usize, z_now: f64) -> Option<(&FilmState, f64)> {
        let n = self.slots.len();
        let (state, z_then) = self.slots.get(level.checked_rem(n)?)?.as_ref()?;
        let better = matches!(self.switched, Some((period, step)) if period <= step);
        // Z of level − period − 1 (the slot of level − 1 holds level − 1 itself).
        let z_before = self.z[level.checked_sub(n + 1)? % (n + 1)]?;
        better.then_some((state, z_now + (z_then - z_before)))
    }

    /// Keeps the solved state of time level `level` (reusing the slot's buffers). The last
    /// argument says how the next step's other guess carries the previous state with the
    /// texture, so that the switches counted against the previous level are those that
    /// guess would need.
    pub(super) fn store(
        &mut self,
        level: usize,
        state: &FilmState,
        z: f64,
        (shift, grid, hl): (TextureShift, &Grid, &[f64]),
    ) {
        let n = self.slots.len();
        if let Some(slot) = level.checked_rem(n + 1).and_then(|k| self.z.get_mut(k)) {
            *slot = Some(z);
        }
        let Some(k) = level.checked_rem(n) else {
            return;
        };
        let differ = |s: &Option<(FilmState, f64)>, shift: TextureShift| {
            s.as_ref()
                .map(|(s, _)| shift.switches(grid, hl, &s.pressurised, &state.pressurised))
        };
        self.switched = differ(&self.slots[k], TextureShift::NONE)
            .zip(differ(&self.slots[(k + n - 1) % n], shift));
        let slot = &mut self.slots[k];
        match slot {
            Some((s, zs)) => {
                s.assign(state);
                *zs = z;
            }
            None => *slot = Some((state.clone(), z)),
        }
    }
}

/// How a step's initial guess from the previous time level follows the texture: the liner,
/// and the pockets with it, move u·dt per step, about one node column at every tier (dt is
/// matched to dx). Inside a pocket the film moves with it (the oil it carries, the cavity
/// it opens), so there the previous state `columns` upstream is the nearer guess; outside,
/// the film is held by the ring, which stays. Only a starting point: the step's film
/// problem has one solution, so outcomes change at round-off only. Measured against holding
/// the previous state in place: iterations a step at `paper` from the paper's start (`bench`), Case I 1.69 → 1.65, Case
/// III 2.59 → 2.26, R = 51.2 2.47 → 1.89; instructions (valgrind) at `fast` Case III 17.16 G
/// → 16.05 G, R = 51.2 17.00 G → 13.51 G, at `paper` Case III 83.4 G → 81.4 G (its 512×32
/// windows eliminate as many band rows as before: fewer, longer refactorisations). Carrying
/// every node instead (the ring's own cavity too) cost Case I at `fast` 1.92 → 2.50.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct TextureShift {
    pub(super) columns: usize,
}

impl TextureShift {
    pub(super) const NONE: TextureShift = TextureShift { columns: 0 };

    pub(super) fn of(case: &CaseSpec, dt: f64, g: &Grid) -> Self {
        let columns = if case.texture.is_some() {
            (case.u * dt / g.dx).round().clamp(0.0, g.n1 as f64) as usize
        } else {
            0
        };
        TextureShift { columns }
    }

    /// The node whose previous state guesses node m's: `columns` upstream when m (an
    /// interior node) lies in a pocket and that node is interior too; m itself otherwise.
    #[inline]
    pub(super) fn source(self, g: &Grid, hl: &[f64], m: usize) -> usize {
        let back = self.columns * g.n2;
        let interior = m >= back + g.n2 && m < g.n1 * g.n2;
        if back > 0 && interior && hl[m] > 0.0 {
            m - back
        } else {
            m
        }
    }

    /// How many nodes m are in another set in `now` than their source was in `before`
    /// (`before[source(m)] != now[m]`). Counted over slices, without a branch per node:
    /// counted node by node it was ≈ 3.7 % of a settled 512×32 step.
    pub(super) fn switches(self, g: &Grid, hl: &[f64], before: &[bool], now: &[bool]) -> usize {
        let differ = |a: &[bool], b: &[bool]| a.iter().zip(b).filter(|(x, y)| x != y).count();
        let back = self.columns * g.n2;
        // Nodes that may take a source upstream (see `source`): [lo, hi).
        let (lo, hi) = (back + g.n2, (g.n1 * g.n2).min(now.len()));
        if back == 0 || lo >= hi {
            return differ(before, now);
        }
        let shifted = now[lo..hi]
            .iter()
            .zip(&hl[lo..hi])
            .zip(before[lo..hi].iter().zip(&before[lo - back..hi - back]))
            .filter(|((&x, &h), (&own, &up))| x != if h > 0.0 { up } else { own })
            .count();
        differ(&before[..lo], &now[..lo]) + shifted + differ(&before[hi..], &now[hi..])
    }

    /// Carries `state` (the previous time level) with the texture placed now (`hl`), in
    /// place: downstream first, so every node reads a source not yet overwritten.
    pub(super) fn carry(self, g: &Grid, hl: &[f64], state: &mut FilmState) {
        if self.columns == 0 {
            return;
        }
        for m in (0..g.nodes()).rev() {
            let from = self.source(g, hl, m);
            if from != m {
                state.pressurised[m] = state.pressurised[from];
                state.p[m] = state.p[from];
                state.phi[m] = state.phi[from];
            }
        }
    }
}
