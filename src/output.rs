//! Output files of a run: impacts.csv, impacts.h5, shots.csv and summary.json, each written under a
//! temporary name and renamed when complete, so a killed run never leaves a truncated file.

use crate::record::Impact;
use crate::scene::Scene;
use crate::sim::{RunOutput, RunSink};
use crate::state::ShotState;
use crate::summary::Summary;
use serde::Serialize;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Output errors.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum OutputError {
    /// The output directory exists and holds files.
    #[error(
        "{path}: output directory exists and is not empty; pass --force to overwrite its files or choose another --out"
    )]
    Exists {
        /// Directory.
        path: String,
    },
    /// The output path exists and is not a directory.
    #[error("{path}: exists and is not a directory; choose another --out")]
    NotADirectory {
        /// Path.
        path: String,
    },
    /// Creating or writing failed.
    #[error("{path}: cannot write: {source}")]
    Io {
        /// File or directory.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// The HDF5 writer failed.
    #[error(transparent)]
    Hdf5(#[from] crate::export::hdf5::H5Error),
    /// CSV serialisation failed.
    #[error("{path}: cannot write CSV: {source}")]
    Csv {
        /// File.
        path: String,
        /// Cause.
        source: csv::Error,
    },
}

fn io(path: &Path) -> impl FnOnce(std::io::Error) -> OutputError + '_ {
    move |source| OutputError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Makes sure `dir` can take a run's outputs: created if missing, refused if it holds
/// files and `force` is not set. Call before the run starts.
pub fn prepare_dir(dir: &Path, force: bool) -> Result<(), OutputError> {
    if dir.exists() {
        if !dir.is_dir() {
            return Err(OutputError::NotADirectory {
                path: dir.display().to_string(),
            });
        }
        let non_empty = fs::read_dir(dir).map_err(io(dir))?.next().is_some();
        if non_empty && !force {
            return Err(OutputError::Exists {
                path: dir.display().to_string(),
            });
        }
    } else {
        fs::create_dir_all(dir).map_err(io(dir))?;
    }
    // Probe writability now rather than after a long run.
    let probe = dir.join(".peenflow-write-test");
    fs::write(&probe, b"").map_err(io(dir))?;
    let _ = fs::remove_file(&probe);
    Ok(())
}

/// Prepares the output directory `dir` ([`prepare_dir`]) and runs `f`; if `f` fails
/// and `dir` was created for it and is still empty, removes it again, so that a command
/// refused after reading its input leaves nothing behind.
pub fn with_dir<T, E: From<OutputError>>(
    dir: &Path,
    force: bool,
    f: impl FnOnce() -> Result<T, E>,
) -> Result<T, E> {
    let created = !dir.exists();
    prepare_dir(dir, force)?;
    let result = f();
    if result.is_err() && created {
        // Fails, as it should, if anything was written.
        let _ = fs::remove_dir(dir);
    }
    result
}

/// Writes `bytes` to `path` atomically (temporary file in the same directory, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), OutputError> {
    let tmp = temp_name(path);
    let result = (|| {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result.map_err(io(path))
}

/// A CSV file written row by row under a temporary name, renamed by
/// [`CsvStream::finish`] (removed if dropped unfinished): the table is never held in
/// memory.
struct CsvStream {
    w: Option<csv::Writer<std::io::BufWriter<fs::File>>>,
    header: &'static str,
    empty: bool,
    tmp: PathBuf,
    path: PathBuf,
}

impl CsvStream {
    fn create(path: &Path, header: &'static str) -> Result<Self, OutputError> {
        let tmp = temp_name(path);
        let file = fs::File::create(&tmp).map_err(io(path))?;
        Ok(CsvStream {
            w: Some(csv::Writer::from_writer(std::io::BufWriter::new(file))),
            header,
            empty: true,
            tmp,
            path: path.to_path_buf(),
        })
    }

    fn row<T: Serialize>(&mut self, r: T) -> Result<(), OutputError> {
        self.empty = false;
        self.w
            .as_mut()
            .expect("BUG: CSV stream used after finish")
            .serialize(r)
            .map_err(|source| OutputError::Csv {
                path: self.path.display().to_string(),
                source,
            })
    }

    fn finish(mut self) -> Result<(), OutputError> {
        let w = self.w.take().expect("BUG: CSV stream finished twice");
        let path = self.path.clone();
        let result = (|| {
            let mut buf = w.into_inner().map_err(|e| OutputError::Io {
                path: path.display().to_string(),
                source: e.into_error(),
            })?;
            if self.empty {
                // serde writes the header with the first row: write it alone.
                buf.write_all(self.header.as_bytes()).map_err(io(&path))?;
            }
            let file = buf.into_inner().map_err(|e| OutputError::Io {
                path: path.display().to_string(),
                source: e.into_error(),
            })?;
            file.sync_all().map_err(io(&path))?;
            fs::rename(&self.tmp, &path).map_err(io(&path))
        })();
        if result.is_err() {
            let _ = fs::remove_file(&self.tmp);
        }
        result
    }
}

impl Drop for CsvStream {
    fn drop(&mut self) {
        if self.w.take().is_some() {
            let _ = fs::remove_file(&self.tmp);
        }
    }
}

fn temp_name(path: &Path) -> PathBuf {
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    path.with_file_name(format!(".{name}.tmp"))
}

fn csv_bytes<T: Serialize>(
    path: &Path,
    rows: impl IntoIterator<Item = T>,
) -> Result<Vec<u8>, OutputError> {
    let err = |source| OutputError::Csv {
        path: path.display().to_string(),
        source,
    };
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in rows {
        w.serialize(r).map_err(err)?;
    }
    w.into_inner().map_err(|e| OutputError::Io {
        path: path.display().to_string(),
        source: e.into_error(),
    })
}

/// impacts.csv: one row per shot-specimen contact (see [`Impact`] for the columns).
pub fn impacts_csv(impacts: &[Impact], path: &Path) -> Result<Vec<u8>, OutputError> {
    if impacts.is_empty() {
        // Header only: serde writes headers with the first row.
        return Ok(IMPACT_HEADER.as_bytes().to_vec());
    }
    csv_bytes(path, impacts)
}

/// Header of impacts.csv.
pub const IMPACT_HEADER: &str = "shot,time_s,x_m,y_m,z_m,vx_m_s,vy_m_s,vz_m_s,speed_m_s,normal_speed_m_s,angle_deg,diameter_m,first_hit,tangential_speed_m_s,center_x_m,center_y_m,center_z_m,mass_kg,kinetic_energy_j,collisions_before,omega_x_rad_s,omega_y_rad_s,omega_z_rad_s\n";

/// Header of shots.csv (written alone when a run has no shot).
pub const SHOT_HEADER: &str = "shot,status,t_start_s,t_stop_s,hits,collisions,wall_contacts,x_m,y_m,z_m,vx_m_s,vy_m_s,vz_m_s,speed_m_s,diameter_m,steps,steps_to_first_contact,first_contact_steps,omega_x_rad_s,omega_y_rad_s,omega_z_rad_s\n";

/// One row of shots.csv: a shot's final state and history.
#[derive(Debug, Serialize)]
pub struct ShotRow {
    /// Shot id.
    pub shot: u32,
    /// active / left_domain / failed.
    pub status: crate::state::ShotStatus,
    /// Entry time, s.
    pub t_start_s: f64,
    /// Time the shot was stopped, s (empty if it ran to the end).
    pub t_stop_s: Option<f64>,
    /// Specimen contacts.
    pub hits: u32,
    /// Shot-shot contacts.
    pub collisions: u32,
    /// Wall contacts.
    pub wall_contacts: u32,
    /// Final centre x, m.
    pub x_m: f64,
    /// Final centre y, m.
    pub y_m: f64,
    /// Final centre z, m.
    pub z_m: f64,
    /// Final velocity x, m/s.
    pub vx_m_s: f64,
    /// Final velocity y, m/s.
    pub vy_m_s: f64,
    /// Final velocity z, m/s.
    pub vz_m_s: f64,
    /// Final speed, m/s.
    pub speed_m_s: f64,
    /// Diameter, m.
    pub diameter_m: f64,
    /// Accepted steps.
    pub steps: u64,
    /// Steps to the first specimen contact (empty if none).
    pub steps_to_first_contact: Option<u64>,
    /// Steps during the first specimen contact.
    pub first_contact_steps: u64,
    /// Final angular velocity x, rad/s (0 without the friction effect).
    pub omega_x_rad_s: f64,
    /// Final angular velocity y, rad/s.
    pub omega_y_rad_s: f64,
    /// Final angular velocity z, rad/s.
    pub omega_z_rad_s: f64,
}

impl From<&ShotState> for ShotRow {
    fn from(s: &ShotState) -> Self {
        ShotRow {
            shot: s.id.0,
            status: s.status,
            t_start_s: s.t_start,
            t_stop_s: s.t_stop,
            hits: s.hits,
            collisions: s.collisions,
            wall_contacts: s.wall_contacts,
            x_m: s.pos.x,
            y_m: s.pos.y,
            z_m: s.pos.z,
            vx_m_s: s.vel.x,
            vy_m_s: s.vel.y,
            vz_m_s: s.vel.z,
            speed_m_s: s.vel.norm(),
            diameter_m: 2.0 * s.body.radius,
            steps: s.steps,
            steps_to_first_contact: s.steps_to_first_contact,
            first_contact_steps: s.first_contact_steps,
            omega_x_rad_s: s.omega.x,
            omega_y_rad_s: s.omega.y,
            omega_z_rad_s: s.omega.z,
        }
    }
}

/// Writes impacts.csv, impacts.h5, shots.csv and summary.json into `dir`.
pub fn write_run(
    dir: &Path,
    scene: &Scene,
    out: &RunOutput,
    summary: &Summary,
) -> Result<(), OutputError> {
    let mut w = RunWriter::create(dir)?;
    w.impacts(&out.impacts);
    let mut shots: Vec<&ShotState> = out.shots.iter().collect();
    shots.sort_by(|a, b| crate::sim::stop_order(a, b));
    for s in shots {
        w.shot(s);
    }
    w.finish(scene, out.end_time, summary)
}

/// A run's impacts.csv, shots.csv and impacts.h5 written as the run hands over its
/// records (a [`RunSink`]), then summary.json: every file under a temporary name until
/// [`RunWriter::finish`] renames it, removed if the writer is dropped unfinished. The
/// first write error stops the writing and is returned by `finish`.
pub struct RunWriter {
    dir: PathBuf,
    impacts_csv: CsvStream,
    shots_csv: CsvStream,
    h5: crate::export::hdf5::ImpactStream,
    error: Option<OutputError>,
}

impl RunWriter {
    /// Starts the files in `dir` (see [`prepare_dir`]).
    pub fn create(dir: &Path) -> Result<Self, OutputError> {
        Ok(RunWriter {
            impacts_csv: CsvStream::create(&dir.join("impacts.csv"), IMPACT_HEADER)?,
            shots_csv: CsvStream::create(&dir.join("shots.csv"), SHOT_HEADER)?,
            h5: crate::export::hdf5::ImpactStream::create(
                &dir.join(crate::export::hdf5::IMPACT_FILE),
            )?,
            dir: dir.to_path_buf(),
            error: None,
        })
    }

    fn keep(&mut self, r: Result<(), OutputError>) {
        if let Err(e) = r
            && self.error.is_none()
        {
            self.error = Some(e);
        }
    }

    /// Completes the files with the run's simulated time and summary.
    pub fn finish(
        self,
        scene: &Scene,
        simulated_time: f64,
        summary: &Summary,
    ) -> Result<(), OutputError> {
        let RunWriter {
            dir,
            impacts_csv,
            shots_csv,
            h5,
            error,
        } = self;
        if let Some(e) = error {
            return Err(e);
        }
        impacts_csv.finish()?;
        shots_csv.finish()?;
        h5.finish(
            &crate::export::hdf5::FileHead {
                scene_text: &scene.text,
                scene_path: &scene.path,
                title: &scene.title,
                seed: scene.seed,
                simulated_time,
                specimen: &scene.specimen_shape,
            },
            summary,
        )?;
        let mut json = serde_json::to_vec_pretty(summary).expect("BUG: summary serialises");
        json.push(b'\n');
        write_atomic(&dir.join("summary.json"), &json)
    }
}

impl RunSink for RunWriter {
    fn impacts(&mut self, batch: &[Impact]) {
        if self.error.is_some() {
            return;
        }
        let mut r = Ok(());
        for i in batch {
            r = self.impacts_csv.row(i);
            if r.is_err() {
                break;
            }
        }
        self.keep(r);
        let r = self.h5.impacts(batch).map_err(OutputError::from);
        self.keep(r);
    }

    fn shot(&mut self, s: &ShotState) {
        if self.error.is_some() {
            return;
        }
        let r = self.shots_csv.row(ShotRow::from(s));
        self.keep(r);
        let r = self.h5.shot(s).map_err(OutputError::from);
        self.keep(r);
    }
}

/// Writes a ParaView series: `dir/shots_NNNNN.vtp` per snapshot and `dir/shots.pvd`.
pub fn write_snapshots(
    dir: &Path,
    snapshots: &[(f64, Vec<crate::export::vtk::SnapshotPoint>)],
) -> Result<(), OutputError> {
    fs::create_dir_all(dir).map_err(io(dir))?;
    let mut entries = Vec::new();
    for (k, (t, pts)) in snapshots.iter().enumerate() {
        let name = format!("shots_{k:05}.vtp");
        write_atomic(
            &dir.join(&name),
            crate::export::vtk::snapshot_vtp(pts).as_bytes(),
        )?;
        entries.push((*t, name));
    }
    write_atomic(
        &dir.join("shots.pvd"),
        crate::export::vtk::pvd(&entries).as_bytes(),
    )
}
