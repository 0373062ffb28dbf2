//! The gap across a cell on the deep close-packed pockets (results/rim_rows/): `texopt-lab
//! rim-rows`.
//!
//! The benchmark's deep close-packed case (R = 3.2, l1 = 0.03, per = width = 0.06, 20 µm
//! deep) on 512 cells along at the tiers' characteristic step, as the cells across double
//! (N2 = 8 → 64), for three ways of seeing the gap across a cell ([`RimModel`]): at the
//! nodes; sampled across each cell with an x1 face's strips in parallel and the gap between
//! two rows in series across an x2 face; and the same strips with nodal x2 faces. Then the
//! samples a cell takes (2, 8, 32) at N2 = 8, and the strips with the shear threshold θ_s
//! at 0.01. Then the benchmark's shallower pockets at 700 along. Then the same array on R = 25.6, nodal and
//! strips, as the cells across double at 600 along and as the cells along double (the step
//! with them) at 24 across.

use std::fmt::Write as _;

use super::rim_1d::write_report;
use texopt::mesh::RimModel;
use texopt::model::case::{CaseSpec, Texture};
use texopt::time::{resolve, simulate, Fidelity, Outcome, Overrides, TimeScheme};

const HEAD: &str = "| gap across a cell | mesh | f̄ | Couette | Poiseuille | pressure | C_min (µm) | s |\n|---|---|---|---|---|---|---|---|\n";

fn run(case: &CaseSpec, (n1, n2): (usize, usize), rim: RimModel) -> Result<Outcome, String> {
    let given = Overrides {
        n1: Some(n1),
        n2: Some(n2),
        scheme: Some(TimeScheme::Characteristic),
        ..Overrides::default()
    };
    let mut num = resolve(Fidelity::Fast, &given, case);
    num.rim = rim;
    simulate(case, &num)
        .map(|r| r.outcome)
        .map_err(|e| e.to_string())
}

fn label(rim: RimModel) -> String {
    match rim {
        RimModel::Nodal => "nodal".into(),
        RimModel::Strips { samples } => format!("strips, x2 faces in series ({samples} samples)"),
        RimModel::StripsAlong { samples } => {
            format!("strips, x2 faces nodal ({samples} samples)")
        }
    }
}

fn row(md: &mut String, rim: RimModel, (n1, n2): (usize, usize), o: &Outcome) {
    let line = format!(
        "| {} | {n1}×{n2} | {:.5} | {:.5} | {:.5} | {:.5} | {:.4} | {:.2} |\n",
        label(rim),
        o.f_mean,
        o.f_couette,
        o.f_poiseuille,
        o.f_pressure,
        o.c_min,
        o.wall_time_s
    );
    print!("{line}");
    md.push_str(&line);
}

pub fn main(_args: &[String]) -> Result<(), String> {
    let case = CaseSpec::paper(3.2).with_texture(Texture::circular(0.03, 0.06, 20.0));
    let mut md = String::from(
        "# The gap across a cell: deep close-packed pockets\n\nReproduce: `texopt-lab rim-rows` (≈ 11 min on one core; lab/src/studies/rim_rows.rs). The benchmark's deep close-packed case (R = 3.2, l1 = 0.03, per = width = 0.06, 20 µm deep: depth/C_min ≈ 11) on 512 cells along, the characteristic scheme at its step 2·dx1/u, the `fast` tier's periodic tolerance and coarse approach. Each row of cells seen three ways: at its centre line (nodal, texopt's stencil); sampled at points across the cell, an x1 face the mean of its strips' h_f³ (in parallel) and an x2 face the samples between the two rows in series (strips); and the same strips with the nodal x2 face. Couette, Poiseuille and pressure are f̄'s terms; wall times on one core. What it shows: docs/solver.md, \"The gap across a cell\".\n\n",
    );
    md.push_str(HEAD);
    let models = [
        RimModel::Nodal,
        RimModel::Strips { samples: 8 },
        RimModel::StripsAlong { samples: 8 },
    ];
    for rim in models {
        for n2 in [8, 16, 32, 64] {
            row(&mut md, rim, (512, n2), &run(&case, (512, n2), rim)?);
        }
    }
    md.push_str(&format!(
        "\nSamples a cell takes (strips, x2 faces in series), at 512×8:\n\n{HEAD}"
    ));
    for samples in [2, 32] {
        let rim = RimModel::Strips { samples };
        row(&mut md, rim, (512, 8), &run(&case, (512, 8), rim)?);
    }
    md.push_str(&format!(
        "\nThe shear threshold θ_s at 0.01 instead of 0.95 (the Couette shear u·θ/h counted wherever there is film), strips with x2 faces in series:\n\n{HEAD}"
    ));
    let mut low = case.clone();
    low.theta_s = 0.01;
    for n2 in [8, 16, 32] {
        let rim = RimModel::Strips { samples: 8 };
        row(&mut md, rim, (512, n2), &run(&low, (512, n2), rim)?);
    }
    md.push_str("\nThe benchmark's shallower pockets on the `fast` tier's 700 cells along (their references: results/references/):\n\n| case | gap across a cell | mesh | f̄ | C_min (µm) |\n|---|---|---|---|---|\n");
    let shallow = [
        ("Case I (R = 0.8, 0.01 / 0.06 / 5 µm)", 0.8, 0.01, 5.0),
        ("Case III (R = 3.2, 0.03 / 0.06 / 10 µm)", 3.2, 0.03, 10.0),
        ("R = 51.2, 0.01 / 0.06 / 5 µm", 51.2, 0.01, 5.0),
    ];
    for (name, r, l1, depth) in shallow {
        let case = CaseSpec::paper(r).with_texture(Texture::circular(l1, 0.06, depth));
        for rim in [RimModel::Nodal, RimModel::Strips { samples: 8 }] {
            for n2 in [8, 16] {
                let o = run(&case, (700, n2), rim)?;
                let line = format!(
                    "| {name} | {} | 700×{n2} | {:.6} | {:.5} |\n",
                    label(rim),
                    o.f_mean,
                    o.c_min
                );
                print!("{line}");
                md.push_str(&line);
            }
        }
    }
    let wide = CaseSpec::paper(25.6).with_texture(Texture::circular(0.03, 0.06, 20.0));
    md.push_str(&format!("\nThe same array on R = 25.6 (the paper study's large ring: depth/C_min ≈ 13), the cells across doubling at 600 along, then the cells along doubling at 24 across (the characteristic step halving with them):\n\n{HEAD}"));
    let meshes = [
        (600, 12),
        (600, 24),
        (600, 48),
        (600, 96),
        (1200, 24),
        (2400, 24),
    ];
    for rim in [RimModel::Nodal, RimModel::Strips { samples: 8 }] {
        for mesh in meshes {
            row(&mut md, rim, mesh, &run(&wide, mesh, rim)?);
        }
    }
    let _ = writeln!(md);
    write_report("rim_rows", &md)
}
