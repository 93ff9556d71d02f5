//! impacts.h5: the run's impact records, shots and summary in HDF5, written with the
//! pure-Rust `rust-hdf5` crate (no system library), read back by `peenflow export`.
//!
//! Layout (one 1-D dataset per field, the form h5py, pandas and ParaView's XDMF reader
//! take most easily; every dataset has a `units` and a `description` attribute):
//! ```text
//! /                      attrs: format, tool, tool_version, seed, title, scene (TOML),
//!                               scene_path, simulated_time_s, summary_json,
//!                               specimen_shape ("plane" or "cylinder"; a cylinder's
//!                               specimen_radius_m and specimen_axis_deg: its axis runs
//!                               at that angle from +x through (0, 0, -radius))
//! /impacts/<column>      the columns of impacts.csv, one value per impact
//! /shots/<column>        every shot's final state (status_code: 0 active, 1 left the
//!                        domain, 2 failed), in the order of shots.csv: by the time
//!                        the shot stopped, then id; shots in the domain at the end last
//! /never_hit/<column>    the same columns for the shots that never reached the specimen
//! /summary/normal_speed_histogram/{lower_edges, counts}, /summary/radius_histogram/...
//! /summary/jet_loading   attrs: summary.json's `jet_loading`, one per field (a stream's
//!                        or a batch's runs in the jet)
//! ```
//! The file is written under a temporary name and renamed when closed. A table that fits
//! in one block of 8,192 rows is stored as contiguous datasets; a longer one as chunked
//! datasets (8,192-row chunks) extended block by block while the run goes, so the writer
//! never holds more than a block per table.

use crate::record::Impact;
use crate::state::{ShotState, ShotStatus};
use crate::summary::{Histogram, Summary};
use rust_hdf5::{H5File, H5Group};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Format tag stored in the root attribute `format`.
pub const FORMAT: &str = "peenflow-impacts/1";

/// HDF5 errors, naming the file.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum H5Error {
    /// Writing failed.
    #[error("{path}: cannot write HDF5: {message}")]
    Write {
        /// File.
        path: String,
        /// Cause.
        message: String,
    },
    /// Reading failed or the file is not a peenflow impact file.
    #[error("{path}: cannot read impacts: {message}")]
    Read {
        /// File.
        path: String,
        /// Cause.
        message: String,
    },
}

/// One column: name, units, description, values.
pub(crate) enum Column {
    F64(&'static str, &'static str, &'static str, Vec<f64>),
    U64(&'static str, &'static str, &'static str, Vec<u64>),
    U32(&'static str, &'static str, &'static str, Vec<u32>),
    U8(&'static str, &'static str, &'static str, Vec<u8>),
}

pub(crate) fn impact_columns(v: &[Impact]) -> Vec<Column> {
    use Column::*;
    let f = |g: fn(&Impact) -> f64| v.iter().map(g).collect::<Vec<f64>>();
    vec![
        U32(
            "shot",
            "1",
            "shot id (0-based, feed order)",
            v.iter().map(|i| i.shot).collect(),
        ),
        F64("time_s", "s", "first-contact time", f(|i| i.time_s)),
        F64(
            "x_m",
            "m",
            "contact point x (specimen plane z = 0, jet axis x = y = 0)",
            f(|i| i.x_m),
        ),
        F64("y_m", "m", "contact point y", f(|i| i.y_m)),
        F64("z_m", "m", "contact point z", f(|i| i.z_m)),
        F64(
            "vx_m_s",
            "m/s",
            "velocity x at first contact",
            f(|i| i.vx_m_s),
        ),
        F64(
            "vy_m_s",
            "m/s",
            "velocity y at first contact",
            f(|i| i.vy_m_s),
        ),
        F64(
            "vz_m_s",
            "m/s",
            "velocity z at first contact",
            f(|i| i.vz_m_s),
        ),
        F64("speed_m_s", "m/s", "impact speed", f(|i| i.speed_m_s)),
        F64(
            "normal_speed_m_s",
            "m/s",
            "normal impact speed towards the specimen",
            f(|i| i.normal_speed_m_s),
        ),
        F64(
            "angle_deg",
            "deg",
            "impact angle from the specimen normal",
            f(|i| i.angle_deg),
        ),
        F64("diameter_m", "m", "shot diameter", f(|i| i.diameter_m)),
        U8(
            "first_hit",
            "1",
            "1: the shot's first impact, 0: a rebound hit",
            v.iter().map(|i| i.first_hit).collect(),
        ),
        F64(
            "tangential_speed_m_s",
            "m/s",
            "speed along the specimen",
            f(|i| i.tangential_speed_m_s),
        ),
        F64(
            "center_x_m",
            "m",
            "shot centre x at first contact",
            f(|i| i.center_x_m),
        ),
        F64(
            "center_y_m",
            "m",
            "shot centre y at first contact",
            f(|i| i.center_y_m),
        ),
        F64(
            "center_z_m",
            "m",
            "shot centre z at first contact",
            f(|i| i.center_z_m),
        ),
        F64("mass_kg", "kg", "shot mass", f(|i| i.mass_kg)),
        F64(
            "kinetic_energy_j",
            "J",
            "kinetic energy at first contact",
            f(|i| i.kinetic_energy_j),
        ),
        U32(
            "collisions_before",
            "1",
            "shot-shot collisions before this impact",
            v.iter().map(|i| i.collisions_before).collect(),
        ),
        F64(
            "omega_x_rad_s",
            "rad/s",
            "angular velocity x at first contact (0 without the friction effect)",
            f(|i| i.omega_x_rad_s),
        ),
        F64(
            "omega_y_rad_s",
            "rad/s",
            "angular velocity y at first contact",
            f(|i| i.omega_y_rad_s),
        ),
        F64(
            "omega_z_rad_s",
            "rad/s",
            "angular velocity z at first contact",
            f(|i| i.omega_z_rad_s),
        ),
    ]
}

fn status_code(s: ShotStatus) -> u8 {
    match s {
        ShotStatus::Active => 0,
        ShotStatus::LeftDomain => 1,
        ShotStatus::Failed => 2,
    }
}

fn shot_columns(v: &[&ShotState]) -> Vec<Column> {
    use Column::*;
    let f = |g: fn(&ShotState) -> f64| v.iter().map(|s| g(s)).collect::<Vec<f64>>();
    vec![
        U32("shot", "1", "shot id", v.iter().map(|s| s.id.0).collect()),
        U8(
            "status_code",
            "1",
            "0: active at the end, 1: left the domain, 2: stopped by a failure",
            v.iter().map(|s| status_code(s.status)).collect(),
        ),
        F64(
            "t_start_s",
            "s",
            "time the shot entered the run",
            f(|s| s.t_start),
        ),
        F64(
            "t_stop_s",
            "s",
            "time the shot was stopped (NaN: ran to the end)",
            f(|s| s.t_stop.unwrap_or(f64::NAN)),
        ),
        U32(
            "hits",
            "1",
            "specimen contacts",
            v.iter().map(|s| s.hits).collect(),
        ),
        U32(
            "collisions",
            "1",
            "shot-shot contacts",
            v.iter().map(|s| s.collisions).collect(),
        ),
        U32(
            "wall_contacts",
            "1",
            "nozzle-wall contacts",
            v.iter().map(|s| s.wall_contacts).collect(),
        ),
        F64("x_m", "m", "final centre x", f(|s| s.pos.x)),
        F64("y_m", "m", "final centre y", f(|s| s.pos.y)),
        F64("z_m", "m", "final centre z", f(|s| s.pos.z)),
        F64("vx_m_s", "m/s", "final velocity x", f(|s| s.vel.x)),
        F64("vy_m_s", "m/s", "final velocity y", f(|s| s.vel.y)),
        F64("vz_m_s", "m/s", "final velocity z", f(|s| s.vel.z)),
        F64("diameter_m", "m", "diameter", f(|s| 2.0 * s.body.radius)),
        F64(
            "omega_x_rad_s",
            "rad/s",
            "final angular velocity x (0 without the friction effect)",
            f(|s| s.omega.x),
        ),
        F64(
            "omega_y_rad_s",
            "rad/s",
            "final angular velocity y",
            f(|s| s.omega.y),
        ),
        F64(
            "omega_z_rad_s",
            "rad/s",
            "final angular velocity z",
            f(|s| s.omega.z),
        ),
    ]
}

pub(crate) fn werr(path: &Path) -> impl Fn(rust_hdf5::Hdf5Error) -> H5Error + '_ {
    move |e| H5Error::Write {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

/// A 1-D dataset holding `v` (empty datasets are created but not written).
fn dataset<T: rust_hdf5::types::H5Type + Copy>(
    g: &H5Group,
    name: &str,
    v: &[T],
    e: &impl Fn(rust_hdf5::Hdf5Error) -> H5Error,
) -> Result<rust_hdf5::H5Dataset, H5Error> {
    let ds = g
        .new_dataset::<T>()
        .shape([v.len()])
        .create(name)
        .map_err(e)?;
    if !v.is_empty() {
        ds.write_raw(v).map_err(e)?;
    }
    Ok(ds)
}

pub(crate) fn write_columns(g: &H5Group, cols: &[Column], path: &Path) -> Result<(), H5Error> {
    let e = werr(path);
    for c in cols {
        let (ds, units, desc) = match c {
            Column::F64(n, u, d, v) => (dataset(g, n, v, &e)?, u, d),
            Column::U64(n, u, d, v) => (dataset(g, n, v, &e)?, u, d),
            Column::U32(n, u, d, v) => (dataset(g, n, v, &e)?, u, d),
            Column::U8(n, u, d, v) => (dataset(g, n, v, &e)?, u, d),
        };
        describe(&ds, units, desc, &e)?;
    }
    Ok(())
}

/// The `units` and `description` attributes of a column dataset.
fn describe(
    ds: &rust_hdf5::H5Dataset,
    units: &str,
    desc: &str,
    e: &impl Fn(rust_hdf5::Hdf5Error) -> H5Error,
) -> Result<(), H5Error> {
    ds.new_attr::<rust_hdf5::VarLenUnicode>()
        .shape(())
        .create("units")
        .and_then(|a| a.write_string(units))
        .map_err(e)?;
    ds.new_attr::<rust_hdf5::VarLenUnicode>()
        .shape(())
        .create("description")
        .and_then(|a| a.write_string(desc))
        .map_err(e)?;
    Ok(())
}

pub(crate) fn write_histogram(
    g: &H5Group,
    name: &str,
    h: &Histogram,
    units: &'static str,
    path: &Path,
) -> Result<(), H5Error> {
    let e = werr(path);
    let hg = g.create_group(name).map_err(&e)?;
    hg.set_attr_string("quantity", &h.quantity).map_err(&e)?;
    hg.set_attr_numeric("bin_width", &h.bin_width).map_err(&e)?;
    hg.set_attr_numeric("overflow", &(h.overflow as u64))
        .map_err(&e)?;
    let counts: Vec<u64> = h.counts.iter().map(|&c| c as u64).collect();
    write_columns(
        &hg,
        &[Column::F64(
            "lower_edges",
            units,
            "lower bin edges",
            h.lower_edges.clone(),
        )],
        path,
    )?;
    let ds = hg
        .new_dataset::<u64>()
        .shape([counts.len()])
        .create("counts")
        .map_err(&e)?;
    ds.write_raw(&counts).map_err(&e)?;
    Ok(())
}

fn temp_path(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp"))
}

/// Everything impacts.h5 holds.
pub struct ImpactFileData<'a> {
    /// The root attributes.
    pub head: FileHead<'a>,
    /// Impacts.
    pub impacts: &'a [Impact],
    /// Final shot states.
    pub shots: &'a [ShotState],
    /// Run summary.
    pub summary: &'a Summary,
    /// Seed of each impact and of each shot, when the file pools several runs (a sweep
    /// case); written as `impacts/seed` and `shots/seed`.
    pub seeds: Option<(&'a [u64], &'a [u64])>,
}

/// Writes impacts.h5 atomically.
pub fn write(path: &Path, d: &ImpactFileData<'_>) -> Result<(), H5Error> {
    write_atomic(path, |tmp| write_inner(tmp, path, d))
}

/// Runs `write` on a temporary file next to `path` and renames it to `path` when it
/// succeeds (removes it when it fails): readers never see a half-written file.
pub(crate) fn write_atomic(
    path: &Path,
    write: impl FnOnce(&Path) -> Result<(), H5Error>,
) -> Result<(), H5Error> {
    let tmp = temp_path(path);
    let result = write(&tmp);
    match result {
        Ok(()) => std::fs::rename(&tmp, path).map_err(|e| H5Error::Write {
            path: path.display().to_string(),
            message: e.to_string(),
        }),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

fn write_inner(tmp: &Path, shown: &Path, d: &ImpactFileData<'_>) -> Result<(), H5Error> {
    let mut w = Tables::create(tmp, shown, d.seeds.is_some())?;
    w.impacts(d.impacts, d.seeds.map(|s| s.0))?;
    w.shots(d.shots, d.seeds.map(|s| s.1))?;
    w.finish(&d.head, d.summary)
}

/// Rows per block when a table is written as it comes: a table that fits in one block
/// is written as contiguous datasets (small runs); longer tables as chunked datasets
/// extended block by block, so the writer holds at most one block per table.
const BLOCK: usize = 8192;

/// One group of 1-D column datasets, filled as rows come.
struct Table<T> {
    group: H5Group,
    columns: fn(&[T]) -> Vec<Column>,
    rows: Vec<T>,
    seeds: Option<Vec<u64>>,
    sets: Option<Vec<rust_hdf5::H5Dataset>>,
}

fn seed_col(v: Vec<u64>) -> Column {
    Column::U64(
        "seed",
        "1",
        "seed of the run the row comes from (files pooling several seeds)",
        v,
    )
}

impl<T: Clone> Table<T> {
    fn new(group: H5Group, columns: fn(&[T]) -> Vec<Column>, seeded: bool) -> Self {
        Table {
            group,
            columns,
            rows: Vec::new(),
            seeds: seeded.then(Vec::new),
            sets: None,
        }
    }

    fn push(&mut self, row: &T, seed: Option<u64>, shown: &Path) -> Result<(), H5Error> {
        self.rows.push(row.clone());
        if let (Some(v), Some(s)) = (&mut self.seeds, seed) {
            v.push(s);
        }
        if self.rows.len() == BLOCK {
            self.flush(shown)?;
        }
        Ok(())
    }

    fn block(&self) -> Vec<Column> {
        let mut cols = (self.columns)(&self.rows);
        if let Some(s) = &self.seeds {
            cols.push(seed_col(s.clone()));
        }
        cols
    }

    /// Appends the buffered rows to chunked datasets (created at the first block).
    fn flush(&mut self, shown: &Path) -> Result<(), H5Error> {
        let e = werr(shown);
        let cols = self.block();
        if self.sets.is_none() {
            fn chunked<T: rust_hdf5::types::H5Type>(
                g: &H5Group,
                name: &str,
            ) -> rust_hdf5::Result<rust_hdf5::H5Dataset> {
                g.new_dataset::<T>()
                    .shape([0])
                    .chunk(&[BLOCK])
                    .resizable()
                    .create(name)
            }
            let mut sets = Vec::with_capacity(cols.len());
            for c in &cols {
                let (ds, units, desc) = match c {
                    Column::F64(n, u, d, _) => (chunked::<f64>(&self.group, n), u, d),
                    Column::U64(n, u, d, _) => (chunked::<u64>(&self.group, n), u, d),
                    Column::U32(n, u, d, _) => (chunked::<u32>(&self.group, n), u, d),
                    Column::U8(n, u, d, _) => (chunked::<u8>(&self.group, n), u, d),
                };
                let ds = ds.map_err(&e)?;
                describe(&ds, units, desc, &e)?;
                sets.push(ds);
            }
            self.sets = Some(sets);
        }
        let sets = self.sets.as_ref().expect("BUG: datasets just created");
        for (ds, c) in sets.iter().zip(&cols) {
            match c {
                Column::F64(.., v) => ds.append(v),
                Column::U64(.., v) => ds.append(v),
                Column::U32(.., v) => ds.append(v),
                Column::U8(.., v) => ds.append(v),
            }
            .map_err(&e)?;
        }
        self.rows.clear();
        if let Some(v) = &mut self.seeds {
            v.clear();
        }
        Ok(())
    }

    fn finish(mut self, shown: &Path) -> Result<(), H5Error> {
        if self.sets.is_none() {
            write_columns(&self.group, &self.block(), shown)
        } else if !self.rows.is_empty() {
            self.flush(shown)
        } else {
            Ok(())
        }
    }
}

/// The root attributes of impacts.h5.
pub struct FileHead<'a> {
    /// Scene TOML text.
    pub scene_text: &'a str,
    /// Scene file name.
    pub scene_path: &'a str,
    /// Scene title.
    pub title: &'a str,
    /// Seed.
    pub seed: u64,
    /// Simulated time, s.
    pub simulated_time: f64,
    /// The specimen's surface (root attributes `specimen_shape`, and for a cylinder
    /// `specimen_radius_m` and `specimen_axis_deg`).
    pub specimen: &'a crate::contact::specimen::SpecimenShape,
}

/// The three tables of impacts.h5 being written.
struct Tables {
    file: H5File,
    shown: PathBuf,
    impacts: Table<Impact>,
    shots: Table<ShotState>,
    never_hit: Table<ShotState>,
}

fn shot_table(v: &[ShotState]) -> Vec<Column> {
    shot_columns(&v.iter().collect::<Vec<_>>())
}

impl Tables {
    fn create(tmp: &Path, shown: &Path, seeded: bool) -> Result<Self, H5Error> {
        let e = werr(shown);
        let file = H5File::create(tmp).map_err(&e)?;
        let root = file.root_group();
        let g = |name: &str| root.create_group(name).map_err(&e);
        Ok(Tables {
            impacts: Table::new(g("impacts")?, impact_columns, seeded),
            shots: Table::new(g("shots")?, shot_table, seeded),
            never_hit: Table::new(g("never_hit")?, shot_table, seeded),
            shown: shown.to_path_buf(),
            file,
        })
    }

    fn impacts(&mut self, v: &[Impact], seeds: Option<&[u64]>) -> Result<(), H5Error> {
        for (k, i) in v.iter().enumerate() {
            self.impacts.push(i, seeds.map(|s| s[k]), &self.shown)?;
        }
        Ok(())
    }

    fn shots(&mut self, v: &[ShotState], seeds: Option<&[u64]>) -> Result<(), H5Error> {
        for (k, s) in v.iter().enumerate() {
            let seed = seeds.map(|x| x[k]);
            self.shots.push(s, seed, &self.shown)?;
            if s.hits == 0 {
                self.never_hit.push(s, seed, &self.shown)?;
            }
        }
        Ok(())
    }

    fn finish(self, head: &FileHead<'_>, summary: &Summary) -> Result<(), H5Error> {
        let shown = self.shown.as_path();
        let e = werr(shown);
        self.impacts.finish(shown)?;
        self.shots.finish(shown)?;
        self.never_hit.finish(shown)?;
        let file = self.file;
        file.set_attr_string("format", FORMAT).map_err(&e)?;
        file.set_attr_string("tool", "peenflow").map_err(&e)?;
        file.set_attr_string("tool_version", env!("CARGO_PKG_VERSION"))
            .map_err(&e)?;
        file.set_attr_numeric("seed", &head.seed).map_err(&e)?;
        file.set_attr_string("title", head.title).map_err(&e)?;
        file.set_attr_string("scene", head.scene_text).map_err(&e)?;
        file.set_attr_string("scene_path", head.scene_path)
            .map_err(&e)?;
        file.set_attr_numeric("simulated_time_s", &head.simulated_time)
            .map_err(&e)?;
        // The specimen's surface for scripts that do not read the scene's TOML.
        use crate::contact::specimen::SpecimenShape;
        match head.specimen {
            SpecimenShape::Plane => {
                file.set_attr_string("specimen_shape", "plane")
                    .map_err(&e)?;
            }
            SpecimenShape::Cylinder { radius, axis } => {
                file.set_attr_string("specimen_shape", "cylinder")
                    .map_err(&e)?;
                file.set_attr_numeric("specimen_radius_m", radius)
                    .map_err(&e)?;
                file.set_attr_numeric("specimen_axis_deg", &axis.y.atan2(axis.x).to_degrees())
                    .map_err(&e)?;
            }
            SpecimenShape::Groove(g) => {
                let z = g.size();
                let shape = if g.gear().is_some() { "gear" } else { "groove" };
                file.set_attr_string("specimen_shape", shape).map_err(&e)?;
                if let Some(gear) = g.gear() {
                    // A gear's: its teeth, module and pitch, root, tip and base radii;
                    // the groove's attributes below are its cutting rack's.
                    let (r_p, r_f, r_a, r_b) = gear.radii();
                    for (name, value) in [
                        ("specimen_teeth", gear.teeth() as f64),
                        (
                            "specimen_module_m",
                            z.pitch.unwrap_or(0.0) / std::f64::consts::PI,
                        ),
                        ("specimen_pitch_radius_m", r_p),
                        ("specimen_root_radius_m", r_f),
                        ("specimen_tip_radius_m", r_a),
                        ("specimen_base_radius_m", r_b),
                    ] {
                        file.set_attr_numeric(name, &value).map_err(&e)?;
                    }
                }
                for (name, value) in [
                    ("specimen_radius_m", z.radius),
                    ("specimen_bottom_m", z.bottom),
                    ("specimen_flank_deg", z.flank.to_degrees()),
                    ("specimen_depth_m", z.depth),
                    ("specimen_edge_radius_m", z.edge_radius),
                    // 0: one groove, its lands running on for ever.
                    ("specimen_pitch_m", z.pitch.unwrap_or(0.0)),
                    ("specimen_axis_deg", z.axis_angle.to_degrees()),
                    // The groove's middle, across from the jet axis' foot.
                    ("specimen_offset_m", z.offset),
                ] {
                    file.set_attr_numeric(name, &value).map_err(&e)?;
                }
            }
        }
        let json = serde_json::to_string(summary).expect("BUG: summary serialises");
        file.set_attr_string("summary_json", &json).map_err(&e)?;
        let g = file.root_group().create_group("summary").map_err(&e)?;
        g.set_attr_numeric("hit_fraction", &summary.hit_fraction)
            .map_err(&e)?;
        g.set_attr_numeric("shots", &(summary.shots as u64))
            .map_err(&e)?;
        g.set_attr_numeric("shots_hit", &(summary.shots_hit as u64))
            .map_err(&e)?;
        if let Some(loading) = &summary.jet_loading {
            // One attribute per field of summary.json's `jet_loading`.
            let l = g.create_group("jet_loading").map_err(&e)?;
            let fields = serde_json::to_value(loading).expect("BUG: loading serialises");
            for (name, value) in fields.as_object().expect("BUG: a struct") {
                match value {
                    serde_json::Value::String(text) => l.set_attr_string(name, text),
                    serde_json::Value::Number(n) => match n.as_u64() {
                        Some(count) => l.set_attr_numeric(name, &count),
                        None => l.set_attr_numeric(name, &n.as_f64().expect("BUG: a number")),
                    },
                    other => unreachable!("BUG: jet_loading field {name} = {other}"),
                }
                .map_err(&e)?;
            }
        }
        write_histogram(
            &g,
            "normal_speed_histogram",
            &summary.normal_speed_histogram,
            "m/s",
            shown,
        )?;
        write_histogram(
            &g,
            "radius_histogram",
            &summary.radius_histogram,
            "mm",
            shown,
        )?;
        file.close().map_err(&e)?;
        Ok(())
    }
}

/// impacts.h5 written as a run hands over its records (see [`crate::sim::RunSink`]):
/// under a temporary name, renamed by [`ImpactStream::finish`], removed if dropped
/// unfinished. Holds at most one block of rows per table.
pub struct ImpactStream {
    tables: Option<Tables>,
    tmp: PathBuf,
    path: PathBuf,
}

impl ImpactStream {
    /// Starts writing `path`.
    pub fn create(path: &Path) -> Result<Self, H5Error> {
        let tmp = temp_path(path);
        Ok(ImpactStream {
            tables: Some(Tables::create(&tmp, path, false)?),
            tmp,
            path: path.to_path_buf(),
        })
    }

    /// Appends impacts (in the order they are to be stored).
    pub fn impacts(&mut self, v: &[Impact]) -> Result<(), H5Error> {
        self.tables
            .as_mut()
            .expect("BUG: impact stream used after finish")
            .impacts(v, None)
    }

    /// Appends one final shot state (to `shots`, and to `never_hit` if it never hit).
    pub fn shot(&mut self, s: &ShotState) -> Result<(), H5Error> {
        self.tables
            .as_mut()
            .expect("BUG: impact stream used after finish")
            .shots(std::slice::from_ref(s), None)
    }

    /// Writes the root attributes and the summary, closes the file and renames it.
    pub fn finish(mut self, head: &FileHead<'_>, summary: &Summary) -> Result<(), H5Error> {
        let tables = self
            .tables
            .take()
            .expect("BUG: impact stream finished twice");
        // `tables` writes to `self.tmp`, the name `write_atomic` renames (or removes).
        write_atomic(&self.path, move |_| tables.finish(head, summary))
    }
}

impl Drop for ImpactStream {
    fn drop(&mut self) {
        if let Some(t) = self.tables.take() {
            drop(t);
            let _ = std::fs::remove_file(&self.tmp);
        }
    }
}

/// What `peenflow export` needs from an impact file.
#[derive(Debug, Clone)]
pub struct ImpactFile {
    /// Scene TOML text.
    pub scene_text: String,
    /// Seed.
    pub seed: u64,
    /// Tool version that wrote it.
    pub tool_version: String,
    /// Impact records.
    pub impacts: Vec<Impact>,
    /// Seed of each impact: the file's seed, or the `impacts/seed` column of a file
    /// pooling several seeds (a sweep case).
    pub seeds: Vec<u64>,
}

/// The name of a run's impact file in its output directory.
pub const IMPACT_FILE: &str = "impacts.h5";

/// Reads an impact file written by [`write()`].
pub fn read(path: &Path) -> Result<ImpactFile, H5Error> {
    let shown = path.display().to_string();
    let err = |m: String| H5Error::Read {
        path: shown.clone(),
        message: m,
    };
    if !path.exists() {
        return Err(err("no such file".into()));
    }
    // A run's directory, or another of its files (impacts.csv), for its impact file: name
    // the file meant.
    let run_file = |p: std::path::PathBuf| p.is_file().then(|| p.display().to_string());
    if path.is_dir() {
        return Err(err(match run_file(path.join(IMPACT_FILE)) {
            Some(f) => format!("is a directory; pass the run's impact file, {f}"),
            None => format!("is a directory, not an impact file (a run's {IMPACT_FILE})"),
        }));
    }
    let file = H5File::open(path).map_err(|e| {
        let beside = path.file_name().is_some_and(|n| n != IMPACT_FILE);
        err(
            match run_file(path.with_file_name(IMPACT_FILE)).filter(|_| beside) {
                Some(f) => format!("not a readable HDF5 file ({e}); the run's impact file is {f}"),
                None => format!("not a readable HDF5 file ({e})"),
            },
        )
    })?;
    let format = file
        .attr_string("format")
        .map_err(|_| err("no `format` attribute: not written by peenflow".into()))?;
    if format != FORMAT {
        return Err(err(format!("format `{format}`, expected `{FORMAT}`")));
    }
    let scene_text = file
        .attr_string("scene")
        .map_err(|e| err(format!("attribute scene: {e}")))?;
    let tool_version = file.attr_string("tool_version").unwrap_or_default();
    // The root `seed` attribute is numeric for h5py users; the reader takes it from the
    // stored summary, which carries the same value.
    let summary: serde_json::Value = file
        .attr_string("summary_json")
        .ok()
        .and_then(|s| serde_json::from_str(&s).ok())
        .ok_or_else(|| err("attribute summary_json missing or not JSON".into()))?;
    let seed = summary["seed"]
        .as_u64()
        .ok_or_else(|| err("summary_json has no seed".into()))?;
    let f64s = |name: &str| -> Result<Vec<f64>, H5Error> {
        file.dataset(&format!("impacts/{name}"))
            .and_then(|d| {
                if d.total_elements() == 0 {
                    Ok(vec![])
                } else {
                    d.read_raw::<f64>()
                }
            })
            .map_err(|e| err(format!("dataset impacts/{name}: {e}")))
    };
    let u32s = |name: &str| -> Result<Vec<u32>, H5Error> {
        file.dataset(&format!("impacts/{name}"))
            .and_then(|d| {
                if d.total_elements() == 0 {
                    Ok(vec![])
                } else {
                    d.read_raw::<u32>()
                }
            })
            .map_err(|e| err(format!("dataset impacts/{name}: {e}")))
    };
    let shot = u32s("shot")?;
    let n = shot.len();
    let cols: Vec<Vec<f64>> = [
        "time_s",
        "x_m",
        "y_m",
        "z_m",
        "vx_m_s",
        "vy_m_s",
        "vz_m_s",
        "speed_m_s",
        "normal_speed_m_s",
        "angle_deg",
        "diameter_m",
        "tangential_speed_m_s",
        "center_x_m",
        "center_y_m",
        "center_z_m",
        "mass_kg",
        "kinetic_energy_j",
    ]
    .iter()
    .map(|c| f64s(c))
    .collect::<Result<_, _>>()?;
    let first_hit: Vec<u8> = file
        .dataset("impacts/first_hit")
        .and_then(|d| {
            if d.total_elements() == 0 {
                Ok(vec![])
            } else {
                d.read_raw::<u8>()
            }
        })
        .map_err(|e| err(format!("dataset impacts/first_hit: {e}")))?;
    let collisions = u32s("collisions_before")?;
    // Files written before spin was recorded have no omega columns: zero spin.
    let spin: Vec<Vec<f64>> = ["omega_x_rad_s", "omega_y_rad_s", "omega_z_rad_s"]
        .iter()
        .map(|c| {
            if file.dataset(&format!("impacts/{c}")).is_ok() {
                f64s(c)
            } else {
                Ok(vec![0.0; n])
            }
        })
        .collect::<Result<_, _>>()?;
    let seeds: Vec<u64> = if file.dataset("impacts/seed").is_ok() {
        file.dataset("impacts/seed")
            .and_then(|d| {
                if d.total_elements() == 0 {
                    Ok(vec![])
                } else {
                    d.read_raw::<u64>()
                }
            })
            .map_err(|e| err(format!("dataset impacts/seed: {e}")))?
    } else {
        vec![seed; n]
    };
    if cols.iter().any(|c| c.len() != n)
        || first_hit.len() != n
        || collisions.len() != n
        || seeds.len() != n
        || spin.iter().any(|c| c.len() != n)
    {
        return Err(err(
            "impact columns have different lengths (corrupt file)".into()
        ));
    }
    let impacts = (0..n)
        .map(|k| Impact {
            shot: shot[k],
            time_s: cols[0][k],
            x_m: cols[1][k],
            y_m: cols[2][k],
            z_m: cols[3][k],
            vx_m_s: cols[4][k],
            vy_m_s: cols[5][k],
            vz_m_s: cols[6][k],
            speed_m_s: cols[7][k],
            normal_speed_m_s: cols[8][k],
            angle_deg: cols[9][k],
            diameter_m: cols[10][k],
            first_hit: first_hit[k],
            tangential_speed_m_s: cols[11][k],
            center_x_m: cols[12][k],
            center_y_m: cols[13][k],
            center_z_m: cols[14][k],
            mass_kg: cols[15][k],
            kinetic_energy_j: cols[16][k],
            collisions_before: collisions[k],
            omega_x_rad_s: spin[0][k],
            omega_y_rad_s: spin[1][k],
            omega_z_rad_s: spin[2][k],
        })
        .collect();
    Ok(ImpactFile {
        scene_text,
        seed,
        tool_version,
        impacts,
        seeds,
    })
}
