//! Sweep file -> plan: the base scene, the parameters to vary, the cases (each a
//! resolved, validated scene with its content hash) and the seeds.
//!
//! ```toml
//! title = "Table 1"
//! base = "base.toml"      # relative to the sweep file; omitted: the embedded scene
//! seeds = 5               # seeds 1..=5, or a list: seeds = [3, 7, 11]
//! combine = "zip"         # "product" (every combination, default) or "zip" (i-th values)
//! names = ["test1", ...]  # optional case names, one per case
//!
//! [vary]
//! "air.gauge_pressure_mpa" = [0.6, 0.3]                 # a list
//! "shots.diameter_mm" = { from = 0.4, to = 1.0, steps = 4 }  # a range, ends included
//! ```

use crate::scene::validate::{did_you_mean, num};
use crate::scene::{DEFAULT_SCENE, Scene, SceneError};
use serde::Deserialize;
use sha2::{Digest, Sha256};
use std::path::{Path, PathBuf};
use thiserror::Error;

/// Everything that can be wrong with a sweep file: one line, naming the file and key.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum SweepError {
    /// The file could not be read.
    #[error("{path}: cannot read the sweep file: {source}")]
    Io {
        /// File.
        path: String,
        /// Cause.
        source: std::io::Error,
    },
    /// A key or value of the sweep file is wrong.
    #[error("{path}: {message}")]
    Invalid {
        /// File.
        path: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

/// How the parameter lists combine into cases.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Combine {
    /// Every combination (cartesian product; the last parameter varies fastest).
    Product,
    /// The i-th value of every list together; all lists have the same length.
    Zip,
}

impl Combine {
    /// Name as written in sweep files.
    pub fn name(self) -> &'static str {
        match self {
            Combine::Product => "product",
            Combine::Zip => "zip",
        }
    }
}

/// One case: a resolved scene run over the sweep's seeds.
#[derive(Debug, Clone)]
pub struct Case {
    /// Position in the sweep (0-based).
    pub index: usize,
    /// Directory name under the output directory.
    pub name: String,
    /// One value per varied parameter, in the order of [`Plan::parameters`].
    pub values: Vec<toml::Value>,
    /// The resolved scene as TOML (base scene with the values set).
    pub scene_text: String,
    /// The validated scene.
    pub scene: Scene,
    /// SHA-256 of tool version, resolved scene and seeds: a finished case with this hash
    /// is not run again.
    pub hash: String,
}

/// A checked sweep, ready to run.
#[derive(Debug, Clone)]
pub struct Plan {
    /// Sweep file as shown in messages.
    pub path: String,
    /// Sweep file text.
    pub text: String,
    /// Title.
    pub title: String,
    /// Base scene file (empty for the embedded scene).
    pub base_path: String,
    /// Base scene text.
    pub base_text: String,
    /// Seeds every case runs with.
    pub seeds: Vec<u64>,
    /// How lists combine.
    pub combine: Combine,
    /// Varied parameters (dotted scene keys), in file order.
    pub parameters: Vec<String>,
    /// The cases.
    pub cases: Vec<Case>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepToml {
    #[serde(default)]
    title: Option<String>,
    #[serde(default)]
    base: Option<String>,
    #[serde(default)]
    seeds: Option<SeedsToml>,
    #[serde(default)]
    combine: Option<String>,
    #[serde(default)]
    names: Option<Vec<String>>,
    vary: toml::Table,
}

#[derive(Debug, Deserialize)]
#[serde(untagged)]
enum SeedsToml {
    Count(i64),
    List(Vec<i64>),
}

/// Most cases a sweep may hold (a guard against a runaway product).
pub const MAX_CASES: usize = 100_000;
/// Most seeds per case.
pub const MAX_SEEDS: usize = 10_000;

impl Plan {
    /// Reads and checks a sweep file; the base scene is resolved relative to it.
    pub fn load(path: &Path) -> Result<Plan, SweepError> {
        let shown = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|source| SweepError::Io {
            path: shown.clone(),
            source,
        })?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        Plan::from_toml(&text, &shown, &dir)
    }

    /// Parses and checks sweep text; `base` paths are taken relative to `dir`.
    pub fn from_toml(text: &str, path: &str, dir: &Path) -> Result<Plan, SweepError> {
        let bad = |message: String| SweepError::Invalid {
            path: path.to_string(),
            message,
        };
        let raw: SweepToml = toml::from_str(text).map_err(|e| {
            let msg = e.message().replace('\n', " ");
            let msg = if let Some(rest) = msg.strip_prefix("unknown field ") {
                let key = rest.split('`').nth(1).unwrap_or("");
                let keys = ["title", "base", "seeds", "combine", "names", "vary"];
                let hint = crate::scene::validate::did_you_mean(key, keys.into_iter())
                    .map(|s| format!("did you mean `{s}`? "))
                    .unwrap_or_default();
                format!(
                    "unknown key `{key}`; {hint}allowed: title, base, seeds, combine, names, [vary]"
                )
            } else if msg.starts_with("missing field `vary`") {
                "missing [vary] table: name at least one scene key to vary, e.g. \
                 \"air.gauge_pressure_mpa\" = [0.3, 0.6]"
                    .to_string()
            } else if msg.contains("untagged enum SeedsToml") {
                "seeds: expected a count (seeds = 5) or a list of seeds (seeds = [1, 7])"
                    .to_string()
            } else {
                format!("TOML: {}", msg.trim())
            };
            bad(msg)
        })?;
        let (base_path, base_text) = match &raw.base {
            None => (String::new(), DEFAULT_SCENE.to_string()),
            Some(b) => {
                let p: PathBuf = if Path::new(b).is_absolute() {
                    PathBuf::from(b)
                } else {
                    dir.join(b)
                };
                let t = std::fs::read_to_string(&p).map_err(|e| {
                    bad(format!("base = \"{b}\": cannot read {} ({e})", p.display()))
                })?;
                (p.display().to_string(), t)
            }
        };
        let base_shown = if base_path.is_empty() {
            "<default scene>".to_string()
        } else {
            base_path.clone()
        };
        let base_table: toml::Table = toml::from_str(&base_text)
            .map_err(|e| bad(format!("base scene {base_shown}: {}", e.message().trim())))?;
        // The base must be a valid scene on its own.
        Scene::from_toml(&base_text, &base_shown).map_err(|e| bad(format!("base scene: {e}")))?;

        let seeds = match raw.seeds {
            None => vec![1],
            Some(SeedsToml::Count(n)) => {
                if n < 1 || n as usize > MAX_SEEDS {
                    return Err(bad(format!(
                        "seeds = {n}: allowed a count from 1 to {MAX_SEEDS} or a list of seeds"
                    )));
                }
                (1..=n as u64).collect()
            }
            Some(SeedsToml::List(v)) => {
                if v.is_empty() || v.len() > MAX_SEEDS {
                    return Err(bad(format!(
                        "seeds = []: allowed a list of 1 to {MAX_SEEDS} seeds"
                    )));
                }
                let mut out = Vec::with_capacity(v.len());
                for s in v {
                    if s < 0 {
                        return Err(bad(format!("seeds: {s}: allowed seeds >= 0")));
                    }
                    if out.contains(&(s as u64)) {
                        return Err(bad(format!("seeds: {s} appears twice")));
                    }
                    out.push(s as u64);
                }
                out
            }
        };
        let combine = match raw.combine.as_deref() {
            None | Some("product") => Combine::Product,
            Some("zip") => Combine::Zip,
            Some(o) => {
                return Err(bad(format!(
                    "combine = \"{o}\": allowed \"product\" or \"zip\""
                )));
            }
        };
        if raw.vary.is_empty() {
            return Err(bad(
                "[vary] is empty: name at least one scene key to vary, e.g. \
                 \"air.gauge_pressure_mpa\" = [0.3, 0.6]"
                    .into(),
            ));
        }
        let mut parameters = Vec::new();
        let mut lists: Vec<Vec<toml::Value>> = Vec::new();
        for (key, spec) in &raw.vary {
            let values = expand_values(key, spec).map_err(bad)?;
            // Each value alone on the base scene: names the value a problem comes from.
            for v in &values {
                resolve(&base_table, &[(key.as_str(), v)], &base_shown)
                    .map_err(|m| bad(format!("[vary] \"{key}\" = {}: {m}", show(v))))?;
            }
            parameters.push(key.clone());
            lists.push(values);
        }
        let combos: Vec<Vec<toml::Value>> = match combine {
            Combine::Zip => {
                let n = lists[0].len();
                if let Some(k) = lists.iter().position(|l| l.len() != n) {
                    return Err(bad(format!(
                        "combine = \"zip\": [vary] \"{}\" has {} values but \"{}\" has {n}; \
                         zipped lists need the same length",
                        parameters[k],
                        lists[k].len(),
                        parameters[0]
                    )));
                }
                (0..n)
                    .map(|i| lists.iter().map(|l| l[i].clone()).collect())
                    .collect()
            }
            Combine::Product => {
                let total = lists
                    .iter()
                    .try_fold(1usize, |acc, l| acc.checked_mul(l.len()));
                match total {
                    Some(t) if t <= MAX_CASES => {}
                    _ => {
                        return Err(bad(format!(
                            "the product of the [vary] lists has more than {MAX_CASES} cases; \
                             vary fewer values or use combine = \"zip\""
                        )));
                    }
                }
                let mut out: Vec<Vec<toml::Value>> = vec![vec![]];
                for l in &lists {
                    out = out
                        .into_iter()
                        .flat_map(|c| {
                            l.iter().map(move |v| {
                                let mut c = c.clone();
                                c.push(v.clone());
                                c
                            })
                        })
                        .collect();
                }
                out
            }
        };
        if let Some(names) = &raw.names {
            if names.len() != combos.len() {
                return Err(bad(format!(
                    "names has {} entries but the sweep has {} cases",
                    names.len(),
                    combos.len()
                )));
            }
            for (i, n) in names.iter().enumerate() {
                if n.is_empty()
                    || n.starts_with('.')
                    || !n
                        .chars()
                        .all(|c| c.is_ascii_alphanumeric() || "._-+=".contains(c))
                {
                    return Err(bad(format!(
                        "names[{i}] = \"{n}\": allowed letters, digits and . _ - + = \
                         (it names a directory), not starting with a dot"
                    )));
                }
                if names[..i].contains(n) {
                    return Err(bad(format!("names: \"{n}\" appears twice")));
                }
            }
        }
        let version = env!("CARGO_PKG_VERSION");
        let mut cases = Vec::with_capacity(combos.len());
        for (index, values) in combos.into_iter().enumerate() {
            let name = match &raw.names {
                Some(n) => n[index].clone(),
                None => default_name(index, &parameters, &values),
            };
            let pairs: Vec<(&str, &toml::Value)> = parameters
                .iter()
                .map(String::as_str)
                .zip(values.iter())
                .collect();
            let mut table = base_table.clone();
            table.insert("seed".into(), toml::Value::Integer(seeds[0] as i64));
            let (scene_text, scene) = resolve(&table, &pairs, &format!("{name}/scene.toml"))
                .map_err(|m| bad(format!("case `{name}` ({}): {m}", describe(&pairs))))?;
            let mut h = Sha256::new();
            h.update(format!("peenflow {version}\n").as_bytes());
            h.update(scene_text.as_bytes());
            h.update(format!("\nseeds = {seeds:?}\n").as_bytes());
            let hash = hex(&h.finalize());
            cases.push(Case {
                index,
                name,
                values,
                scene_text,
                scene,
                hash,
            });
        }
        Ok(Plan {
            path: path.to_string(),
            text: text.to_string(),
            title: raw.title.unwrap_or_else(|| path.to_string()),
            base_path,
            base_text,
            seeds,
            combine,
            parameters,
            cases,
        })
    }

    /// SHA-256 over the cases' hashes: two directories hold the same sweep when equal.
    pub fn hash(&self) -> String {
        let mut h = Sha256::new();
        for c in &self.cases {
            h.update(c.name.as_bytes());
            h.update(b"\0");
            h.update(c.hash.as_bytes());
            h.update(b"\n");
        }
        hex(&h.finalize())
    }

    /// The cases of shard `k` of `n` (1-based): every n-th case, starting at the k-th.
    pub fn shard(&self, k: usize, n: usize) -> Vec<&Case> {
        self.cases.iter().filter(|c| c.index % n == k - 1).collect()
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// A value as written in TOML.
pub fn show(v: &toml::Value) -> String {
    match v {
        toml::Value::Float(f) => num(*f),
        other => other.to_string(),
    }
}

fn describe(pairs: &[(&str, &toml::Value)]) -> String {
    pairs
        .iter()
        .map(|(k, v)| format!("{k} = {}", show(v)))
        .collect::<Vec<_>>()
        .join(", ")
}

fn default_name(index: usize, parameters: &[String], values: &[toml::Value]) -> String {
    let mut name = format!("case-{index:03}");
    for (p, v) in parameters.iter().zip(values) {
        let last = p.rsplit('.').next().unwrap_or(p);
        let v = show(v);
        let v: String = v
            .chars()
            .filter_map(|c| match c {
                c if c.is_ascii_alphanumeric() || c == '.' || c == '-' => Some(c),
                ' ' | ',' | '_' => Some('_'),
                _ => None,
            })
            .collect();
        name.push_str(&format!("_{last}-{v}"));
    }
    name
}

/// The values of one `[vary]` entry: a non-empty list or `{ from, to, steps }`.
fn expand_values(key: &str, spec: &toml::Value) -> Result<Vec<toml::Value>, String> {
    if key == "seed" {
        return Err("[vary] \"seed\": seeds are set with the top-level `seeds` key".into());
    }
    if key.split('.').any(str::is_empty) {
        return Err(format!(
            "[vary] \"{key}\": not a dotted scene key (e.g. \"air.gauge_pressure_mpa\")"
        ));
    }
    match spec {
        toml::Value::Array(a) => {
            if a.is_empty() {
                return Err(format!(
                    "[vary] \"{key}\" = []: the list is empty; give at least one value"
                ));
            }
            Ok(a.clone())
        }
        toml::Value::Table(t) => {
            let allowed = ["from", "to", "steps", "scale"];
            for k in t.keys() {
                if !allowed.contains(&k.as_str()) {
                    let hint = did_you_mean(k, allowed.iter().copied())
                        .map(|s| format!("did you mean `{s}`? "))
                        .unwrap_or_default();
                    return Err(format!(
                        "[vary] \"{key}\": unknown range key `{k}`; {hint}allowed: from, to, steps, scale"
                    ));
                }
            }
            let number = |k: &str| -> Result<f64, String> {
                match t.get(k) {
                    Some(toml::Value::Float(f)) => Ok(*f),
                    Some(toml::Value::Integer(i)) => Ok(*i as f64),
                    Some(o) => Err(format!("[vary] \"{key}\": {k} = {o}: expected a number")),
                    None => Err(format!(
                        "[vary] \"{key}\": a range needs from, to and steps, e.g. \
                         {{ from = 0.2, to = 0.8, steps = 4 }}; {k} is missing"
                    )),
                }
            };
            let from = number("from")?;
            let to = number("to")?;
            let steps = match t.get("steps") {
                Some(toml::Value::Integer(i)) if (1..=10_000).contains(i) => *i as usize,
                Some(o) => {
                    return Err(format!(
                        "[vary] \"{key}\": steps = {o}: allowed a whole number from 1 to 10000"
                    ));
                }
                None => number("steps").map(|_| 0)?,
            };
            let log = match t.get("scale").map(|v| v.as_str()) {
                None | Some(Some("linear")) => false,
                Some(Some("log")) => true,
                Some(_) => {
                    return Err(format!(
                        "[vary] \"{key}\": scale = {}: allowed \"linear\" or \"log\"",
                        t["scale"]
                    ));
                }
            };
            if !from.is_finite() || !to.is_finite() || (log && (from <= 0.0 || to <= 0.0)) {
                return Err(format!(
                    "[vary] \"{key}\": from = {}, to = {}: allowed finite numbers (> 0 on a log scale)",
                    num(from),
                    num(to)
                ));
            }
            if steps == 1 && from != to {
                return Err(format!(
                    "[vary] \"{key}\": steps = 1 but from != to; use steps >= 2 or a list"
                ));
            }
            let ints = matches!(t.get("from"), Some(toml::Value::Integer(_)))
                && matches!(t.get("to"), Some(toml::Value::Integer(_)));
            let mut out = Vec::with_capacity(steps);
            for i in 0..steps {
                let f = if steps == 1 {
                    0.0
                } else {
                    i as f64 / (steps - 1) as f64
                };
                let x = if log {
                    (from.ln() + (to.ln() - from.ln()) * f).exp()
                } else {
                    from + (to - from) * f
                };
                // Round to 12 significant digits so 0.1 + 2 * 0.1 reads as 0.3.
                let x: f64 = format!("{x:.11e}").parse().expect("BUG: float format");
                if ints {
                    let r = x.round();
                    if out.last() != Some(&toml::Value::Integer(r as i64)) {
                        out.push(toml::Value::Integer(r as i64));
                    }
                } else {
                    out.push(toml::Value::Float(x));
                }
            }
            Ok(out)
        }
        other => Err(format!(
            "[vary] \"{key}\" = {other}: expected a list of values or a range \
             {{ from = .., to = .., steps = .. }}"
        )),
    }
}

/// Sets `pairs` (dotted key, value) on `base` and validates the result as a scene shown
/// as `shown`. Returns the resolved TOML text and the scene, or a one-line message.
fn resolve(
    base: &toml::Table,
    pairs: &[(&str, &toml::Value)],
    shown: &str,
) -> Result<(String, Scene), String> {
    let mut table = base.clone();
    // A varied key replaces its alternative in the base scene (the default scene writes
    // `shot_specimen = 0.70`, which a varied curve would otherwise meet); if both are
    // varied, the scene's own check names the conflict.
    let varies = |k: &str| {
        pairs
            .iter()
            .any(|(v, _)| *v == k || v.strip_prefix(k).is_some_and(|r| r.starts_with('.')))
    };
    for (a, b) in ALTERNATIVES {
        for (this, other) in [(a, b), (b, a)] {
            if varies(this) && !varies(other) {
                unset(&mut table, other);
            }
        }
    }
    for (key, value) in pairs {
        set(&mut table, key, (*value).clone())?;
    }
    let text = toml::to_string(&table).map_err(|e| format!("cannot write the scene: {e}"))?;
    let scene = Scene::from_toml(&text, shown).map_err(|e| match e {
        // Positions point into generated text: keep the message only.
        SceneError::Parse { message, .. } => message,
        SceneError::OutOfRange {
            key,
            value,
            allowed,
            ..
        } => format!("{key} = {value} is out of range: allowed {allowed}"),
        SceneError::Invalid { key, message, .. } => format!("{key}: {message}"),
        other => other.to_string(),
    })?;
    Ok((text, scene))
}

/// Scene keys that stand for each other (a scene gives one of the two).
const ALTERNATIVES: [(&str, &str); 3] = [
    (
        "restitution.shot_specimen",
        "restitution.shot_specimen_curve",
    ),
    ("shots.diameter_mm", "shots.size_distribution"),
    ("shots.feed.rate_per_s", "shots.feed.mass_flow_kg_min"),
];

/// Removes dotted `key` from `table`, if it is there.
fn unset(table: &mut toml::Table, key: &str) {
    let (path, last) = key.rsplit_once('.').unwrap_or(("", key));
    let mut t = table;
    for p in path.split('.').filter(|p| !p.is_empty()) {
        match t.get_mut(p) {
            Some(toml::Value::Table(inner)) => t = inner,
            _ => return,
        }
    }
    t.remove(last);
}

fn set(table: &mut toml::Table, key: &str, value: toml::Value) -> Result<(), String> {
    let parts: Vec<&str> = key.split('.').collect();
    let mut t = table;
    for (i, p) in parts[..parts.len() - 1].iter().enumerate() {
        let entry = t
            .entry(p.to_string())
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        t = match entry {
            toml::Value::Table(inner) => inner,
            _ => {
                return Err(format!(
                    "`{}` is a value, not a table, so `{key}` names nothing",
                    parts[..=i].join(".")
                ));
            }
        };
    }
    let last = parts[parts.len() - 1];
    if let Some(toml::Value::Table(_)) = t.get(last) {
        return Err(format!(
            "`{key}` is a table; vary one of its keys (e.g. \"{key}.<key>\")"
        ));
    }
    // Integer-valued keys written as floats in a range (count = 30.0) are not accepted by
    // the scene parser; a float list for a float key that holds an integer is fine.
    t.insert(last.to_string(), value);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn plan(vary: &str) -> Result<Plan, SweepError> {
        Plan::from_toml(&format!("[vary]\n{vary}\n"), "s.toml", Path::new("."))
    }

    /// A varied key replaces its alternative in the base scene: the default scene's
    /// `shot_specimen = 0.70` gives way to a varied curve, its `diameter_mm` to a varied
    /// size distribution; varying both of a pair is the scene's conflict, named.
    #[test]
    fn a_varied_key_replaces_its_alternative() {
        let p = plan(
            "\"restitution.shot_specimen_curve\" = [{ speed_m_s = [20.0, 70.0], restitution = [0.5, 0.3] }]",
        )
        .unwrap();
        let r = &p.cases[0].scene.restitution;
        assert_eq!(r.shot_specimen_curve.as_ref().unwrap().at(70.0), 0.3);
        let text: toml::Table = toml::from_str(&p.cases[0].scene_text).unwrap();
        assert!(
            !text["restitution"]
                .as_table()
                .unwrap()
                .contains_key("shot_specimen")
        );
        let p = plan(
            "\"shots.size_distribution\" = [{ type = \"uniform\", min_mm = 0.5, max_mm = 0.7 }]",
        )
        .unwrap();
        let text: toml::Table = toml::from_str(&p.cases[0].scene_text).unwrap();
        assert!(
            !text["shots"]
                .as_table()
                .unwrap()
                .contains_key("diameter_mm")
        );
        // The constant varied on a base that gives the constant: nothing removed.
        let p = plan("\"restitution.shot_specimen\" = [0.5]").unwrap();
        assert_eq!(p.cases[0].scene.restitution.shot_specimen, 0.5);
        let e = plan(
            "\"restitution.shot_specimen\" = [0.5]\n\
             \"restitution.shot_specimen_curve\" = [{ speed_m_s = [20.0], restitution = [0.5] }]",
        )
        .unwrap_err()
        .to_string();
        assert!(e.contains("not both"), "{e}");
    }
}
