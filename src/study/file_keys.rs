//! What a study file may say: the parameters it may vary and the limits on its size, read
//! by the study file's reader and named in its errors.

/// The parameters a study may vary, with their units (docs/model.md §1). Texture parameters
/// first-class; the rest default to the paper's operating point (CaseSpec::paper).
pub const PARAMETERS: [(&str, &str); 21] = [
    ("R", "ring face radius, cm (\"inf\" for a flat ring)"),
    (
        "texture",
        "chosen textures: a list of { l1, per, depth [, l2, width, phase] }",
    ),
    ("l1", "pocket semiaxis along sliding, cm"),
    ("l2", "pocket semiaxis across sliding, cm"),
    ("per", "texture period along sliding, cm"),
    ("width", "texture period across sliding, cm"),
    ("depth", "pocket depth, µm"),
    ("phase", "x1 of a pocket centre at t = 0, cm"),
    ("u", "liner speed, units of 10 m/s"),
    ("w_ps", "ring load per unit width, units of 2.4e7 N/m"),
    ("mass", "ring mass per unit width, units of 2.4e7 kg/m"),
    ("d_oil", "inlet oil film, µm"),
    ("theta_s", "shear threshold of the Couette switch"),
    ("e", "gap outside the ring, µm"),
    ("z0", "initial ring position, µm"),
    ("v0", "initial ring velocity"),
    ("speed", "sliding speed, m/s"),
    ("load", "ring load per unit circumferential length, N/m"),
    ("viscosity", "oil viscosity, Pa·s"),
    ("ring_width", "axial width of the ring face, mm"),
    (
        "ring_mass",
        "ring mass per unit circumferential length, kg/m",
    ),
];

/// Most combinations a study expands by default: 100,000 (the paper's study has 1,760; at
/// `fast`, 100,000 cases are ≈ 14 h on two cores). Why a limit: a typo in a range (a step of
/// 1e-9) would otherwise expand to billions of cases, in memory, before any is run.
pub const MAX_CASES: u64 = 100_000;

/// Most cases `max_cases` may allow: 1,000,000 (≈ 140 h at `fast` on two cores, a cluster's
/// work in shares). Every case is expanded in memory before any runs (≈ 0.5 kB each), so a
/// larger limit would let a typo fill the memory all the same.
pub const MAX_CASES_CEILING: u64 = 1_000_000;

/// Most values one parameter may expand to (a typo in a range should not make a million).
pub const MAX_VALUES: usize = 10_000;
