//! Material library: the paper's Table 2 steel, SUJ-2 shot steel, A5052 aluminium and a
//! few materials for hard cases. Scenes may add their own under `[materials.NAME]`.

use serde::Serialize;

/// Elastic (and, for FE export, plastic) properties of a material. SI units.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Material {
    /// Library or scene name.
    pub name: String,
    /// Young's modulus, Pa.
    pub youngs_modulus: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
    /// Density, kg/m^3.
    pub density: f64,
    /// Yield strength, Pa, where known.
    pub yield_strength: Option<f64>,
}

/// One built-in material, in the units users quote.
#[derive(Debug, Clone, Copy)]
pub struct LibraryEntry {
    /// Name used in scenes.
    pub name: &'static str,
    /// Young's modulus, GPa.
    pub youngs_modulus_gpa: f64,
    /// Poisson's ratio.
    pub poisson_ratio: f64,
    /// Density, kg/m^3.
    pub density_kg_m3: f64,
    /// Yield strength, MPa.
    pub yield_strength_mpa: Option<f64>,
    /// Source or use.
    pub note: &'static str,
}

const fn entry(
    name: &'static str,
    e: f64,
    nu: f64,
    rho: f64,
    y: Option<f64>,
    note: &'static str,
) -> LibraryEntry {
    LibraryEntry {
        name,
        youngs_modulus_gpa: e,
        poisson_ratio: nu,
        density_kg_m3: rho,
        yield_strength_mpa: y,
        note,
    }
}

/// Built-in materials.
pub const LIBRARY: &[LibraryEntry] = &[
    entry(
        "table2-steel",
        210.0,
        0.3,
        7850.0,
        None,
        "paper Table 2 (shots and specimen); SUJ-2 density",
    ),
    entry(
        "SUJ-2",
        208.0,
        0.3,
        7850.0,
        Some(1700.0),
        "JIS SUJ-2 / AISI 52100 bearing steel, hardened",
    ),
    entry(
        "A5052",
        70.3,
        0.33,
        2680.0,
        Some(195.0),
        "JIS A5052 / AA 5052 aluminium: the paper's real specimen",
    ),
    entry(
        "hardened-steel",
        210.0,
        0.3,
        7850.0,
        Some(1500.0),
        "through-hardened tool steel",
    ),
    entry(
        "tungsten-carbide",
        600.0,
        0.22,
        15600.0,
        None,
        "cemented WC, for stiff fine shots",
    ),
    entry(
        "boron-carbide",
        450.0,
        0.17,
        2520.0,
        None,
        "common blast-nozzle liner",
    ),
];

/// Looks up a built-in material.
pub fn builtin(name: &str) -> Option<Material> {
    LIBRARY.iter().find(|m| m.name == name).map(|m| Material {
        name: m.name.to_string(),
        youngs_modulus: m.youngs_modulus_gpa * 1e9,
        poisson_ratio: m.poisson_ratio,
        density: m.density_kg_m3,
        yield_strength: m.yield_strength_mpa.map(|v| v * 1e6),
    })
}
