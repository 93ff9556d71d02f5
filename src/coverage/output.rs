//! `peenflow coverage`: reads impacts.h5, computes the coverage, prints the numbers,
//! writes coverage.csv, coverage.json, the map and the curve (PNG + SVG), and adds a
//! `/coverage` group to the impact file (rewritten atomically).

use super::gear::{GearProfile, OffsetRuns, Turning, ZoneDents};
use super::traverse::{self, Point, Track, Traverse};
use super::{Coverage, DentModel, compute, default_window, dents_on};
use crate::export::hdf5::{self as h5, Column, H5Error, werr, write_columns};
use crate::plot::{self, Field, PlotError, Series};
use crate::scene::{Material, Scene};
use std::path::{Path, PathBuf};

/// The moving nozzle's profiles are averaged over lateral bands this many median dent
/// diameters wide ([`Track::new`]).
pub const BAND_DIAMETERS: f64 = 2.0;

/// Everything `peenflow coverage` was asked.
#[derive(Debug, Clone)]
pub struct Request {
    /// Impact file.
    pub impacts: PathBuf,
    /// Window `[x0, y0, x1, y1]`, m (default: [`default_window`]).
    pub window: Option<[f64; 4]>,
    /// Cell size, m (default: a fifth of the median dent radius).
    pub cell: Option<f64>,
    /// Target material (default: the scene's specimen).
    pub target: Option<Material>,
    /// Output directory.
    pub out: PathBuf,
    /// Add `/coverage` to the impact file.
    pub update_h5: bool,
    /// Seed to use from a file pooling several seeds (a sweep case); default: the first.
    pub seed: Option<u64>,
    /// A moving nozzle: coverage per pass and per raster ([`traverse`]).
    pub traverse: Option<Traverse>,
    /// Measured dents instead of the material's model (`--dent-curve`).
    pub dent: Option<DentModel>,
}

/// The study's result, for printing.
#[derive(Debug, Clone)]
pub struct Report {
    /// Dent model used.
    pub model: DentModel,
    /// Target material name.
    pub target: String,
    /// Dents (impacts with a positive normal speed).
    pub dents: usize,
    /// Median dent diameter, m (on a curved part, that of the disc of a dent's area).
    pub median_dent_diameter: f64,
    /// On a curved part (a bar, a groove's fillets and edges): the dents' ratio of the
    /// axis across to the axis along, `[min, median, max]` (`None` on the plate, where
    /// dents are round).
    pub dent_aspect: Option<[f64; 3]>,
    /// The coverage.
    pub coverage: Coverage,
    /// Files written.
    pub written: Vec<PathBuf>,
    /// The seed used and how many the file holds (a sweep case pools several).
    pub seed: (u64, usize),
    /// Coverage under the moving nozzle, when asked.
    pub track: Option<Track>,
    /// Whether the run's feed is a steady stream (what [`traverse`] assumes).
    pub steady_feed: bool,
    /// The window's coordinates: the plane's `x`, `y`, or a cylinder's unrolled surface.
    pub axes: (&'static str, &'static str),
    /// On a grooved specimen: the coverage of each zone the window spans, from `-x` to
    /// `+x` (a zone met twice, on both sides of the groove, once per side).
    pub zones: Vec<ZoneCoverage>,
}

/// The coverage of one zone of a grooved specimen inside the window.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ZoneCoverage {
    /// `bottom`, `fillet`, `flank`, `edge` or `land`.
    pub zone: &'static str,
    /// Its span across the groove inside the window, m of arc `[from, to]`.
    pub across_m: [f64; 2],
    /// Cells of the window in it.
    pub cells: usize,
    /// Their covered fraction at the end of the run.
    pub coverage: f64,
}

/// The coverage of each of `spans` (a groove's zones across the window) from the cells
/// whose centres fall in it.
fn zone_coverage(
    cov: &super::Coverage,
    spans: &[(f64, f64, crate::contact::groove::Zone)],
) -> Vec<ZoneCoverage> {
    spans
        .iter()
        .map(|&(a, b, z)| {
            let (mut cells, mut covered) = (0usize, 0usize);
            for i in 0..cov.nx {
                let x = cov.window[0] + (i as f64 + 0.5) * cov.cell;
                if x < a || x >= b {
                    continue;
                }
                for j in 0..cov.ny {
                    cells += 1;
                    covered += (cov.counts[j * cov.nx + i] > 0) as usize;
                }
            }
            ZoneCoverage {
                zone: z.name(),
                across_m: [a, b],
                cells,
                coverage: if cells > 0 {
                    covered as f64 / cells as f64
                } else {
                    0.0
                },
            }
        })
        .filter(|z| z.cells > 0)
        .collect()
}

/// Errors of the coverage command.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum CoverageError {
    /// Reading or writing HDF5.
    #[error(transparent)]
    H5(#[from] H5Error),
    /// The scene stored in the file.
    #[error(transparent)]
    Export(#[from] crate::export::ExportError),
    /// Plots.
    #[error(transparent)]
    Plot(#[from] PlotError),
    /// Other files.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// Nothing to compute.
    #[error("{path}: {message}")]
    Empty {
        /// File.
        path: String,
        /// Why.
        message: String,
    },
}

/// The target material and the dent model asked (`--target-material`,
/// `--dent-curve`), or the scene's.
fn target_and_model(
    target: Option<&Material>,
    dent: Option<&DentModel>,
    scene: &Scene,
) -> (Material, DentModel) {
    let target = target
        .cloned()
        .unwrap_or_else(|| scene.specimen_material.clone());
    let model = dent
        .cloned()
        .unwrap_or_else(|| DentModel::for_pair(&scene.shot_material, &target));
    (target, model)
}

/// The dents of one seed's run in an impact file (all of them where the file does not
/// name seeds per impact).
fn seed_dents(
    file: &h5::ImpactFile,
    seed: u64,
    model: &DentModel,
    scene: &Scene,
) -> Vec<super::Dent> {
    let impacts: Vec<crate::record::Impact> = file
        .impacts
        .iter()
        .enumerate()
        .filter(|(i, _)| file.seeds.get(*i).is_none_or(|s| *s == seed))
        .map(|(_, imp)| imp.clone())
        .collect();
    dents_on(&impacts, model, &scene.specimen_shape)
}

/// Runs the study.
pub fn run(req: &Request) -> Result<Report, CoverageError> {
    let (file, scene): (h5::ImpactFile, Scene) = crate::export::read_impact_file(&req.impacts)?;
    // In a groove only a nozzle moving along it keeps the still nozzle's pattern: moving
    // across, it meets the flanks and fillets at other angles and distances.
    if let (Some(tr), crate::contact::specimen::SpecimenShape::Groove(_)) =
        (req.traverse, &scene.specimen_shape)
        && tr.direction.cos().abs() > 1e-9
    {
        return Err(CoverageError::Empty {
            path: req.impacts.display().to_string(),
            message: format!(
                "--traverse-deg {}: in a groove the nozzle can only move along it (--traverse-deg 90 or -90, the unrolled surface's y): moving across, it meets the flanks and fillets at other angles, so the still nozzle's pattern does not carry over",
                tr.direction_deg()
            ),
        });
    }
    let (target, model) = target_and_model(req.target.as_ref(), req.dent.as_ref(), &scene);
    let shown = req.impacts.display().to_string();
    // A sweep case pools several seeds (independent repeats of the same exposure): the
    // coverage is that of one of them.
    let mut seeds: Vec<u64> = file.seeds.clone();
    seeds.sort_unstable();
    seeds.dedup();
    let seed = match req.seed {
        Some(s) if seeds.contains(&s) => s,
        Some(s) => {
            return Err(CoverageError::Empty {
                path: shown,
                message: format!(
                    "--seed {s}: the file holds seeds {}",
                    seeds
                        .iter()
                        .map(|s| s.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            });
        }
        None => seeds.first().copied().unwrap_or(file.seed),
    };
    let dents_of = |seed: u64| seed_dents(&file, seed, &model, &scene);
    let ds = dents_of(seed);
    if ds.is_empty() {
        return Err(CoverageError::Empty {
            path: shown,
            message: "no impact with a positive normal speed: nothing dents the specimen".into(),
        });
    }
    let mut radii: Vec<f64> = ds.iter().map(super::Dent::radius).collect();
    radii.sort_by(f64::total_cmp);
    let median_r = crate::summary::percentile(&radii, 50.0);
    let dent_aspect = (!scene.specimen_shape.is_plane()).then(|| {
        let mut a: Vec<f64> = ds.iter().map(|d| d.rx / d.ry).collect();
        a.sort_by(f64::total_cmp);
        [a[0], crate::summary::percentile(&a, 50.0), a[a.len() - 1]]
    });
    let window = match req.window {
        Some(w) => w,
        None => default_window(&ds).expect("BUG: dents are not empty"),
    };
    let cell = req.cell.unwrap_or(median_r / 5.0);
    let t_end = scene.duration;
    let cov = compute(&ds, window, cell, t_end);
    let spans = match &scene.specimen_shape {
        crate::contact::specimen::SpecimenShape::Groove(g) => {
            g.zone_spans(cov.window[0], cov.window[2])
        }
        _ => Vec::new(),
    };
    let zones = zone_coverage(&cov, &spans);
    let mut written = Vec::new();
    // The moving nozzle pools a sweep case's seeds (independent runs of the same still
    // nozzle) unless one was chosen.
    let runs: Vec<Vec<super::Dent>> = if req.seed.is_none() && seeds.len() > 1 {
        seeds.iter().map(|&s| dents_of(s)).collect()
    } else {
        vec![ds.clone()]
    };
    let track = match req.traverse {
        Some(tr) => {
            let runs: Vec<&[super::Dent]> = runs.iter().map(|r| r.as_slice()).collect();
            let band = BAND_DIAMETERS * 2.0 * median_r;
            Some(
                Track::pooled(&runs, tr, median_r / 5.0, band).ok_or_else(|| {
                    CoverageError::Empty {
                        path: shown.clone(),
                        message: "--traverse-mm-s needs at least two dents at different times in each run (a dent rate)".into(),
                    }
                })?,
            )
        }
        None => None,
    };
    let steady_feed = matches!(scene.feed, crate::scene::Feed::Stream { .. });
    if let Some(t) = &track {
        written.extend(write_track(&req.out, t)?);
    }
    // coverage.csv
    let mut csv = String::from("exposure_time_s,coverage,avrami_fit\n");
    for (t, c) in &cov.curve {
        let f = cov
            .fit
            .map(|f| format!("{}", f.coverage(*t)))
            .unwrap_or_default();
        csv.push_str(&format!("{t},{c},{f}\n"));
    }
    let p = req.out.join("coverage.csv");
    crate::output::write_atomic(&p, csv.as_bytes())?;
    written.push(p);
    // coverage.json
    let json = serde_json::json!({
        "impacts": shown,
        "target": target.name,
        "dent_model": model.describe(),
        "seed": seed,
        "dents": ds.len(),
        "dents_in_window": cov.dents_in_window,
        "median_dent_diameter_m": 2.0 * median_r,
        "dent_aspect_across_along": dent_aspect,
        "window_m": cov.window,
        "cell_m": cov.cell,
        "cells": [cov.nx, cov.ny],
        "first_impact_s": cov.t0,
        "exposure_s": cov.exposure,
        "final_coverage": cov.final_coverage,
        "avrami": cov.fit,
        "time_to_98_percent_fit_s": cov.fit.map(|f| f.time_to(0.98)),
        "time_to_98_percent_measured_s": cov.t98_measured,
        "traverse": track.as_ref().map(track_json),
    });
    let mut json = json;
    if !zones.is_empty() {
        json["zones"] = serde_json::to_value(&zones).expect("BUG: json");
    }
    let p = req.out.join("coverage.json");
    let mut bytes = serde_json::to_vec_pretty(&json).expect("BUG: json");
    bytes.push(b'\n');
    crate::output::write_atomic(&p, &bytes)?;
    written.push(p);
    // Map and curve.
    let marks: Vec<(f64, f64, &str)> = spans
        .iter()
        .map(|&(a, b, z)| (a * 1e3, b * 1e3, z.name()))
        .collect();
    let values: Vec<f64> = cov.counts.iter().map(|&c| c as f64).collect();
    let stem = req.out.join("coverage_map");
    plot::heatmap(
        &stem,
        &format!(
            "coverage {:.1} % ({} dents, {:.2} ms exposure)",
            100.0 * cov.final_coverage,
            cov.dents_in_window,
            cov.exposure * 1e3
        ),
        (
            &format!("{}, mm", scene.specimen_shape.unrolled_names().0),
            &format!("{}, mm", scene.specimen_shape.unrolled_names().1),
        ),
        &Field {
            extent: [
                window[0] * 1e3,
                window[2] * 1e3,
                window[1] * 1e3,
                window[3] * 1e3,
            ],
            nx: cov.nx,
            ny: cov.ny,
            values: &values,
            label: "dents per cell",
            spans: &marks,
        },
    )?;
    written.push(stem.with_extension("png"));
    let mut series = vec![Series {
        name: "simulated".into(),
        points: cov
            .curve
            .iter()
            .map(|(t, c)| (t * 1e3, 100.0 * c))
            .collect(),
    }];
    if let Some(f) = cov.fit {
        series.push(Series {
            name: format!("1 - exp(-k t^n), n = {:.2}", f.n),
            points: cov
                .curve
                .iter()
                .map(|(t, _)| (t * 1e3, 100.0 * f.coverage(*t)))
                .collect(),
        });
    }
    let stem = req.out.join("coverage_curve");
    plot::lines(
        &stem,
        "coverage against exposure time",
        ("exposure time since the first impact, ms", "coverage, %"),
        &series,
        false,
    )?;
    written.push(stem.with_extension("png"));
    if req.update_h5 {
        add_to_h5(
            &req.impacts,
            &cov,
            track.as_ref(),
            &model,
            &target.name,
            dent_aspect,
        )?;
        written.push(req.impacts.clone());
    }
    Ok(Report {
        model,
        target: target.name,
        dents: ds.len(),
        median_dent_diameter: 2.0 * median_r,
        dent_aspect,
        coverage: cov,
        written,
        seed: (seed, seeds.len().max(1)),
        track,
        steady_feed,
        axes: scene.specimen_shape.unrolled_names(),
        zones,
    })
}

/// The moving nozzle's numbers for coverage.json.
fn track_json(t: &Track) -> serde_json::Value {
    let peak = t.peak();
    let full = t.full_coverage();
    serde_json::json!({
        "speed_m_s": t.traverse.speed,
        "direction_deg": t.traverse.direction_deg(),
        "pitch_m": t.traverse.pitch,
        "dents": t.dents,
        "runs": t.runs,
        "dent_rate_per_s": t.rate,
        "one_pass": {
            "peak_dents_per_point": peak.dents,
            "peak_standard_error": peak.se,
            "peak_offset_m": peak.offset,
            "peak_coverage": traverse::coverage(peak.dents),
            "width_98_percent_m": t.width(0.98),
            "width_50_percent_m": t.width(0.5),
        },
        "raster": t.raster_range().map(|(least, mean)| serde_json::json!({
            "least_dents_per_point": least.dents,
            "least_standard_error": least.se,
            "least_offset_m": least.offset,
            "mean_dents_per_point": mean,
            "least_coverage": traverse::coverage(least.dents),
            "mean_coverage": traverse::coverage(mean),
        })),
        "full_coverage_speed_m_s": full.map(|f| f.0),
        "passes_for_full_coverage": full.map(|f| f.1),
    })
}

/// traverse.csv (one pass across the track), raster.csv (one pitch of a raster) and
/// the plot of coverage across the track.
fn write_track(out: &Path, t: &Track) -> Result<Vec<PathBuf>, CoverageError> {
    let mut written = Vec::new();
    let rows = |pts: &[Point]| {
        let mut csv =
            String::from("lateral_offset_m,dents_per_point,standard_error,coverage,times_full\n");
        for p in pts {
            csv.push_str(&format!(
                "{},{},{},{},{}\n",
                p.offset,
                p.dents,
                p.se,
                traverse::coverage(p.dents),
                p.dents / traverse::FULL
            ));
        }
        csv
    };
    let p = out.join("traverse.csv");
    crate::output::write_atomic(&p, rows(&t.pass).as_bytes())?;
    written.push(p);
    let v_mm_s = t.traverse.speed * 1e3;
    // The plot shows the core of the track (rebound hits scatter far and thin).
    let (lo, hi) = t.core;
    let shown = |w: f64| (lo..=hi).contains(&w);
    let mut series = vec![Series {
        name: format!("one pass at {v_mm_s} mm/s"),
        points: t
            .pass
            .iter()
            .filter(|p| shown(p.offset))
            .map(|p| (p.offset * 1e3, 100.0 * traverse::coverage(p.dents)))
            .collect(),
    }];
    if let (Some(r), Some(pitch)) = (&t.raster, t.traverse.pitch) {
        let p = out.join("raster.csv");
        crate::output::write_atomic(&p, rows(r).as_bytes())?;
        written.push(p);
        // The raster's profile repeats every pitch.
        let (first, last) = ((lo / pitch).floor() as i64, (hi / pitch).ceil() as i64);
        let points = (first..last)
            .flat_map(|k| {
                r.iter()
                    .map(move |p| (p.offset + k as f64 * pitch, p.dents))
            })
            .filter(|p| shown(p.0))
            .map(|(w, n)| (w * 1e3, 100.0 * traverse::coverage(n)))
            .collect();
        series.push(Series {
            name: format!("raster, passes {} mm apart", pitch * 1e3),
            points,
        });
    }
    let stem = out.join("traverse");
    plot::lines(
        &stem,
        &format!(
            "coverage across the track: nozzle at {v_mm_s} mm/s towards {} deg",
            t.traverse.direction_deg()
        ),
        ("offset from the jet axis' line, mm", "coverage, %"),
        &series,
        false,
    )?;
    written.push(stem.with_extension("png"));
    Ok(written)
}

/// Adds (or replaces) `/coverage` in the impact file: a copy is updated and renamed
/// over the original, so a failure leaves the original untouched.
fn add_to_h5(
    path: &Path,
    cov: &Coverage,
    track: Option<&Track>,
    model: &DentModel,
    target: &str,
    dent_aspect: Option<[f64; 3]>,
) -> Result<(), H5Error> {
    let err = |m: String| H5Error::Write {
        path: path.display().to_string(),
        message: m,
    };
    h5::write_atomic(path, |tmp| {
        std::fs::copy(path, tmp).map_err(|e| err(e.to_string()))?;
        let e = werr(path);
        let file = rust_hdf5::H5File::open_rw(tmp).map_err(&e)?;
        let existing = file.root_group().group_names().map_err(&e)?;
        if existing
            .iter()
            .any(|n| n.trim_start_matches('/') == "coverage")
        {
            file.delete_group("coverage").map_err(&e)?;
        }
        let g = file.create_group("coverage").map_err(&e)?;
        g.set_attr_string("dent_model", &model.describe())
            .map_err(&e)?;
        g.set_attr_string("target", target).map_err(&e)?;
        g.set_attr_array_numeric("window_m", &cov.window)
            .map_err(&e)?;
        g.set_attr_numeric("cell_m", &cov.cell).map_err(&e)?;
        g.set_attr_numeric("final_coverage", &cov.final_coverage)
            .map_err(&e)?;
        g.set_attr_numeric("first_impact_s", &cov.t0).map_err(&e)?;
        if let Some(a) = dent_aspect {
            g.set_attr_array_numeric("dent_aspect_across_along", &a)
                .map_err(&e)?;
        }
        if let Some(f) = cov.fit {
            g.set_attr_numeric("avrami_k", &f.k).map_err(&e)?;
            g.set_attr_numeric("avrami_n", &f.n).map_err(&e)?;
            g.set_attr_numeric("time_to_98_percent_fit_s", &f.time_to(0.98))
                .map_err(&e)?;
        }
        let counts = g
            .new_dataset::<u32>()
            .shape([cov.ny, cov.nx])
            .create("dent_count")
            .map_err(&e)?;
        counts.write_raw(&cov.counts).map_err(&e)?;
        counts
            .new_attr::<rust_hdf5::VarLenUnicode>()
            .shape(())
            .create("description")
            .and_then(|a| {
                a.write_string("dents per cell; row j spans y0 + j cell .. y0 + (j+1) cell")
            })
            .map_err(&e)?;
        let first = g
            .new_dataset::<f64>()
            .shape([cov.ny, cov.nx])
            .create("first_dent_time_s")
            .map_err(&e)?;
        let ft: Vec<f64> = cov
            .first_time
            .iter()
            .map(|t| if t.is_finite() { *t } else { f64::NAN })
            .collect();
        first.write_raw(&ft).map_err(&e)?;
        write_columns(
            &g,
            &[
                Column::F64(
                    "curve_time_s",
                    "s",
                    "exposure time since the first impact",
                    cov.curve.iter().map(|p| p.0).collect(),
                ),
                Column::F64(
                    "curve_coverage",
                    "1",
                    "share of the window dented at least once",
                    cov.curve.iter().map(|p| p.1).collect(),
                ),
            ],
            path,
        )?;
        if let Some(t) = track {
            add_track(&g, t, path)?;
        }
        file.close().map_err(&e)?;
        Ok(())
    })
}

/// `/coverage/traverse`: the moving nozzle's parameters as attributes, one pass's
/// profile (`pass_*`) and, with a pitch, the raster's over one pitch (`raster_*`).
fn add_track(g: &rust_hdf5::H5Group, t: &Track, path: &Path) -> Result<(), H5Error> {
    let e = werr(path);
    let tg = g.create_group("traverse").map_err(&e)?;
    tg.set_attr_numeric("speed_m_s", &t.traverse.speed)
        .map_err(&e)?;
    tg.set_attr_numeric("direction_deg", &t.traverse.direction_deg())
        .map_err(&e)?;
    if let Some(p) = t.traverse.pitch {
        tg.set_attr_numeric("pitch_m", &p).map_err(&e)?;
    }
    tg.set_attr_numeric("dent_rate_per_s", &t.rate)
        .map_err(&e)?;
    tg.set_attr_numeric("band_m", &t.band).map_err(&e)?;
    if let Some((v, passes)) = t.full_coverage() {
        tg.set_attr_numeric("full_coverage_speed_m_s", &v)
            .map_err(&e)?;
        tg.set_attr_numeric("passes_for_full_coverage", &passes)
            .map_err(&e)?;
    }
    let columns = |prefix: &'static [&'static str; 3], pts: &[Point]| {
        [
            Column::F64(
                prefix[0],
                "m",
                "lateral offset, to the left of the line the jet axis follows",
                pts.iter().map(|p| p.offset).collect(),
            ),
            Column::F64(
                prefix[1],
                "1",
                "expected dents per point (coverage 1 - exp(-n))",
                pts.iter().map(|p| p.dents).collect(),
            ),
            Column::F64(
                prefix[2],
                "1",
                "standard error of the expected dents per point",
                pts.iter().map(|p| p.se).collect(),
            ),
        ]
    };
    write_columns(
        &tg,
        &columns(
            &["pass_offset_m", "pass_dents", "pass_standard_error"],
            &t.pass,
        ),
        path,
    )?;
    if let Some(r) = &t.raster {
        write_columns(
            &tg,
            &columns(
                &["raster_offset_m", "raster_dents", "raster_standard_error"],
                r,
            ),
            path,
        )?;
    }
    Ok(())
}

/// Everything `peenflow coverage --gear-teeth` was asked.
#[derive(Debug, Clone)]
pub struct GearRequest {
    /// Impact files of still-nozzle runs on one rack at several offsets.
    pub impacts: Vec<PathBuf>,
    /// Target material (default: the scenes' specimen).
    pub target: Option<Material>,
    /// Measured dents instead of the material's model (`--dent-curve`).
    pub dent: Option<DentModel>,
    /// Output directory.
    pub out: PathBuf,
    /// The gear and the nozzle's speed along its axis.
    pub turning: Turning,
    /// The gear's speed, revolutions per minute (the helical bands' check).
    pub rpm: Option<f64>,
}

/// A turning gear's coverage, for printing.
#[derive(Debug, Clone)]
pub struct GearReport {
    /// Dent model used.
    pub model: DentModel,
    /// Target material name.
    pub target: String,
    /// Dents over all files.
    pub dents: usize,
    /// Median dent diameter, m.
    pub median_dent_diameter: f64,
    /// The profile over one period.
    pub profile: GearProfile,
    /// The profile zone by zone.
    pub zones: Vec<ZoneDents>,
    /// The zone (and side) of the least covered point.
    pub least_zone: String,
    /// Whether every run's feed is a steady stream.
    pub steady_feed: bool,
    /// With the gear's speed: the largest helical banding.
    pub banding: Option<Banding>,
    /// Files written.
    pub written: Vec<PathBuf>,
}

/// The helical bands of a turning gear ([`GearProfile::new`]'s `feed`).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Banding {
    /// The gear's speed, rev/min.
    pub rpm: f64,
    /// The nozzle's advance per revolution, m.
    pub feed_per_revolution_m: f64,
    /// The rms amplitude of the dents' variation along the axis over their mean, over
    /// the whole profile.
    pub rms: Bandwidth,
    /// The same zone by zone, in order across the tooth space (`flank -`, `fillet -`,
    /// `bottom`, ...).
    pub zones: Vec<(String, Bandwidth)>,
}

/// An rms band amplitude estimated from the runs' dents.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Bandwidth {
    /// The estimate, `sqrt(max(0, mean power))`.
    pub rms: f64,
    /// Three standard errors of the mean power, as an amplitude: the estimate is the
    /// runs' noise where `rms` is below it (three, not two: a profile has eight zones
    /// to look at).
    pub noise: f64,
}

impl Bandwidth {
    fn of(b: &super::gear::Bands, idx: impl Iterator<Item = usize>, correlated: f64) -> Self {
        let (p, se) = b.mean_power(idx, correlated);
        Bandwidth {
            rms: p.max(0.0).sqrt(),
            noise: (3.0 * se).sqrt(),
        }
    }

    /// Whether the bands stand out of the noise.
    pub fn resolved(&self) -> bool {
        self.rms > self.noise
    }
}

impl Banding {
    /// The zone with the strongest bands that stand out of the noise, or where none
    /// does, the one whose noise level is highest (the bound that holds everywhere).
    pub fn worst(&self) -> (&str, Bandwidth) {
        let key = |w: &Bandwidth| {
            if w.resolved() {
                (1, w.rms)
            } else {
                (0, w.noise)
            }
        };
        self.zones
            .iter()
            .max_by(|a, b| {
                let (ka, kb) = (key(&a.1), key(&b.1));
                ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1))
            })
            .map(|(n, w)| (n.as_str(), *w))
            .unwrap_or((
                "",
                Bandwidth {
                    rms: 0.0,
                    noise: 0.0,
                },
            ))
    }
}

/// ` -` or ` +` after a zone's name for its side of the tooth space (nothing for the
/// bottom and the tooth top).
pub fn side_word(side: &str) -> String {
    if side.is_empty() {
        String::new()
    } else {
        format!(" {side}")
    }
}

/// A turning gear's coverage from still-nozzle runs at several offsets of one rack
/// ([`super::gear`]): gear.csv, gear.json and the profile's figure.
pub fn run_gear(req: &GearRequest) -> Result<GearReport, CoverageError> {
    use crate::contact::specimen::SpecimenShape;
    let empty = |path: &Path, message: String| CoverageError::Empty {
        path: path.display().to_string(),
        message,
    };
    let mut read = Vec::with_capacity(req.impacts.len());
    for path in &req.impacts {
        let (file, scene) = crate::export::read_impact_file(path)?;
        let groove = match &scene.specimen_shape {
            SpecimenShape::Groove(g) => **g,
            other => {
                return Err(empty(
                    path,
                    format!(
                        "--gear-teeth: the specimen is a {}; a turning gear needs runs on a rack ([specimen] shape = \"groove\" with pitch_mm) or on the gear (shape = \"gear\")",
                        match other {
                            SpecimenShape::Plane => "plane",
                            _ => "cylinder",
                        }
                    ),
                ));
            }
        };
        if groove.size().pitch.is_none() {
            return Err(empty(
                path,
                "--gear-teeth: [specimen] pitch_mm is left out (one groove); a gear's tooth spaces repeat: give the rack's pitch".into(),
            ));
        }
        if let Some(g) = groove.gear()
            && g.teeth() != req.turning.teeth
        {
            return Err(empty(
                path,
                format!(
                    "--gear-teeth {}: the runs' gear has {} teeth ([specimen] teeth); give --gear-teeth {}",
                    req.turning.teeth,
                    g.teeth(),
                    g.teeth()
                ),
            ));
        }
        read.push((path, file, scene, groove));
    }
    let (path0, _, scene0, groove0) = &read[0];
    let unmoved = |g: &crate::contact::groove::Groove| {
        let mut s = *g.size();
        s.offset = 0.0;
        s
    };
    for (path, _, scene, groove) in &read[1..] {
        if unmoved(groove) != unmoved(groove0) {
            return Err(empty(
                path,
                format!(
                    "--gear-teeth: its groove differs from {}'s in more than offset_mm: the runs must be of one rack, set at different offsets",
                    path0.display()
                ),
            ));
        }
        for (what, a, b) in [
            (
                "specimen",
                &scene.specimen_material.name,
                &scene0.specimen_material.name,
            ),
            (
                "shot",
                &scene.shot_material.name,
                &scene0.shot_material.name,
            ),
        ] {
            if a != b {
                return Err(empty(
                    path,
                    format!(
                        "--gear-teeth: its {what} material is {a}, {}'s is {b}: the runs must peen one gear with one shot",
                        path0.display()
                    ),
                ));
            }
        }
    }
    let (target, model) = target_and_model(req.target.as_ref(), req.dent.as_ref(), scene0);
    // Each file's dents, seed by seed.
    let per_file: Vec<(f64, Vec<Vec<super::Dent>>)> = read
        .iter()
        .map(|(_, file, scene, groove)| {
            let mut seeds = file.seeds.clone();
            seeds.sort_unstable();
            seeds.dedup();
            if seeds.is_empty() {
                seeds.push(file.seed);
            }
            let runs = seeds
                .iter()
                .map(|&s| seed_dents(file, s, &model, scene))
                .collect();
            (groove.size().offset, runs)
        })
        .collect();
    let mut radii: Vec<f64> = per_file
        .iter()
        .flat_map(|(_, runs)| runs.iter().flatten().map(super::Dent::radius))
        .collect();
    if radii.is_empty() {
        return Err(empty(
            path0,
            "no impact with a positive normal speed in any file: nothing dents the gear".into(),
        ));
    }
    radii.sort_by(f64::total_cmp);
    let median_r = crate::summary::percentile(&radii, 50.0);
    let offsets: Vec<OffsetRuns> = per_file
        .iter()
        .map(|(o, runs)| OffsetRuns {
            offset: *o,
            runs: runs.iter().map(Vec::as_slice).collect(),
        })
        .collect();
    let pitch = groove0.size().pitch.expect("BUG: checked above");
    let period = groove0.period_arc().expect("BUG: a rack has a period");
    let band = BAND_DIAMETERS * 2.0 * median_r;
    let profile = GearProfile::new(
        &offsets,
        pitch,
        period,
        req.turning,
        median_r / 5.0,
        band,
        req.rpm.map(|rpm| req.turning.speed * 60.0 / rpm),
    )
    .map_err(|e| {
        // Name the files the message is about.
        let files = req
            .impacts
            .iter()
            .map(|p| p.display().to_string())
            .collect::<Vec<_>>()
            .join(", ");
        CoverageError::Empty {
            path: files,
            message: format!("--gear-teeth: {e}"),
        }
    })?;
    let zones = profile.zones(groove0);
    let least = profile.least();
    let least_zone = zones
        .iter()
        .find(|z| z.least_dents == least.dents && z.least_arc_m == least.offset)
        .map(|z| format!("{}{}", z.zone, side_word(z.side)))
        .unwrap_or_else(|| groove0.zone_at(least.offset).name().to_string());
    let banding = match (&profile.banding, req.rpm) {
        (Some(b), Some(rpm)) => {
            let n = profile.points.len();
            // Points within a dent and the band of each other share most dents.
            let correlated = (2.0 * median_r + band) / profile.spacing;
            Some(Banding {
                rpm,
                feed_per_revolution_m: b.feed,
                rms: Bandwidth::of(b, 0..n, correlated),
                zones: profile
                    .stretches(groove0)
                    .iter()
                    .map(|st| {
                        let name = format!("{}{}", st.zone.name(), side_word(st.side));
                        (
                            name,
                            Bandwidth::of(b, st.points.iter().copied(), correlated),
                        )
                    })
                    .collect(),
            })
        }
        _ => None,
    };
    let steady_feed = read
        .iter()
        .all(|(_, _, s, _)| matches!(s.feed, crate::scene::Feed::Stream { .. }));
    let mut written = Vec::new();
    // gear.csv
    let amplitude = profile.banding.as_ref().map(super::gear::Bands::amplitude);
    let mut csv = String::from("arc_m,zone,dents_per_point,standard_error,coverage,times_full");
    csv.push_str(if amplitude.is_some() {
        ",banding\n"
    } else {
        "\n"
    });
    for (i, p) in profile.points.iter().enumerate() {
        csv.push_str(&format!(
            "{},{},{},{},{},{}",
            p.offset,
            groove0.zone_at(p.offset).name(),
            p.dents,
            p.se,
            traverse::coverage(p.dents),
            p.dents / traverse::FULL
        ));
        match &amplitude {
            Some(a) => csv.push_str(&format!(",{}\n", a[i])),
            None => csv.push('\n'),
        }
    }
    let p = req.out.join("gear.csv");
    crate::output::write_atomic(&p, csv.as_bytes())?;
    written.push(p);
    // gear.json
    let full = profile.full_coverage();
    let files: Vec<serde_json::Value> = req
        .impacts
        .iter()
        .zip(&profile.offsets)
        .map(|(p, s)| {
            serde_json::json!({
                "impacts": p.display().to_string(),
                "offset_m": s.offset_m,
                "weight": s.weight,
                "dents": s.dents,
                "runs": s.runs,
                "dent_rate_per_s": s.dent_rate_per_s,
            })
        })
        .collect();
    let teeth = f64::from(req.turning.teeth);
    let json = serde_json::json!({
        "target": target.name,
        "dent_model": model.describe(),
        "teeth": req.turning.teeth,
        "speed_along_axis_m_s": req.turning.speed,
        "pitch_m": pitch,
        "period_arc_m": period,
        "pitch_radius_m": teeth * pitch / std::f64::consts::TAU,
        "spacing_m": profile.spacing,
        "band_m": profile.band,
        "median_dent_diameter_m": 2.0 * median_r,
        "offsets": files,
        "mean_dents_per_point": profile.mean(),
        "least": {
            "dents_per_point": least.dents,
            "standard_error": least.se,
            "arc_m": least.offset,
            "zone": least_zone,
            "coverage": traverse::coverage(least.dents),
        },
        "full_coverage_speed_m_s": full.map(|f| f.0),
        "passes_for_full_coverage": full.map(|f| f.1),
        "zones": zones,
        "banding": banding,
        "steady_feed": steady_feed,
    });
    let p = req.out.join("gear.json");
    let mut bytes = serde_json::to_vec_pretty(&json).expect("BUG: json");
    bytes.push(b'\n');
    crate::output::write_atomic(&p, &bytes)?;
    written.push(p);
    // The profile's figure: one pass, and the passes full coverage takes.
    let v_mm_s = req.turning.speed * 1e3;
    let curve = |passes: f64| -> Vec<(f64, f64)> {
        profile
            .points
            .iter()
            .map(|p| (p.offset * 1e3, 100.0 * traverse::coverage(passes * p.dents)))
            .collect()
    };
    let mut series = vec![Series {
        name: format!("one pass at {v_mm_s} mm/s"),
        points: curve(1.0),
    }];
    if let Some((_, k)) = full
        && k > 1
    {
        series.push(Series {
            name: format!("{k} passes (98 % everywhere)"),
            points: curve(k as f64),
        });
    }
    let spans: Vec<(f64, f64, &str)> = groove0
        .zone_spans(-0.5 * period, 0.5 * period)
        .iter()
        .map(|&(a, b, z)| (a * 1e3, b * 1e3, z.name()))
        .collect();
    let stem = req.out.join("gear");
    plot::lines_marked(
        &stem,
        &format!(
            "turning gear, {} teeth: coverage across a tooth space, nozzle at {v_mm_s} mm/s along the axis",
            req.turning.teeth
        ),
        ("arc from the tooth space's middle, mm", "coverage, %"),
        &series,
        &spans,
    )?;
    written.push(stem.with_extension("png"));
    Ok(GearReport {
        model,
        target: target.name,
        dents: radii.len(),
        median_dent_diameter: 2.0 * median_r,
        profile,
        zones,
        least_zone,
        steady_feed,
        banding,
        written,
    })
}
