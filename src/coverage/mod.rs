//! Coverage: the fraction of the specimen's area dented at least once (SAE J2277), its
//! growth with exposure time, the fitted Avrami law and the time to "full" (98 %)
//! coverage, from a run's impact records and a dent-size model ([`dent`]).
//!
//! The window is divided into square cells; a cell is covered from the earliest time a
//! dent disc contains its centre. Coverage at time `t` is the share of covered cells.
//! Exposure time is counted from the first impact (the jet is then established), and
//! the Avrami-type law `C(t) = 1 - exp(-k t^n)` is fitted by least squares on
//! `ln(-ln(1 - C))` against `ln t` over `0.5 % < C < 99.5 %`. For dents arriving at a
//! steady rate at uniformly random places, `n = 1` and `k` is the dented area per unit
//! time and area (tests/coverage.rs checks both against `1 - exp(-A)`).

pub mod dent;
pub mod gear;
pub mod output;
pub mod traverse;

use crate::contact::specimen::SpecimenShape;
use crate::record::Impact;
use dent::DentModel;

/// One dent: centre (m), semi-axes along x and y (m), time (s). A disc on the plate; on a
/// curved surface an ellipse whose axes are the unrolled surface's (across and along).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Dent {
    /// Centre x, m.
    pub x: f64,
    /// Centre y, m.
    pub y: f64,
    /// Semi-axis along x (across a bar or a groove), m.
    pub rx: f64,
    /// Semi-axis along y (along a bar's or a groove's axis), m.
    pub ry: f64,
    /// Time of the impact, s.
    pub t: f64,
}

impl Dent {
    /// A round dent of radius `r` (m).
    pub fn disc(x: f64, y: f64, r: f64, t: f64) -> Dent {
        Dent {
            x,
            y,
            rx: r,
            ry: r,
            t,
        }
    }

    /// The radius of the disc of the same area, `sqrt(rx ry)`, m.
    pub fn radius(&self) -> f64 {
        (self.rx * self.ry).sqrt()
    }

    /// Whether the point `(x, y)` lies in the dent (its border included).
    #[inline]
    pub fn contains(&self, x: f64, y: f64) -> bool {
        let (dx, dy) = (x - self.x, y - self.y);
        if self.rx == self.ry {
            dx * dx + dy * dy <= self.rx * self.rx
        } else {
            let (u, v) = (dx / self.rx, dy / self.ry);
            u * u + v * v <= 1.0
        }
    }
}

/// Dents of the impacts with a positive normal speed, on the flat specimen.
pub fn dents(impacts: &[Impact], model: &DentModel) -> Vec<Dent> {
    dents_on(impacts, model, &SpecimenShape::Plane)
}

/// [`dents`] on the specimen surface `shape`, placed on its unrolled surface
/// ([`SpecimenShape::unrolled`]: on a cylinder, the arc length around the bar and the
/// distance along its axis). A dent is far smaller than the bar, so it lies flat there;
/// the surface's curvature across makes it an ellipse ([`DentModel::footprint`]).
pub fn dents_on(impacts: &[Impact], model: &DentModel, shape: &SpecimenShape) -> Vec<Dent> {
    impacts
        .iter()
        .filter(|i| i.normal_speed_m_s > 0.0)
        .map(|i| {
            let (x, y) = shape.unrolled(&crate::Vec3::new(i.x_m, i.y_m, i.z_m));
            let centre = crate::Vec3::new(i.center_x_m, i.center_y_m, i.center_z_m);
            let (rx, ry) = model.footprint(
                0.5 * i.diameter_m,
                i.mass_kg,
                i.normal_speed_m_s,
                shape.curvature_across(&centre),
            );
            Dent {
                x,
                y,
                rx,
                ry,
                t: i.time_s,
            }
        })
        .collect()
}

/// `C(t) = 1 - exp(-k t^n)`.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct AvramiFit {
    /// Rate `k`, s^-n.
    pub k: f64,
    /// Exponent `n`.
    pub n: f64,
    /// Coefficient of determination of the linearised fit.
    pub r_squared: f64,
    /// Points used.
    pub points: usize,
}

impl AvramiFit {
    /// Coverage at exposure time `t`.
    pub fn coverage(&self, t: f64) -> f64 {
        1.0 - (-self.k * t.powf(self.n)).exp()
    }

    /// Exposure time to coverage `c` (0 < c < 1).
    pub fn time_to(&self, c: f64) -> f64 {
        (-(1.0 - c).ln() / self.k).powf(1.0 / self.n)
    }
}

/// A coverage map and curve.
#[derive(Debug, Clone)]
pub struct Coverage {
    /// Window `[x0, y0, x1, y1]`, m.
    pub window: [f64; 4],
    /// Cell size, m.
    pub cell: f64,
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Dents per cell (row-major, `ny` rows of `nx`, row 0 at `y0`).
    pub counts: Vec<u32>,
    /// Earliest dent time per cell, s (`INFINITY`: never dented).
    pub first_time: Vec<f64>,
    /// Time of the first impact, s: exposure starts here.
    pub t0: f64,
    /// Exposure at the end of the run, s.
    pub exposure: f64,
    /// `(exposure time s, coverage)` at 200 evenly spaced times.
    pub curve: Vec<(f64, f64)>,
    /// Coverage at the end of the run.
    pub final_coverage: f64,
    /// Fitted Avrami law, when the curve has at least 3 points inside (0.5 %, 99.5 %).
    pub fit: Option<AvramiFit>,
    /// First exposure time at which 98 % was reached in the run.
    pub t98_measured: Option<f64>,
    /// Dents that touch the window.
    pub dents_in_window: usize,
}

/// Default window: a square around the median impact point whose half side is the
/// median distance of the impacts from that point (it holds the dense core of the
/// pattern), and at least two dent diameters.
pub fn default_window(dents: &[Dent]) -> Option<[f64; 4]> {
    if dents.is_empty() {
        return None;
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        crate::summary::percentile(&v, 50.0)
    };
    let cx = median(dents.iter().map(|d| d.x).collect());
    let cy = median(dents.iter().map(|d| d.y).collect());
    let rd = median(dents.iter().map(Dent::radius).collect());
    let w = median(
        dents
            .iter()
            .map(|d| ((d.x - cx).powi(2) + (d.y - cy).powi(2)).sqrt())
            .collect(),
    )
    .max(4.0 * rd);
    Some([cx - w, cy - w, cx + w, cy + w])
}

/// Most cells along one axis.
pub const MAX_CELLS: usize = 2000;

/// Coverage of `window` (`[x0, y0, x1, y1]`, m) with cells of `cell` m (enlarged if the
/// grid would exceed [`MAX_CELLS`] per axis), for a run that ended at `t_end` s.
pub fn compute(dents: &[Dent], window: [f64; 4], cell: f64, t_end: f64) -> Coverage {
    let [x0, y0, x1, y1] = window;
    let (wx, wy) = (x1 - x0, y1 - y0);
    let cell = cell.max(wx.max(wy) / MAX_CELLS as f64);
    let nx = ((wx / cell).round() as usize).max(1);
    let ny = ((wy / cell).round() as usize).max(1);
    let (hx, hy) = (wx / nx as f64, wy / ny as f64);
    let mut counts = vec![0u32; nx * ny];
    let mut first_time = vec![f64::INFINITY; nx * ny];
    let mut in_window = 0;
    for d in dents {
        // Cells whose centre lies within the dent.
        let i_lo = (((d.x - d.rx - x0) / hx - 0.5).ceil().max(0.0)) as usize;
        let i_hi = ((d.x + d.rx - x0) / hx - 0.5).floor();
        let j_lo = (((d.y - d.ry - y0) / hy - 0.5).ceil().max(0.0)) as usize;
        let j_hi = ((d.y + d.ry - y0) / hy - 0.5).floor();
        if i_hi < 0.0 || j_hi < 0.0 {
            continue;
        }
        let i_hi = (i_hi as usize).min(nx - 1);
        let j_hi = (j_hi as usize).min(ny - 1);
        let mut touched = false;
        for j in j_lo..=j_hi {
            let cy = y0 + (j as f64 + 0.5) * hy;
            for i in i_lo..=i_hi {
                let cx = x0 + (i as f64 + 0.5) * hx;
                if d.contains(cx, cy) {
                    let k = j * nx + i;
                    counts[k] += 1;
                    first_time[k] = first_time[k].min(d.t);
                    touched = true;
                }
            }
        }
        in_window += touched as usize;
    }
    let t0 = dents.iter().map(|d| d.t).fold(f64::INFINITY, f64::min);
    let t0 = if t0.is_finite() { t0 } else { 0.0 };
    let exposure = (t_end - t0).max(0.0);
    // Coverage curve from the sorted first-dent times.
    let mut times: Vec<f64> = first_time
        .iter()
        .filter(|t| t.is_finite())
        .map(|t| t - t0)
        .collect();
    times.sort_by(f64::total_cmp);
    let total = (nx * ny) as f64;
    let covered_by = |t: f64| times.partition_point(|&x| x <= t) as f64 / total;
    let curve: Vec<(f64, f64)> = (1..=200)
        .map(|k| {
            let t = exposure * k as f64 / 200.0;
            (t, covered_by(t))
        })
        .collect();
    let final_coverage = times.len() as f64 / total;
    let t98_measured = {
        let need = (0.98 * total).ceil() as usize;
        (need >= 1 && times.len() >= need).then(|| times[need - 1])
    };
    Coverage {
        window,
        cell,
        nx,
        ny,
        counts,
        first_time,
        t0,
        exposure,
        fit: fit_avrami(&curve),
        curve,
        final_coverage,
        t98_measured,
        dents_in_window: in_window,
    }
}

/// Least-squares fit of `ln(-ln(1 - C)) = ln k + n ln t` over `0.5 % < C < 99.5 %`.
pub fn fit_avrami(curve: &[(f64, f64)]) -> Option<AvramiFit> {
    let pts: Vec<(f64, f64)> = curve
        .iter()
        .filter(|(t, c)| *t > 0.0 && *c > 0.005 && *c < 0.995)
        .map(|(t, c)| (t.ln(), (-(1.0 - c).ln()).ln()))
        .collect();
    if pts.len() < 3 {
        return None;
    }
    let m = pts.len() as f64;
    let (sx, sy) = pts.iter().fold((0.0, 0.0), |a, p| (a.0 + p.0, a.1 + p.1));
    let (mx, my) = (sx / m, sy / m);
    let sxx: f64 = pts.iter().map(|p| (p.0 - mx).powi(2)).sum();
    let sxy: f64 = pts.iter().map(|p| (p.0 - mx) * (p.1 - my)).sum();
    let syy: f64 = pts.iter().map(|p| (p.1 - my).powi(2)).sum();
    if sxx <= 0.0 {
        return None;
    }
    let n = sxy / sxx;
    let ln_k = my - n * mx;
    let r_squared = if syy > 0.0 {
        sxy * sxy / (sxx * syy)
    } else {
        1.0
    };
    Some(AvramiFit {
        k: ln_k.exp(),
        n,
        r_squared,
        points: pts.len(),
    })
}
