//! What a run may cost, estimated from its numerics before anything is allocated, and the
//! stated limits it must stay within (a front end lets the user raise them).

use super::memory::{PERIOD_FACTORS_MEMORY, PERIOD_GUESS_MEMORY, PLACED_TEXTURE_MEMORY};
use super::numerics::{short, steps_per_period, Numerics};
use crate::model::case::{bad, CaseSpec, InputError, Waiver};

/// Memory a run may take by default: 8 GiB, a third of the 24 GiB this project is developed
/// on and half of a common 16 GiB workstation. Measured peak (estimate): 512×32 0.6 GiB
/// (1.3), 1024×64 1.8 GiB (1.9); the estimate errs high, most of it the factors kept over a
/// period, which stop growing at 1.5 GiB.
pub const DEFAULT_MEMORY_GIB: f64 = 8.0;

/// Time steps a run may take by default (t_max / dt): 10⁷, ≈ 1 h at 512×8 were a run never
/// to settle. The paper's t_max of 30 ms takes 75,000 at dt = 4e-4, and 2048×128 at
/// dt = 1e-4 300,000.
pub const DEFAULT_STEPS: f64 = 1e7;

const GIB: f64 = (1u64 << 30) as f64;

/// The limits a run is checked against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Limits {
    /// Bytes of memory.
    pub memory: f64,
    /// Time steps up to t_max.
    pub steps: f64,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            memory: DEFAULT_MEMORY_GIB * GIB,
            steps: DEFAULT_STEPS,
        }
    }
}

impl Limits {
    /// The limits with `gib` of memory.
    pub fn with_memory_gib(self, gib: f64) -> Self {
        Limits {
            memory: gib * GIB,
            ..self
        }
    }
}

/// A run's estimated cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cost {
    /// Cells of the mesh (N1·N2, in floating point so that no product overflows).
    pub cells: f64,
    /// Bytes of memory at most.
    pub memory: f64,
    /// Time steps up to t_max.
    pub steps: f64,
}

/// The cost of running `case` with `num`. Memory: per cell the band LU's matrix and factors,
/// 2·(2w + 1) numbers with a band half-width w ≈ N2, and ≈ 40 numbers of fields; and what a
/// textured run keeps from one period to the next (time/memory.rs) as it keeps it: the
/// period's states (and with them its factors, up to their cap) and the placed texture
/// each only when the whole period fits its cap, none of it otherwise.
pub fn estimate(case: &CaseSpec, num: &Numerics) -> Cost {
    let cells = num.n1 as f64 * num.n2 as f64;
    let n2 = num.n2 as f64;
    let per_cell = film_bytes_per_cell(num.n2);
    let kept = match &case.texture {
        Some(t) => {
            let spp = steps_per_period(t.per / case.u, num.dt);
            let period = |per_cell: f64| spp * cells * per_cell;
            let fits = |bytes: f64, cap: usize| if bytes <= cap as f64 { bytes } else { 0.0 };
            let states = fits(period(17.0), PERIOD_GUESS_MEMORY);
            let factors = if states > 0.0 {
                period(8.0 * (2.0 * n2 + 1.0)).min(PERIOD_FACTORS_MEMORY as f64)
            } else {
                0.0
            };
            states + factors + fits(period(16.0), PLACED_TEXTURE_MEMORY)
        }
        None => 0.0,
    };
    Cost {
        cells,
        memory: cells * per_cell + kept,
        steps: (num.t_max / num.dt).ceil(),
    }
}

/// Bytes a film of `n2` cells across takes per cell: its fields and its banded matrix.
fn film_bytes_per_cell(n2: usize) -> f64 {
    8.0 * (4.0 * n2 as f64 + 2.0 + 40.0)
}

/// Memory an observer of a run keeps beside it (a recording, a time series), named by the
/// input that sets it for errors.
#[derive(Clone, Debug, PartialEq)]
pub struct Kept {
    /// The input (`param`, as in [`InputError`]) and its value.
    pub param: &'static str,
    pub value: String,
    /// What is kept ("100 instants of the film and their pictures") and how to keep less,
    /// for the error.
    pub what: String,
    pub fix: String,
    pub bytes: f64,
}

/// [`check`], and then the run with what its observers keep against the memory limit: over
/// it, the error names the observer that keeps the most (the run alone fits).
pub fn check_with(
    case: &CaseSpec,
    num: &Numerics,
    limits: &Limits,
    kept: &[Kept],
) -> Result<(), InputError> {
    check(case, num, limits)?;
    let run = estimate(case, num).memory;
    let total = run + kept.iter().map(|k| k.bytes).sum::<f64>();
    let largest = kept.iter().max_by(|a, b| a.bytes.total_cmp(&b.bytes));
    match largest {
        Some(k) if total.is_nan() || total > limits.memory => Err(InputError {
            waiver: Some(Waiver::MemoryLimit),
            ..bad(
                k.param,
                &k.value,
                format!(
                    "{} take ≈ {} GiB beside the run's ≈ {} GiB, over the limit of {} GiB; {}",
                    k.what,
                    gib(k.bytes),
                    gib(total - k.bytes),
                    short(limits.memory / GIB),
                    k.fix
                ),
            )
        }),
        _ => Ok(()),
    }
}

/// Bytes in GiB, rounded up to two significant digits (a few MB read as 0.0019, not 0).
fn gib(bytes: f64) -> String {
    let x = bytes / GIB;
    if !(x.is_finite() && x > 0.0) {
        return short(x);
    }
    let unit = 10f64.powf(x.log10().floor() - 1.0);
    short((x / unit).ceil() * unit)
}

/// The mesh's memory against the limit.
fn check_memory((n1, n2): (usize, usize), cost: &Cost, limits: &Limits) -> Result<(), InputError> {
    if cost.memory.is_nan() || cost.memory > limits.memory {
        return Err(InputError {
            waiver: Some(Waiver::MemoryLimit),
            ..bad(
                "mesh",
                format!("{n1}x{n2}"),
                format!(
                    "needs ≈ {} GiB of memory ({} cells), over the limit of {} GiB; use fewer cells",
                    gib(cost.memory),
                    short(cost.cells),
                    short(limits.memory / GIB)
                ),
            )
        });
    }
    Ok(())
}

/// Checks a cycle run's cost against `limits` before it runs: its film of `n1`×`n2` cells
/// (memory, as a run's without what a period keeps) and its crank steps, `per_cycle` in each
/// of at most `cycles` cycles. The crank steps follow the mesh (the texture moves at most
/// two cells a step), so the mesh is the input named.
pub fn check_cycle(
    (n1, n2): (usize, usize),
    per_cycle: usize,
    cycles: usize,
    limits: &Limits,
) -> Result<(), InputError> {
    let cells = n1 as f64 * n2 as f64;
    let cost = Cost {
        cells,
        memory: cells * film_bytes_per_cell(n2),
        steps: (per_cycle * cycles) as f64,
    };
    check_memory((n1, n2), &cost, limits)?;
    if cost.steps > limits.steps {
        return Err(InputError {
            waiver: Some(Waiver::StepLimit),
            ..bad(
                "mesh",
                format!("{n1}x{n2}"),
                format!(
                    "gives up to {} crank steps ({per_cycle} a cycle over at most {cycles} cycles), over the limit of {}; use fewer cells along x1 or a lower fidelity",
                    short(cost.steps),
                    short(limits.steps)
                ),
            )
        });
    }
    Ok(())
}

/// Checks a run's estimated cost against `limits`: the mesh (memory) and the time step
/// (steps), each error waivable by raising its limit.
pub fn check(case: &CaseSpec, num: &Numerics, limits: &Limits) -> Result<(), InputError> {
    let cost = estimate(case, num);
    check_memory((num.n1, num.n2), &cost, limits)?;
    if cost.steps.is_nan() || cost.steps > limits.steps {
        return Err(InputError {
            waiver: Some(Waiver::StepLimit),
            ..bad(
                "dt",
                num.dt,
                format!(
                    "gives {} steps up to t_max = {} ms, over the limit of {}; use a larger dt or a shorter t_max",
                    short(cost.steps),
                    short(num.t_max),
                    short(limits.steps)
                ),
            )
        });
    }
    Ok(())
}
