//! Export stage: impact files (HDF5), ParaView views (VTK XML) and FE initial-condition
//! decks (Abaqus, LS-DYNA, CalculiX) from editable templates. Every deck and VTK mesh is
//! built from the one mesh model in `crate::mesh`.
//!
//! [`export`] selects impacts, builds everything in memory and only then writes the
//! files (each atomically), so a failure leaves no partial output.

pub mod deck;
pub mod hdf5;
pub mod select;
pub mod vtk;

use crate::output::{IMPACT_HEADER, OutputError, write_atomic};
use crate::record::Impact;
use crate::scene::{Material, Scene, material};
use deck::{DeckFormat, DeckSettings, UnitSystem};
use select::Selection;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Export formats.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// An FE deck.
    Deck(DeckFormat),
    /// impacts.vtp point cloud.
    Vtk,
    /// selected_impacts.csv.
    Csv,
}

impl Format {
    /// Parses a command-line name.
    pub fn parse(s: &str) -> Option<Format> {
        Some(match s {
            "abaqus" => Format::Deck(DeckFormat::Abaqus),
            "lsdyna" | "ls-dyna" => Format::Deck(DeckFormat::LsDyna),
            "calculix" | "ccx" => Format::Deck(DeckFormat::Calculix),
            "vtk" => Format::Vtk,
            "csv" => Format::Csv,
            _ => return None,
        })
    }

    /// Names accepted by [`Format::parse`].
    pub const NAMES: &'static str = "abaqus, lsdyna, calculix, vtk, csv";
}

/// Export errors.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum ExportError {
    /// Reading the impact file failed.
    #[error(transparent)]
    Read(#[from] hdf5::H5Error),
    /// The scene stored in the impact file is invalid.
    #[error("scene stored in {path}: {message}")]
    Scene {
        /// Impact file.
        path: String,
        /// Scene error.
        message: String,
    },
    /// Building or rendering a deck failed.
    #[error(transparent)]
    Deck(#[from] deck::DeckError),
    /// Writing failed.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// Drawing the selection's picture failed.
    #[error(transparent)]
    Plot(#[from] crate::plot::PlotError),
    /// Template file unreadable.
    #[error("{path}: cannot read the template: {source}")]
    Template {
        /// File.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// Bad combination of options.
    #[error("{0}")]
    Usage(String),
    /// Output file exists.
    #[error("{path}: exists; pass --force to overwrite it")]
    Exists {
        /// File.
        path: String,
    },
}

/// What to export and how.
#[derive(Debug, Clone)]
pub struct ExportRequest {
    /// Formats.
    pub formats: Vec<Format>,
    /// User template (one deck format only).
    pub template: Option<PathBuf>,
    /// Deck units.
    pub units: UnitSystem,
    /// Which impacts.
    pub selection: Selection,
    /// Rigid shots (default) or elastic.
    pub rigid_shots: bool,
    /// Shot mesh resolution (cells per cube edge).
    pub shot_cells: Option<usize>,
    /// Fine element size of the target, m.
    pub element_size: Option<f64>,
    /// Target material name (default: the scene's specimen).
    pub target_material: Option<String>,
    /// Output directory.
    pub out: PathBuf,
    /// Overwrite existing files.
    pub force: bool,
}

fn find_material(name: &str, scene: &Scene) -> Result<Material, ExportError> {
    for m in [
        &scene.specimen_material,
        &scene.shot_material,
        &scene.nozzle_material,
    ] {
        if m.name == name {
            return Ok(m.clone());
        }
    }
    material::builtin(name).ok_or_else(|| {
        let names: Vec<&str> = material::LIBRARY.iter().map(|m| m.name).collect();
        ExportError::Usage(format!(
            "--target-material {name}: unknown material; known: {}",
            names.join(", ")
        ))
    })
}

/// The target material decks of `scene` are built on (`--target-material`, or the
/// scene's specimen), checked for what a deck needs (a yield strength). `peenflow run
/// --export` calls it before running, so a deck that cannot be built is refused before
/// a long run rather than after it.
pub fn deck_target(scene: &Scene, name: Option<&str>) -> Result<Material, ExportError> {
    let m = match name {
        Some(name) => find_material(name, scene)?,
        None => scene.specimen_material.clone(),
    };
    if m.yield_strength.is_none() {
        return Err(deck::DeckError::NoYield(m.name.clone()).into());
    }
    Ok(m)
}

/// Exports `impacts` (of `scene`, read from `source`) as requested. Returns the files
/// written. Nothing is written when anything fails.
pub fn export(
    impacts: &[Impact],
    scene: &Scene,
    source: &str,
    req: &ExportRequest,
) -> Result<Vec<PathBuf>, ExportError> {
    let decks: Vec<DeckFormat> = req
        .formats
        .iter()
        .filter_map(|f| {
            if let Format::Deck(d) = f {
                Some(*d)
            } else {
                None
            }
        })
        .collect();
    if req.template.is_some() && decks.len() != 1 {
        return Err(ExportError::Usage(format!(
            "--template needs exactly one deck format (abaqus, lsdyna or calculix), got {}",
            decks.len()
        )));
    }
    if impacts.is_empty() {
        return Err(deck::DeckError::NoImpacts.into());
    }
    let selected = req.selection.apply(impacts);
    if selected.is_empty() {
        return Err(deck::DeckError::EmptySelection {
            available: impacts.len(),
            selection: req.selection.describe(),
        }
        .into());
    }
    let mut files: Vec<(PathBuf, Vec<u8>)> = Vec::new();
    for f in &req.formats {
        match f {
            Format::Vtk => files.push((
                req.out.join("impacts.vtp"),
                vtk::impacts_vtp(&selected).into_bytes(),
            )),
            Format::Csv => {
                let p = req.out.join("selected_impacts.csv");
                let bytes = if selected.is_empty() {
                    IMPACT_HEADER.as_bytes().to_vec()
                } else {
                    crate::output::impacts_csv(&selected, &p)?
                };
                files.push((p, bytes));
            }
            Format::Deck(_) => {}
        }
    }
    // Rectangles on the selection's picture, mm.
    let mut outlines: Vec<([f64; 4], &str)> = Vec::new();
    if let Some([x0, y0, x1, y1]) = req.selection.window {
        outlines.push(([x0, x1, y0, y1].map(|v| v * 1e3), "--window"));
    }
    if !decks.is_empty() {
        let target_material = deck_target(scene, req.target_material.as_deref())?;
        let settings = DeckSettings {
            units: req.units,
            rigid_shots: req.rigid_shots,
            shot_cells: req
                .shot_cells
                .unwrap_or(if req.rigid_shots { 4 } else { 6 }),
            element_size: req.element_size,
            shot_material: scene.shot_material.clone(),
            target_material,
            source: source.to_string(),
            selection: req.selection.describe(),
            shape: scene.specimen_shape.clone(),
        };
        let model = deck::build(&selected, &settings)?;
        for d in &decks {
            let (name, text) = match &req.template {
                Some(p) => (
                    p.display().to_string(),
                    std::fs::read_to_string(p).map_err(|source| ExportError::Template {
                        path: p.display().to_string(),
                        source,
                    })?,
                ),
                None => (
                    format!("templates/{}.j2", d.file_name()),
                    d.builtin_template().to_string(),
                ),
            };
            let rendered = deck::render(&model, &name, &text)?;
            files.push((req.out.join(d.file_name()), rendered.into_bytes()));
        }
        files.push((
            req.out.join("fe_model.vtu"),
            vtk::mesh_vtu(&model.mesh, &["ALL"]).into_bytes(),
        ));
        // The target block in specimen coordinates: deck units about the model origin.
        let e = &model.target.extent;
        let mm = 1e3 / model.units.length_factor;
        let [ox, oy] = model.origin;
        outlines.push((
            [e[0] + ox, e[1] + ox, e[2] + oy, e[3] + oy].map(|v| v * mm),
            "FE target block",
        ));
    }
    let effects = scene.effects();
    let picture = crate::record::figure::selection(
        &scene.title,
        &scene.specimen_shape,
        impacts,
        &selected,
        &outlines,
        (effects.drag || effects.lateral_force).then_some((0.0, 0.0)),
    )?;
    for (ext, bytes) in picture {
        files.push((req.out.join(format!("selection.{ext}")), bytes));
    }
    if !req.force
        && let Some((p, _)) = files.iter().find(|(p, _)| p.exists())
    {
        return Err(ExportError::Exists {
            path: p.display().to_string(),
        });
    }
    std::fs::create_dir_all(&req.out).map_err(|source| OutputError::Io {
        path: req.out.display().to_string(),
        source,
    })?;
    for (p, bytes) in &files {
        write_atomic(p, bytes)?;
    }
    Ok(files.into_iter().map(|(p, _)| p).collect())
}

/// Reads an impact file and its stored scene.
pub fn read_impact_file(path: &Path) -> Result<(hdf5::ImpactFile, Scene), ExportError> {
    let file = hdf5::read(path)?;
    let shown = path.display().to_string();
    let mut scene = Scene::from_toml(&file.scene_text, &shown).map_err(|e| ExportError::Scene {
        path: shown.clone(),
        message: e.to_string(),
    })?;
    scene.seed = file.seed;
    Ok((file, scene))
}
