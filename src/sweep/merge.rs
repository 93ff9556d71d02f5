//! `peenflow merge`: combines shard directories into one finished sweep directory.

use super::run::{CaseResult, Manifest, SweepRunError, missing_cases};
use std::path::{Path, PathBuf};

/// What a merge did.
#[derive(Debug, Clone, Default)]
pub struct MergeReport {
    /// Output directory.
    pub out: PathBuf,
    /// Cases copied in from other directories.
    pub copied: usize,
    /// Cases in the sweep.
    pub cases: usize,
}

/// Checks that `dirs` hold shards of one sweep, gathers every finished case into `out`
/// (default: the first directory) and assembles sweep.h5 there.
pub fn merge(
    dirs: &[PathBuf],
    out: Option<&Path>,
    force: bool,
) -> Result<MergeReport, SweepRunError> {
    let Some(first) = dirs.first() else {
        return Err(SweepRunError::Dir {
            path: ".".into(),
            message: "merge needs at least one sweep directory".into(),
        });
    };
    let manifest = Manifest::read(first)?;
    let mut manifests = vec![manifest.clone()];
    for d in &dirs[1..] {
        let m = Manifest::read(d)?;
        if m.sweep_hash != manifest.sweep_hash {
            return Err(SweepRunError::Dir {
                path: d.display().to_string(),
                message: format!(
                    "holds sweep \"{}\" ({} cases, hash {}), not the sweep of {} (\"{}\", {} cases, hash {})",
                    m.title,
                    m.cases.len(),
                    &m.sweep_hash[..12],
                    first.display(),
                    manifest.title,
                    manifest.cases.len(),
                    &manifest.sweep_hash[..12]
                ),
            });
        }
        manifests.push(m);
    }
    let out = out.map(Path::to_path_buf).unwrap_or_else(|| first.clone());
    let out_is_input = dirs.iter().any(|d| same_dir(d, &out));
    if !out_is_input {
        if out.join("sweep.json").exists() {
            let m = Manifest::read(&out)?;
            if m.sweep_hash != manifest.sweep_hash && !force {
                return Err(SweepRunError::Dir {
                    path: out.display().to_string(),
                    message: "holds another sweep; use another --out or --force".into(),
                });
            }
        } else {
            crate::output::prepare_dir(&out, force)?;
        }
        let mut json = serde_json::to_vec_pretty(&manifest).expect("BUG: manifest serialises");
        json.push(b'\n');
        crate::output::write_atomic(&out.join("sweep.json"), &json)?;
    }
    let mut report = MergeReport {
        out: out.clone(),
        copied: 0,
        cases: manifest.cases.len(),
    };
    let mut missing = Vec::new();
    for c in &manifest.cases {
        let finished = |d: &Path| {
            CaseResult::read(&d.join(&c.name)).is_some_and(|r| r.hash == c.hash)
                && d.join(&c.name)
                    .join(crate::export::hdf5::IMPACT_FILE)
                    .is_file()
        };
        if finished(&out) {
            continue;
        }
        match dirs.iter().find(|d| finished(d)) {
            Some(src) => {
                copy_case(&src.join(&c.name), &out, &c.name)?;
                report.copied += 1;
            }
            None => missing.push(c.name.clone()),
        }
    }
    if !missing.is_empty() {
        return Err(missing_cases(
            &out,
            &missing,
            manifest.cases.len(),
            "are in none of the directories",
            ": a shard did not finish; run it again with the same --shard K/N, then merge",
        ));
    }
    super::assemble::assemble(&out)?;
    Ok(report)
}

fn same_dir(a: &Path, b: &Path) -> bool {
    match (a.canonicalize(), b.canonicalize()) {
        (Ok(x), Ok(y)) => x == y,
        _ => a == b,
    }
}

/// Copies a finished case directory into `out/name` atomically (temporary, then rename).
fn copy_case(src: &Path, out: &Path, name: &str) -> Result<(), SweepRunError> {
    let err = |p: &Path, e: std::io::Error| SweepRunError::Dir {
        path: p.display().to_string(),
        message: e.to_string(),
    };
    let tmp = out.join(format!(".{name}.tmp-{}", std::process::id()));
    if tmp.exists() {
        std::fs::remove_dir_all(&tmp).map_err(|e| err(&tmp, e))?;
    }
    std::fs::create_dir_all(&tmp).map_err(|e| err(&tmp, e))?;
    for entry in std::fs::read_dir(src).map_err(|e| err(src, e))? {
        let entry = entry.map_err(|e| err(src, e))?;
        let p = entry.path();
        if p.is_file() {
            std::fs::copy(&p, tmp.join(entry.file_name())).map_err(|e| err(&p, e))?;
        }
    }
    let dest = out.join(name);
    if dest.exists() {
        std::fs::remove_dir_all(&dest).map_err(|e| err(&dest, e))?;
    }
    std::fs::rename(&tmp, &dest).map_err(|e| err(&dest, e))?;
    Ok(())
}
