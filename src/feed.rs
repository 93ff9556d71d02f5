//! Feed stage: creates the shots of a scene (batch, stream or list), seeded.
//!
//! Batch: `count` shots at rest with centres at random distances from the axis
//! (uniform in area between the two radial offsets), random azimuth and random depth
//! below the inlet plane, placed one by one without overlap. Stream: Poisson (or regular)
//! arrivals at the configured rate, each entering at a random point of the bore's inlet
//! cross-section, clear of the shots that entered shortly before. Same seed, same shots.

use crate::Vec3;
use crate::forces::ShotBody;
use crate::scene::validate::num;
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
    cells: rustc_hash::FxHashMap<(i64, i64, i64), Vec<usize>>,
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
            crate::floor_i64(p.x / self.cell),
            crate::floor_i64(p.y / self.cell),
            crate::floor_i64(p.z / self.cell),
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

    /// Draws up to `PLACEMENT_ATTEMPTS` centres with `draw` and takes the first where a
    /// sphere of radius `r` overlaps none of `shots`: it is entered in the grid as shot
    /// `shots.len()` (the caller pushes it next). `None`: no draw was clear.
    fn place(
        &mut self,
        shots: &[ShotState],
        r: f64,
        mut draw: impl FnMut() -> Vec3,
    ) -> Option<Vec3> {
        let p = (0..PLACEMENT_ATTEMPTS)
            .map(|_| draw())
            .find(|p| self.clear(shots, p, r))?;
        self.insert(&p, shots.len());
        Some(p)
    }
}

/// Mass (kg) of a sphere of diameter `d` (m) and density `rho` (kg/m^3).
pub fn sphere_mass(d: f64, rho: f64) -> f64 {
    rho * std::f64::consts::PI / 6.0 * d * d * d
}

/// A stream feed's shots, generated one at a time in id (= entry time) order, so a run
/// can create each shot when it enters instead of holding every shot of the stream.
/// Same seed, same shots as [`initial_shots`] (which collects this iterator).
pub struct StreamFeed {
    rng: ChaCha8Rng,
    rate: f64,
    duration: f64,
    entry_speed: f64,
    poisson: bool,
    t_clear: f64,
    inlet: Vec3,
    /// Unit vector along the nozzle axis, downstream: shots enter moving along it.
    axis: Vec3,
    e1: Vec3,
    e2: Vec3,
    bore: f64,
    sizes: SizeDistribution,
    density: f64,
    path: String,
    t: f64,
    id: u32,
    /// Regular arrivals: the entry time and id they count from (`(0, 0)`, moved to a
    /// shot the crowded inlet held back), so that shot `id` enters at
    /// `t0 + (id - id0) / rate` without a running sum's rounding (which let a 250 ms
    /// feed at 40,000 shots/s deliver a 10,001st shot at 249.999... ms).
    regular_from: (f64, u32),
    done: bool,
    /// Shots that entered within `t_clear` of the newest (centre, radius, entry time).
    recent: std::collections::VecDeque<(Vec3, f64, f64)>,
}

impl StreamFeed {
    /// The generator of `scene`'s stream (a scene without a stream feed yields nothing).
    pub fn of_scene(scene: &Scene) -> Self {
        StreamFeed::new(scene, ChaCha8Rng::seed_from_u64(scene.seed))
    }

    fn new(scene: &Scene, rng: ChaCha8Rng) -> Self {
        let (rate, duration, entry_speed, poisson) = match &scene.feed {
            Feed::Stream {
                rate,
                duration,
                entry_speed,
                poisson,
            } => (*rate, *duration, *entry_speed, *poisson),
            _ => (1.0, 0.0, 0.0, false),
        };
        let rho = scene.shot_material.density;
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
        let (e1, e2) = scene.nozzle.cross_axes();
        StreamFeed {
            rng,
            rate,
            duration,
            entry_speed,
            poisson,
            t_clear: (2.0 * d_max / a0.max(1e-9)).sqrt(),
            inlet: scene.nozzle.inlet(),
            axis: scene.nozzle.axis(),
            e1,
            e2,
            bore: scene.nozzle.bore,
            sizes: scene.sizes.clone(),
            density: rho,
            path: scene.path.clone(),
            t: 0.0,
            id: 0,
            regular_from: (0.0, 0),
            done: !matches!(scene.feed, Feed::Stream { .. }),
            recent: Default::default(),
        }
    }

    /// The next shot, `None` once the stream's duration is over; an error when the
    /// shots cannot enter the bore without overlap.
    pub fn next_shot(&mut self) -> Result<Option<ShotState>, SceneError> {
        if self.done {
            return Ok(None);
        }
        let rate = self.rate;
        self.t = if self.poisson {
            self.t - self.rng.random_range(f64::MIN_POSITIVE..1.0f64).ln() / rate
        } else {
            let (t0, id0) = self.regular_from;
            t0 + f64::from(self.id - id0) / rate
        };
        if self.t >= self.duration {
            self.done = true;
            return Ok(None);
        }
        let d = draw_diameter(&self.sizes, &mut self.rng);
        let r = 0.5 * d;
        let limit = 0.5 * self.bore - r;
        let mut placed = None;
        let mut t_in = self.t;
        'search: for _ in 0..1000 {
            for _ in 0..50 {
                let rho_r = self.rng.random_range(0.0..=limit * limit).sqrt();
                let phi = self.rng.random_range(0.0..std::f64::consts::TAU);
                let p = self.inlet + self.e1 * (rho_r * phi.cos()) + self.e2 * (rho_r * phi.sin());
                let clear = self
                    .recent
                    .iter()
                    .rev()
                    .take_while(|s| s.2 > t_in - self.t_clear)
                    .all(|s| (s.0 - p).norm() >= s.1 + r);
                if clear {
                    placed = Some(p);
                    break 'search;
                }
            }
            // The inlet is crowded: wait a little (deterministically) and retry.
            t_in += 0.1 * self.t_clear;
        }
        let Some(p) = placed else {
            self.done = true;
            return Err(SceneError::Invalid {
                path: self.path.clone(),
                key: "shots.feed".into(),
                message: format!(
                    "the stream of {rate:.4e} shots/s cannot enter the {} mm bore without overlap; lower the rate",
                    num(self.bore * 1e3)
                ),
            });
        };
        if t_in > self.t {
            self.regular_from = (t_in, self.id);
        }
        self.t = t_in;
        if self.t >= self.duration {
            self.done = true;
            return Ok(None);
        }
        // Entry times only grow: shots that entered before t - t_clear never block again.
        while self
            .recent
            .front()
            .is_some_and(|s| s.2 <= self.t - self.t_clear)
        {
            self.recent.pop_front();
        }
        self.recent.push_back((p, r, self.t));
        let body = ShotBody {
            radius: r,
            mass: sphere_mass(d, self.density),
        };
        // Along the bore (until session 29 straight down, whatever the nozzle's tilt:
        // at 45 degrees a shot entered moving at 45 degrees to the bore).
        let shot = ShotState::new(
            ShotId(self.id),
            p,
            self.axis * self.entry_speed,
            body,
            self.t,
        );
        self.id += 1;
        Ok(Some(shot))
    }
}

/// The scene's shots, in id order; a list's shots that overlap at the start are refused
/// if the scene's shot-shot contact is on.
pub fn initial_shots(scene: &Scene) -> Result<Vec<ShotState>, SceneError> {
    placed_shots(scene, scene.effects().shot_shot_contact)
}

/// The scene's shots, in id order; a list's shots that overlap at the start are refused
/// if `apart` (they would meet: shot-shot contact is on), let be if not.
pub fn placed_shots(scene: &Scene, apart: bool) -> Result<Vec<ShotState>, SceneError> {
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
                let placed = grid.place(&shots, 0.5 * d, || {
                    let rho_r = rng
                        .random_range(radial_min * radial_min..=radial_max * radial_max)
                        .sqrt();
                    let phi = rng.random_range(0.0..std::f64::consts::TAU);
                    let depth = if *axial_spread > 0.0 {
                        rng.random_range(0.0..=*axial_spread)
                    } else {
                        0.0
                    };
                    in_bore(depth, rho_r, phi)
                });
                let Some(p) = placed else {
                    return Err(SceneError::Invalid {
                        path: scene.path.clone(),
                        key: "shots.feed".into(),
                        message: format!(
                            "cannot place shot {} of {count} without overlap: the placement volume (radial offsets {}-{} mm, axial spread {} mm) is too full; increase axial_spread_mm, widen radial_offset_mm or lower count",
                            i + 1,
                            num(radial_min * 1e3),
                            num(radial_max * 1e3),
                            num(axial_spread * 1e3)
                        ),
                    });
                };
                shots.push(ShotState::new(ShotId(i), p, Vec3::zeros(), body(d), 0.0));
            }
        }
        Feed::Stream { .. } => {
            let mut feed = StreamFeed::new(scene, rng);
            while let Some(shot) = feed.next_shot()? {
                shots.push(shot);
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
                let placed = grid.place(&shots, r, || {
                    Vec3::new(
                        rng.random_range(min.x + r..=max.x - r),
                        rng.random_range(min.y + r..=max.y - r),
                        rng.random_range(min.z + r..=max.z - r),
                    )
                });
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
                    if apart
                        && a.t_start == 0.0
                        && b.t_start == 0.0
                        && (a.pos - b.pos).norm() < a.body.radius + b.body.radius
                    {
                        return Err(SceneError::Invalid {
                            path: scene.path.clone(),
                            key: format!("shots.feed.shots[{}]", a.id.0),
                            message: format!(
                                "overlaps shot {} at the start: move it at least {} mm away",
                                b.id.0,
                                num((a.body.radius + b.body.radius) * 1e3)
                            ),
                        });
                    }
                }
            }
        }
    }
    Ok(shots)
}
