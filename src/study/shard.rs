//! Shards of a study for a cluster: a deterministic split of its cases into N shares of about
//! equal expected cost, the same on every machine (it depends on the study file alone, never
//! on what a cache holds). Cases differing only in θ_s share one simulation and stay together.

use std::collections::BTreeMap;

use super::cache::Key;
use super::file::Job;
use crate::model::case::CaseSpec;

/// Expected cost of a job, in arbitrary units: cells × steps for a transient (its time to
/// the periodic regime varies less than its step cost), a token for a steady plain liner.
fn cost(job: &Job) -> f64 {
    let n = &job.numerics;
    match job.case.texture {
        Some(_) => (n.n1 * n.n2) as f64 / n.dt,
        None => n.n1 as f64,
    }
}

/// The simulation a job belongs to: its key without θ_s.
fn group(job: &Job) -> String {
    let case = CaseSpec {
        theta_s: 0.0,
        ..job.case.clone()
    };
    Key::of(&case, &job.numerics).hash
}

/// The indices of the jobs of shard `i` of `n` (1-based), in study order. Groups are dealt,
/// dearest first (ties by key), each to the share with the least expected cost so far (ties
/// to the lowest): the longest-processing-time rule, within 4/3 of the best balance.
pub fn shard(jobs: &[Job], i: usize, n: usize) -> Vec<usize> {
    assert!(1 <= i && i <= n, "shard {i}/{n}");
    let mut groups: BTreeMap<String, (f64, Vec<usize>)> = BTreeMap::new();
    for (k, j) in jobs.iter().enumerate() {
        let g = groups.entry(group(j)).or_insert((0.0, Vec::new()));
        g.0 = g.0.max(cost(j));
        g.1.push(k);
    }
    let mut order: Vec<(&String, &(f64, Vec<usize>))> = groups.iter().collect();
    order.sort_by(|a, b| b.1 .0.total_cmp(&a.1 .0).then(a.0.cmp(b.0)));
    let mut load = vec![0.0f64; n];
    let mut mine = Vec::new();
    for (_, (c, members)) in order {
        let s = (0..n)
            .min_by(|&a, &b| load[a].total_cmp(&load[b]).then(a.cmp(&b)))
            .unwrap_or(0);
        load[s] += c;
        if s == i - 1 {
            mine.extend(members);
        }
    }
    mine.sort_unstable();
    mine
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::study::file::parse;

    fn jobs() -> Vec<Job> {
        parse(
            r#"
            [study]
            name = "s"
            untextured = true
            [parameters]
            R = [0.8, 3.2, 12.8]
            l1 = [0.005, 0.01, 0.03]
            per = [0.03, 0.06]
            depth = [2, 5]
            theta_s = [0.5, 0.95]
            "#,
            "s.toml",
        )
        .unwrap()
        .jobs
    }

    #[test]
    fn shards_are_disjoint_cover_the_study_and_balance_its_cost() {
        let jobs = jobs();
        for n in [1, 2, 3, 7] {
            let shards: Vec<Vec<usize>> = (1..=n).map(|i| shard(&jobs, i, n)).collect();
            let mut all: Vec<usize> = shards.iter().flatten().copied().collect();
            all.sort_unstable();
            assert_eq!(all, (0..jobs.len()).collect::<Vec<_>>(), "n = {n}");
            // θ_s siblings share a shard.
            for s in &shards {
                for &k in s {
                    let sib = jobs
                        .iter()
                        .position(|j| group(j) == group(&jobs[k]))
                        .unwrap();
                    assert!(s.contains(&sib));
                }
            }
            // Balanced: no share above the lightest by more than the dearest group.
            let load = |s: &Vec<usize>| -> f64 {
                let mut seen = std::collections::HashSet::new();
                s.iter()
                    .filter(|&&k| seen.insert(group(&jobs[k])))
                    .map(|&k| cost(&jobs[k]))
                    .sum()
            };
            let loads: Vec<f64> = shards.iter().map(load).collect();
            let dearest = jobs.iter().map(cost).fold(0.0, f64::max);
            let (lo, hi) = loads
                .iter()
                .fold((f64::INFINITY, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
            assert!(hi - lo <= dearest * (1.0 + 1e-12), "n = {n}: {loads:?}");
        }
        // The same split every time (it depends on the study alone).
        let again = super::tests::jobs();
        assert_eq!(shard(&jobs, 2, 3), shard(&again, 2, 3));
    }
}
