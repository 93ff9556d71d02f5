//! Feed stage: creates the shots of a scene (batch, stream or list), seeded.
//!
//! Batch: `count` shots at rest with centres at random distances from the axis
//! (uniform in area between the two radial offsets), random azimuth and random depth
//! below the inlet plane, placed one by one without overlap. Stream: Poisson (or regular)
//! arrivals at the configured rate, each entering at a random point of the bore's inlet
//! cross-section, clear of the shots that entered shortly before. Same seed, same shots.

use crate::Vec3;
use crate::forces::ShotBody;
use crate::scene::{Feed, Scene, SceneError, SizeDistribution};
use crate::state::{ShotId, ShotState};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, Normal};

/// Attempts per shot before a batch placement is declared impossible.
const PLACEMENT_ATTEMPTS: usize = 20_000;

fn draw_diameter(sizes: &SizeDistribution, rng: &mut ChaCha8Rng) -> f64 {
    match sizes {
        SizeDistribution::Fixed(d) => *d,
        SizeDistribution::Uniform { min, max } => {
            if max > min {
                rng.random_range(*min..=*max)
            } else {
                *min
            }
        }
        SizeDistribution::Normal {
            mean,
            std,
            min,
            max,
        } => {
            if *std == 0.0 {
                return *mean;
            }
            let n = Normal::new(*mean, *std).expect("BUG: validated std");
            loop {
                let d: f64 = n.sample(rng);
                if d >= *min && d <= *max {
                    return d;
                }
            }
        }
        SizeDistribution::Sieve { edges, weights } => {
            let total: f64 = weights.iter().sum();
            let mut u = rng.random_range(0.0..total);
            let mut k = weights.len() - 1;
            for (i, w) in weights.iter().enumerate() {
                if u < *w {
                    k = i;
                    break;
                }
                u -= w;
            }
            rng.random_range(edges[k]..=edges[k + 1])
        }
        SizeDistribution::Discrete { diameters, weights } => {
            let total: f64 = weights.iter().sum();
            let mut u = rng.random_range(0.0..total);
            for (d, w) in diameters.iter().zip(weights) {
                if u < *w {
                    return *d;
                }
                u -= w;
            }
            *diameters.last().expect("BUG: validated non-empty")
        }
    }
}

/// A hash grid of placed shots for overlap checks during placement.
struct Grid {
    cell: f64,
    cells: std::collections::HashMap<(i64, i64, i64), Vec<usize>>,
}

impl Grid {
    fn new(cell: f64) -> Self {
        Grid {
            cell,
            cells: Default::default(),
        }
    }

    fn key(&self, p: &Vec3) -> (i64, i64, i64) {
        (
            (p.x / self.cell).floor() as i64,
            (p.y / self.cell).floor() as i64,
            (p.z / self.cell).floor() as i64,
        )
    }

    fn insert(&mut self, p: &Vec3, index: usize) {
        let k = self.key(p);
        self.cells.entry(k).or_default().push(index);
    }

    /// Whether a sphere of radius `r` at `p` overlaps none of `shots` in the grid.
    fn clear(&self, shots: &[ShotState], p: &Vec3, r: f64) -> bool {
        let (cx, cy, cz) = self.key(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if let Some(v) = self.cells.get(&(cx + dx, cy + dy, cz + dz))
                        && v.iter()
                            .any(|&i| (shots[i].pos - p).norm() < shots[i].body.radius + r)
                    {
                        return false;
                    }
                }
            }
        }
        true
    }
}

/// Mass (kg) of a sphere of diameter `d` (m) and density `rho` (kg/m^3).
pub fn sphere_mass(d: f64, rho: f64) -> f64 {
    rho * std::f64::consts::PI / 6.0 * d * d * d
}

/// The scene's shots, in id order.
pub fn initial_shots(scene: &Scene) -> Result<Vec<ShotState>, SceneError> {
    let mut rng = ChaCha8Rng::seed_from_u64(scene.seed);
    let rho = scene.shot_material.density;
    // Placement in the nozzle frame: centres at a depth below the inlet plane along the
    // axis, at a radial offset across it.
    let inlet = scene.nozzle.inlet();
    let axis = scene.nozzle.axis();
    let (e1, e2) = scene.nozzle.cross_axes();
    let in_bore = |depth: f64, rho: f64, phi: f64| {
        inlet + axis * depth + e1 * (rho * phi.cos()) + e2 * (rho * phi.sin())
    };
    let body = |d: f64| ShotBody {
        radius: 0.5 * d,
        mass: sphere_mass(d, rho),
    };
    let mut shots: Vec<ShotState> = Vec::new();
    match &scene.feed {
        Feed::Batch {
            count,
            radial_min,
            radial_max,
            axial_spread,
        } => {
            let mut grid = Grid::new(2.0 * scene.sizes.max_diameter());
            for i in 0..*count {
                let d = draw_diameter(&scene.sizes, &mut rng);
                let r = 0.5 * d;
                let mut placed = None;
                for _ in 0..PLACEMENT_ATTEMPTS {
                    let rho_r = rng
                        .random_range(radial_min * radial_min..=radial_max * radial_max)
                        .sqrt();
                    let phi = rng.random_range(0.0..std::f64::consts::TAU);
                    let depth = if *axial_spread > 0.0 {
                        rng.random_range(0.0..=*axial_spread)
                    } else {
                        0.0
                    };
                    let p = in_bore(depth, rho_r, phi);
                    if grid.clear(&shots, &p, r) {
                        placed = Some(p);
                        break;
                    }
                }
                let Some(p) = placed else {
                    return Err(SceneError::Invalid {
                        path: scene.path.clone(),
                        key: "shots.feed".into(),
                        message: format!(
                            "cannot place shot {} of {count} without overlap: the placement volume (radial offsets {}-{} mm, axial spread {} mm) is too full; increase axial_spread_mm, widen radial_offset_mm or lower count",
                            i + 1,
                            radial_min * 1e3,
                            radial_max * 1e3,
                            axial_spread * 1e3
                        ),
                    });
                };
                grid.insert(&p, shots.len());
                shots.push(ShotState::new(ShotId(i), p, Vec3::zeros(), body(d), 0.0));
            }
        }
        Feed::Stream {
            rate,
            duration,
            entry_speed,
            poisson,
        } => {
            // A shot blocks its entry spot until drag has moved it one diameter:
            // t_clear = sqrt(2 D / a0) with a0 the drag acceleration from rest in the bore.
            let d_max = scene.sizes.max_diameter();
            let m_min = sphere_mass(scene.sizes.min_diameter(), rho);
            let ui = scene.air.exit_velocity;
            let a0 = 0.5
                * scene.core_density()
                * scene.jet.drag_coefficient
                * std::f64::consts::PI
                * 0.25
                * d_max
                * d_max
                * ui
                * ui
                / m_min;
            let t_clear = (2.0 * d_max / a0.max(1e-9)).sqrt();
            let mut t = 0.0;
            let mut id = 0u32;
            loop {
                t += if *poisson {
                    -rng.random_range(f64::MIN_POSITIVE..1.0f64).ln() / rate
                } else if id == 0 {
                    0.0
                } else {
                    1.0 / rate
                };
                if t >= *duration {
                    break;
                }
                let d = draw_diameter(&scene.sizes, &mut rng);
                let r = 0.5 * d;
                let limit = 0.5 * scene.nozzle.bore - r;
                let mut placed = None;
                let mut t_in = t;
                'search: for _ in 0..1000 {
                    for _ in 0..50 {
                        let rho_r = rng.random_range(0.0..=limit * limit).sqrt();
                        let phi = rng.random_range(0.0..std::f64::consts::TAU);
                        let p = in_bore(0.0, rho_r, phi);
                        let clear = shots
                            .iter()
                            .rev()
                            .take_while(|s| s.t_start > t_in - t_clear)
                            .all(|s| (s.pos - p).norm() >= s.body.radius + r);
                        if clear {
                            placed = Some(p);
                            break 'search;
                        }
                    }
                    // The inlet is crowded: wait a little (deterministically) and retry.
                    t_in += 0.1 * t_clear;
                }
                let Some(p) = placed else {
                    return Err(SceneError::Invalid {
                        path: scene.path.clone(),
                        key: "shots.feed".into(),
                        message: format!(
                            "the stream of {rate:.4e} shots/s cannot enter the {} mm bore without overlap; lower the rate",
                            scene.nozzle.bore * 1e3
                        ),
                    });
                };
                t = t_in;
                if t >= *duration {
                    break;
                }
                shots.push(ShotState::new(
                    ShotId(id),
                    p,
                    Vec3::new(0.0, 0.0, -entry_speed),
                    body(d),
                    t,
                ));
                id += 1;
            }
        }
        Feed::Box {
            count,
            min,
            max,
            velocity,
        } => {
            let mut grid = Grid::new(2.0 * scene.sizes.max_diameter());
            for i in 0..*count {
                let d = draw_diameter(&scene.sizes, &mut rng);
                let r = 0.5 * d;
                let mut placed = None;
                for _ in 0..PLACEMENT_ATTEMPTS {
                    let p = Vec3::new(
                        rng.random_range(min.x + r..=max.x - r),
                        rng.random_range(min.y + r..=max.y - r),
                        rng.random_range(min.z + r..=max.z - r),
                    );
                    if grid.clear(&shots, &p, r) {
                        placed = Some(p);
                        break;
                    }
                }
                let Some(p) = placed else {
                    return Err(SceneError::Invalid {
                        path: scene.path.clone(),
                        key: "shots.feed".into(),
                        message: format!(
                            "cannot place shot {} of {count} without overlap in the box: make it larger or lower count",
                            i + 1
                        ),
                    });
                };
                grid.insert(&p, shots.len());
                shots.push(ShotState::new(ShotId(i), p, *velocity, body(d), 0.0));
            }
        }
        Feed::Bed {
            nx,
            ny,
            layers,
            squeeze,
        } => {
            let d = scene.sizes.max_diameter();
            let a = d * std::f64::consts::SQRT_2 * (1.0 - squeeze);
            let r = 0.5 * d;
            let mut id = 0;
            for k in 0..*layers {
                // (001) layers a/2 apart; alternate layers shift by half a cell.
                let z = r + k as f64 * 0.5 * a;
                let shift = if k % 2 == 0 {
                    [(0.0, 0.0), (0.5, 0.5)]
                } else {
                    [(0.5, 0.0), (0.0, 0.5)]
                };
                for j in 0..*ny {
                    for i in 0..*nx {
                        for (sx, sy) in shift {
                            let p = Vec3::new(
                                (i as f64 + sx + 0.25) * a,
                                (j as f64 + sy + 0.25) * a,
                                z,
                            );
                            shots.push(ShotState::new(ShotId(id), p, Vec3::zeros(), body(d), 0.0));
                            id += 1;
                        }
                    }
                }
            }
        }
        Feed::List(list) => {
            for (i, s) in list.iter().enumerate() {
                shots.push(ShotState::new(
                    ShotId(i as u32),
                    s.position,
                    s.velocity,
                    body(s.diameter),
                    s.start,
                ));
            }
            for (i, a) in shots.iter().enumerate() {
                for b in &shots[..i] {
                    if a.t_start == 0.0
                        && b.t_start == 0.0
                        && (a.pos - b.pos).norm() < a.body.radius + b.body.radius
                    {
                        return Err(SceneError::Invalid {
                            path: scene.path.clone(),
                            key: format!("shots.feed.shots[{}]", a.id.0),
                            message: format!(
                                "overlaps shot {} at the start: move it at least {} mm away",
                                b.id.0,
                                (a.body.radius + b.body.radius) * 1e3
                            ),
                        });
                    }
                }
            }
        }
    }
    Ok(shots)
}
