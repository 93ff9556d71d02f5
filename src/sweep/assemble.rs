//! Assembling a finished sweep directory: sweep.h5 (all impacts with case and seed
//! columns, per-case and per-run statistics), cases.csv and the comparison figures.
//! Built only from the case directories, so a merged set of shards and a single run
//! produce the same file.
//!
//! sweep.h5 layout (every dataset has `units` and `description` attributes):
//! ```text
//! /                  attrs: format, tool, tool_version, title, sweep (TOML), base_scene
//!                    (TOML), combine, sweep_hash, seeds, parameters
//! /impacts/<column>  the impact columns of impacts.h5 plus `case` (index into /cases)
//!                    and `seed`
//! /cases/name, hash, scene          one string per case
//! /cases/parameters/<dotted key>    the varied values (numbers, or TOML text)
//! /cases/shots, shots_hit           totals over the case's seeds
//! /cases/stats/<stat>/{mean, std, ci_low, ci_high, n}   across seeds (95 % Student t;
//!                                   NaN where a case has fewer than 2 seeds with a value)
//! /cases/speed_histogram, radius_histogram: lower_edges and counts[case, bin]
//! /runs/{case, seed, shots, shots_hit, impacts, <stat>}  one row per (case, seed)
//! ```

use super::run::{CaseResult, Manifest, SweepRunError, bin_labels, missing_cases, shares};
use super::stats::STATS;
use crate::export::hdf5::{self as h5, Column, H5Error, impact_columns, werr, write_columns};
use crate::plot;
use crate::record::Impact;
use rust_hdf5::{H5File, H5Group};
use std::path::Path;

/// Format tag of sweep.h5.
pub const SWEEP_FORMAT: &str = "peenflow-sweep-h5/1";

/// A finished case read back from its directory.
struct Finished {
    result: CaseResult,
    impacts: Vec<Impact>,
    seeds: Vec<u64>,
}

/// Writes `dir/sweep.h5`, `dir/cases.csv` and `dir/figures/` from the manifest and the
/// finished case directories. Fails naming the missing cases if any is not finished.
pub fn assemble(dir: &Path) -> Result<(), SweepRunError> {
    let manifest = Manifest::read(dir)?;
    let mut missing = Vec::new();
    let mut cases = Vec::with_capacity(manifest.cases.len());
    for c in &manifest.cases {
        let cdir = dir.join(&c.name);
        match CaseResult::read(&cdir) {
            Some(r) if r.hash == c.hash => {
                let f = h5::read(&cdir.join(h5::IMPACT_FILE))?;
                cases.push(Finished {
                    result: r,
                    impacts: f.impacts,
                    seeds: f.seeds,
                });
            }
            _ => missing.push(c.name.clone()),
        }
    }
    if !missing.is_empty() {
        return Err(missing_cases(
            dir,
            &missing,
            manifest.cases.len(),
            "are not finished",
            "; run the sweep (or its shards) again to finish them",
        ));
    }
    let path = dir.join("sweep.h5");
    h5::write_atomic(&path, |tmp| write_h5(tmp, &path, &manifest, &cases))?;
    write_csv(dir, &manifest, &cases)?;
    figures(dir, &manifest, &cases)?;
    Ok(())
}

fn nan(v: Option<f64>) -> f64 {
    v.unwrap_or(f64::NAN)
}

fn write_h5(tmp: &Path, shown: &Path, m: &Manifest, cases: &[Finished]) -> Result<(), H5Error> {
    let e = werr(shown);
    let file = H5File::create(tmp).map_err(&e)?;
    file.set_attr_string("format", SWEEP_FORMAT).map_err(&e)?;
    file.set_attr_string("tool", "peenflow").map_err(&e)?;
    file.set_attr_string("tool_version", &m.tool_version)
        .map_err(&e)?;
    file.set_attr_string("title", &m.title).map_err(&e)?;
    file.set_attr_string("sweep", &m.sweep_text).map_err(&e)?;
    file.set_attr_string("base_scene", &m.base_text)
        .map_err(&e)?;
    file.set_attr_string("combine", &m.combine).map_err(&e)?;
    file.set_attr_string("sweep_hash", &m.sweep_hash)
        .map_err(&e)?;
    file.set_attr_array_numeric("seeds", &m.seeds).map_err(&e)?;
    let params: Vec<&str> = m.parameters.iter().map(String::as_str).collect();
    file.set_attr_string_array("parameters", &params)
        .map_err(&e)?;
    let root = file.root_group();

    // All impacts, case by case, each case's seeds in order.
    let all: Vec<Impact> = cases.iter().flat_map(|c| c.impacts.clone()).collect();
    let mut cols = impact_columns(&all);
    cols.push(Column::U32(
        "case",
        "1",
        "case index (row of /cases)",
        cases
            .iter()
            .flat_map(|c| std::iter::repeat_n(c.result.index as u32, c.impacts.len()))
            .collect(),
    ));
    cols.push(Column::U64(
        "seed",
        "1",
        "seed of the run",
        cases.iter().flat_map(|c| c.seeds.clone()).collect(),
    ));
    let g = root.create_group("impacts").map_err(&e)?;
    write_columns(&g, &cols, shown)?;

    let g = root.create_group("cases").map_err(&e)?;
    let strings = |g: &H5Group, name: &str, v: Vec<&str>| -> Result<(), H5Error> {
        g.write_vlen_strings(name, &v).map_err(&e)?;
        Ok(())
    };
    strings(
        &g,
        "name",
        m.cases.iter().map(|c| c.name.as_str()).collect(),
    )?;
    strings(
        &g,
        "hash",
        m.cases.iter().map(|c| c.hash.as_str()).collect(),
    )?;
    strings(
        &g,
        "scene",
        m.cases.iter().map(|c| c.scene.as_str()).collect(),
    )?;
    write_columns(
        &g,
        &[
            Column::U64(
                "shots",
                "1",
                "shots fed, all seeds",
                cases
                    .iter()
                    .map(|c| c.result.runs.iter().map(|r| r.shots as u64).sum())
                    .collect(),
            ),
            Column::U64(
                "shots_hit",
                "1",
                "shots that reached the specimen, all seeds",
                cases
                    .iter()
                    .map(|c| c.result.runs.iter().map(|r| r.shots_hit as u64).sum())
                    .collect(),
            ),
        ],
        shown,
    )?;
    let pg = g.create_group("parameters").map_err(&e)?;
    for (k, p) in m.parameters.iter().enumerate() {
        let values: Vec<&toml::Value> = m.cases.iter().map(|c| &c.values[k]).collect();
        let numbers: Option<Vec<f64>> = values
            .iter()
            .map(|v| match v {
                toml::Value::Float(f) => Some(*f),
                toml::Value::Integer(i) => Some(*i as f64),
                _ => None,
            })
            .collect();
        match numbers {
            Some(nums) => {
                let ds = pg
                    .new_dataset::<f64>()
                    .shape([nums.len()])
                    .create(p)
                    .map_err(&e)?;
                ds.write_raw(&nums).map_err(&e)?;
            }
            None => {
                let text: Vec<String> = values.iter().map(|v| super::plan::show(v)).collect();
                strings(&pg, p, text.iter().map(String::as_str).collect())?;
            }
        }
    }
    let sg = g.create_group("stats").map_err(&e)?;
    for d in STATS {
        let one = sg.create_group(d.name).map_err(&e)?;
        one.set_attr_string("description", d.description)
            .map_err(&e)?;
        one.set_attr_string("units", d.units).map_err(&e)?;
        let across: Vec<&super::stats::AcrossSeeds> =
            cases.iter().map(|c| &c.result.stats[d.name]).collect();
        let col = |name: &'static str,
                   desc: &'static str,
                   f: fn(&super::stats::AcrossSeeds) -> Option<f64>| {
            Column::F64(
                name,
                d.units,
                desc,
                across.iter().map(|a| nan(f(a))).collect(),
            )
        };
        write_columns(
            &one,
            &[
                col("mean", "mean over seeds", |a| a.mean),
                col("std", "sample standard deviation over seeds", |a| a.std),
                col(
                    "ci_low",
                    "lower end of the 95 % confidence interval of the mean",
                    |a| a.ci_low,
                ),
                col(
                    "ci_high",
                    "upper end of the 95 % confidence interval of the mean",
                    |a| a.ci_high,
                ),
                Column::U64(
                    "n",
                    "1",
                    "seeds with a value",
                    across.iter().map(|a| a.n as u64).collect(),
                ),
            ],
            shown,
        )?;
    }
    for (name, get) in [
        (
            "speed_histogram",
            (|r: &CaseResult| &r.speed_histogram) as fn(&CaseResult) -> &crate::summary::Histogram,
        ),
        ("radius_histogram", |r: &CaseResult| &r.radius_histogram),
    ] {
        let hg = g.create_group(name).map_err(&e)?;
        let first = get(&cases[0].result);
        hg.set_attr_string("quantity", &first.quantity)
            .map_err(&e)?;
        hg.set_attr_numeric("bin_width", &first.bin_width)
            .map_err(&e)?;
        let unit = if name.starts_with("speed") {
            "m/s"
        } else {
            "mm"
        };
        write_columns(
            &hg,
            &[
                Column::F64(
                    "lower_edges",
                    unit,
                    "lower bin edges",
                    first.lower_edges.clone(),
                ),
                Column::U64(
                    "overflow",
                    "1",
                    "first hits beyond the last bin, per case",
                    cases
                        .iter()
                        .map(|c| get(&c.result).overflow as u64)
                        .collect(),
                ),
            ],
            shown,
        )?;
        let counts: Vec<u64> = cases
            .iter()
            .flat_map(|c| get(&c.result).counts.iter().map(|&x| x as u64))
            .collect();
        let ds = hg
            .new_dataset::<u64>()
            .shape([cases.len(), first.counts.len()])
            .create("counts")
            .map_err(&e)?;
        ds.write_raw(&counts).map_err(&e)?;
    }

    let rows: Vec<(usize, &super::run::SeedRun)> = cases
        .iter()
        .flat_map(|c| c.result.runs.iter().map(move |r| (c.result.index, r)))
        .collect();
    let g = root.create_group("runs").map_err(&e)?;
    let mut cols = vec![
        Column::U32(
            "case",
            "1",
            "case index",
            rows.iter().map(|r| r.0 as u32).collect(),
        ),
        Column::U64("seed", "1", "seed", rows.iter().map(|r| r.1.seed).collect()),
        Column::U64(
            "shots",
            "1",
            "shots fed",
            rows.iter().map(|r| r.1.shots as u64).collect(),
        ),
        Column::U64(
            "shots_hit",
            "1",
            "shots that reached the specimen",
            rows.iter().map(|r| r.1.shots_hit as u64).collect(),
        ),
        Column::U64(
            "impacts",
            "1",
            "impacts incl. rebound hits",
            rows.iter().map(|r| r.1.impacts as u64).collect(),
        ),
    ];
    for d in STATS {
        cols.push(Column::F64(
            d.name,
            d.units,
            d.description,
            rows.iter().map(|r| nan(r.1.stats[d.name])).collect(),
        ));
    }
    write_columns(&g, &cols, shown)?;
    file.close().map_err(&e)?;
    Ok(())
}

fn write_csv(dir: &Path, m: &Manifest, cases: &[Finished]) -> Result<(), SweepRunError> {
    let path = dir.join("cases.csv");
    let mut w = csv::Writer::from_writer(Vec::new());
    let mut header = vec!["case".to_string(), "name".to_string()];
    header.extend(m.parameters.iter().cloned());
    header.extend(["seeds", "shots", "shots_hit"].map(String::from));
    for d in STATS {
        for s in ["mean", "ci_low", "ci_high"] {
            header.push(format!("{}_{s}", d.name));
        }
    }
    let csv_err = |e: csv::Error| SweepRunError::Dir {
        path: path.display().to_string(),
        message: e.to_string(),
    };
    w.write_record(&header).map_err(csv_err)?;
    let f = |v: Option<f64>| v.map(|x| format!("{x}")).unwrap_or_default();
    for (c, mc) in cases.iter().zip(&m.cases) {
        let mut row = vec![c.result.index.to_string(), c.result.name.clone()];
        row.extend(mc.values.iter().map(super::plan::show));
        row.push(c.result.runs.len().to_string());
        row.push(
            c.result
                .runs
                .iter()
                .map(|r| r.shots)
                .sum::<usize>()
                .to_string(),
        );
        row.push(
            c.result
                .runs
                .iter()
                .map(|r| r.shots_hit)
                .sum::<usize>()
                .to_string(),
        );
        for d in STATS {
            let a = &c.result.stats[d.name];
            row.extend([f(a.mean), f(a.ci_low), f(a.ci_high)]);
        }
        w.write_record(&row).map_err(csv_err)?;
    }
    let bytes = w.into_inner().map_err(|e| SweepRunError::Dir {
        path: path.display().to_string(),
        message: e.to_string(),
    })?;
    crate::output::write_atomic(&path, &bytes)?;
    Ok(())
}

/// Cases that differ from each other in parameter `k` only: the largest such group
/// (earliest on ties), if it has at least two cases.
fn effect_group(m: &Manifest, k: usize) -> Option<Vec<usize>> {
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for (i, c) in m.cases.iter().enumerate() {
        let key = |j: usize| -> Vec<&toml::Value> {
            m.cases[j]
                .values
                .iter()
                .enumerate()
                .filter(|(q, _)| *q != k)
                .map(|(_, v)| v)
                .collect()
        };
        match groups.iter_mut().find(|g| key(g[0]) == key(i)) {
            Some(g) => {
                if !g.iter().any(|&j| m.cases[j].values[k] == c.values[k]) {
                    g.push(i)
                }
            }
            None => groups.push(vec![i]),
        }
    }
    let best = groups
        .into_iter()
        .fold(None::<Vec<usize>>, |b, g| match b {
            Some(b) if b.len() >= g.len() => Some(b),
            _ => Some(g),
        })?;
    (best.len() >= 2).then_some(best)
}

fn figures(dir: &Path, m: &Manifest, cases: &[Finished]) -> Result<(), SweepRunError> {
    let fig = dir.join("figures");
    std::fs::create_dir_all(&fig).map_err(|e| SweepRunError::Dir {
        path: fig.display().to_string(),
        message: e.to_string(),
    })?;
    let hist = |stem: &Path,
                title: &str,
                idx: &[usize],
                label: &dyn Fn(usize) -> String,
                speed: bool|
     -> Result<(), plot::PlotError> {
        let h = |i: usize| {
            if speed {
                &cases[i].result.speed_histogram
            } else {
                &cases[i].result.radius_histogram
            }
        };
        let xlabel = if speed {
            "normal impact speed of first hits, m/s"
        } else {
            "impact radius of first hits, mm"
        };
        if idx.len() <= 6 {
            plot::bars(
                stem,
                title,
                (xlabel, "share of first hits, %"),
                &bin_labels(h(idx[0])),
                &idx.iter()
                    .map(|&i| plot::Bars {
                        name: label(i),
                        values: shares(h(i)),
                    })
                    .collect::<Vec<_>>(),
            )
        } else {
            // Many cases: curves through the bin centres read better than bars.
            let series: Vec<plot::Series> = idx
                .iter()
                .map(|&i| {
                    let hh = h(i);
                    plot::Series {
                        name: label(i),
                        points: hh
                            .lower_edges
                            .iter()
                            .zip(shares(hh))
                            .map(|(lo, s)| (lo + hh.bin_width / 2.0, s))
                            .collect(),
                    }
                })
                .collect();
            plot::lines(
                stem,
                title,
                (xlabel, "share of first hits, %"),
                &series,
                false,
            )
        }
    };
    let all: Vec<usize> = (0..cases.len()).collect();
    let name = |i: usize| cases[i].result.name.clone();
    hist(
        &fig.join("compare_speed"),
        &format!("{}: impact speed, all cases", m.title),
        &all,
        &name,
        true,
    )?;
    hist(
        &fig.join("compare_radius"),
        &format!("{}: impact radius, all cases", m.title),
        &all,
        &name,
        false,
    )?;
    // Effect of each parameter (as the paper's Figures 3-5): cases that differ in it alone.
    for (k, p) in m.parameters.iter().enumerate() {
        let Some(group) = effect_group(m, k) else {
            continue;
        };
        let last = p.rsplit('.').next().unwrap_or(p);
        let label = |i: usize| format!("{} = {}", last, super::plan::show(&m.cases[i].values[k]));
        for speed in [false, true] {
            let stem = fig.join(format!(
                "effect_{last}_{}",
                if speed { "speed" } else { "radius" }
            ));
            hist(
                &stem,
                &format!(
                    "effect of {p} on the impact {}",
                    if speed { "speed" } else { "radius" }
                ),
                &group,
                &label,
                speed,
            )?;
        }
        // Trend of the 90th-percentile radius and the mean speed with their 95 % CIs.
        let numeric: Option<Vec<f64>> = group
            .iter()
            .map(|&i| match &m.cases[i].values[k] {
                toml::Value::Float(f) => Some(*f),
                toml::Value::Integer(n) => Some(*n as f64),
                _ => None,
            })
            .collect();
        if let Some(xs) = numeric {
            let mut order: Vec<usize> = (0..group.len()).collect();
            order.sort_by(|&a, &b| xs[a].total_cmp(&xs[b]));
            for (stat, what) in [
                ("radius_p90_mm", "90th-percentile impact radius, mm"),
                ("speed_mean_m_s", "mean normal impact speed, m/s"),
            ] {
                let pick = |f: fn(&super::stats::AcrossSeeds) -> Option<f64>| -> Vec<(f64, f64)> {
                    order
                        .iter()
                        .filter_map(|&j| f(&cases[group[j]].result.stats[stat]).map(|y| (xs[j], y)))
                        .collect()
                };
                let series = vec![
                    plot::Series {
                        name: "mean over seeds".into(),
                        points: pick(|a| a.mean),
                    },
                    plot::Series {
                        name: "95 % CI, low".into(),
                        points: pick(|a| a.ci_low),
                    },
                    plot::Series {
                        name: "95 % CI, high".into(),
                        points: pick(|a| a.ci_high),
                    },
                ];
                plot::lines(
                    &fig.join(format!("trend_{last}_{stat}")),
                    &format!("{what} against {p}"),
                    (p.as_str(), what),
                    &series,
                    false,
                )?;
            }
        }
    }
    Ok(())
}
