//! Coverage under a moving nozzle (beyond the paper), from a run with the nozzle held
//! still.
//!
//! Shops set coverage with the traverse speed, the number of passes and the spacing of
//! the passes (the pitch), not with the time a nozzle stays over one spot. A steady
//! stream from a nozzle held still is a stationary process: dent `i` of a run that
//! spans `T` stands for dents arriving at rate `1 / T` at the same place relative to
//! the jet axis. When the nozzle moves at speed `V`, a point of the part at lateral
//! offset `w` from the line the jet axis follows sweeps, relative to the nozzle, along a
//! line through the pattern; it stays inside dent `i`'s disc for its chord at `w`,
//! `2 sqrt(r_i^2 - (w - w_i)^2)`, over `V`. So one pass brings
//!
//! `n(w) = sum_i 2 sqrt(r_i^2 - (w - w_i)^2) / (V T)`
//!
//! dents to that point on average. Shots arrive independently (Poisson), so the point
//! stays undented with probability `exp(-n)`: coverage `1 - exp(-n(w))` along the whole
//! line at `w` (the Avrami law with `n = 1` that a still nozzle's coverage follows at
//! one spot). Passes add: `k` passes over one line bring `k n(w)`; a raster of passes
//! `p` apart brings `n_p(w) = sum_j n(w + j p)`, the same in every strip between two
//! passes. Full coverage (SAE J2277, 98 %) takes `ln 50` dents per point: the speed
//! that reaches it is `V n / ln 50`.
//!
//! The rate comes from the dents' own times (`T` is their span, times `N / (N - 1)`), so
//! a feed that stops before the run ends does not dilute it. Assumed: the run is a
//! steady stream (the pattern does not change over the run), the part is flat (or a
//! bar or groove, on its unrolled surface), and the dents are those of
//! [`super::dents_on`] (rebound hits included). An elliptic dent (a curved part's) is a
//! disc stretched along the track (`Across` below).

use super::Dent;

/// `ln 50`: the dents per point that give 98 % ("full") coverage, `1 - exp(-ln 50)`.
pub const FULL: f64 = 3.912_023_005_428_146;

/// A nozzle moving over the part in straight passes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Traverse {
    /// Speed of the nozzle over the part, m/s.
    pub speed: f64,
    /// Direction of travel in the specimen plane, radians from +x towards +y.
    pub direction: f64,
    /// Distance between neighbouring passes of a raster, m (`None`: one pass).
    pub pitch: Option<f64>,
}

impl Traverse {
    /// The direction in degrees, as typed (the radians' round trip rounded off).
    pub fn direction_deg(&self) -> f64 {
        (self.direction.to_degrees() * 1e9).round() / 1e9
    }
}

/// Expected dents per point across the track, for one pass and for a raster.
#[derive(Debug, Clone)]
pub struct Track {
    /// The traverse.
    pub traverse: Traverse,
    /// Dents of the still nozzle used.
    pub dents: usize,
    /// Runs they come from.
    pub runs: usize,
    /// The still nozzle's dent rate, 1/s.
    pub rate: f64,
    /// Spacing of the profiles' points, m.
    pub spacing: f64,
    /// Width of the lateral band the profiles are averaged over, m (0: none).
    pub band: f64,
    /// One pass across the track, the offset to the left of the line the jet axis
    /// follows (`w = -x sin(direction) + y cos(direction)`).
    pub pass: Vec<Point>,
    /// A raster (with a pitch): offsets in `[0, pitch)`, every pass once.
    pub raster: Option<Vec<Point>>,
    /// The offsets between which one pass brings all but 1 % of its dents on either
    /// side, m: where the profile is worth showing (rebound hits scatter far and thin).
    pub core: (f64, f64),
}

/// Expected dents per point at one lateral offset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    /// Lateral offset, m.
    pub offset: f64,
    /// Expected dents per point (the estimate from the still nozzle's dents).
    pub dents: f64,
    /// The estimate's standard error: each dent of the run is one Poisson draw, so the
    /// variance is the sum of the squares of their contributions.
    pub se: f64,
}

/// Coverage of a point that expects `n` dents: `1 - exp(-n)`.
pub fn coverage(n: f64) -> f64 {
    1.0 - (-n).exp()
}

impl Track {
    /// The profiles of `dents` (of a still nozzle) under `traverse`, with points
    /// `spacing` m apart (made coarser if one pass would need more than 100,000 points),
    /// averaged over lateral bands `band` m wide (0: at the point itself;
    /// a band a few dents wide cuts the estimate's noise, at a bias of the profile's
    /// curvature times `band^2 / 24`). `None` without at least two dents at distinct
    /// times.
    pub fn new(dents: &[Dent], traverse: Traverse, spacing: f64, band: f64) -> Option<Track> {
        Track::pooled(&[dents], traverse, spacing, band)
    }

    /// [`Track::new`] for independent runs of the same still nozzle (a sweep case's
    /// seeds): each dent stands for one over their summed exposure. `None` unless
    /// every run has two dents at distinct times.
    pub fn pooled(runs: &[&[Dent]], traverse: Traverse, spacing: f64, band: f64) -> Option<Track> {
        let exposure = exposure(runs)?;
        let dents: Vec<&Dent> = runs.iter().flat_map(|r| r.iter()).collect();
        let n = dents.len();
        if n == 0 {
            return None;
        }
        let rate = n as f64 / exposure;
        let (s, c) = traverse.direction.sin_cos();
        let across: Vec<Across> = dents.iter().map(|d| Across::of(d, s, c)).collect();
        let reach = |a: &Across, side: f64| a.w + side * (a.half + 0.5 * band);
        let lo = across
            .iter()
            .map(|a| reach(a, -1.0))
            .fold(f64::INFINITY, f64::min);
        let hi = across
            .iter()
            .map(|a| reach(a, 1.0))
            .fold(f64::NEG_INFINITY, f64::max);
        let spacing = spacing.max((hi - lo) / 100_000.0);
        // Each dent stands for one over the exposure dents per second; a point crosses
        // its disc in chord / speed seconds.
        let scale = 1.0 / exposure / traverse.speed;
        let q0 = (lo / spacing).floor() as i64;
        let q1 = (hi / spacing).ceil() as i64;
        let mut sums = vec![(0.0, 0.0); (q1 - q0 + 1) as usize];
        for_each_chord(&across, spacing, band, |q, chord| {
            let s = &mut sums[(q - q0) as usize];
            s.0 += chord * scale;
            s.1 += (chord * scale).powi(2);
        });
        let pass = points(sums, |k| (q0 + k as i64) as f64 * spacing);
        let raster = traverse.pitch.map(|p| {
            // Points over one pitch, `p / m` apart.
            let m = ((p / spacing).ceil() as i64).clamp(1, 100_000);
            let step = p / m as f64;
            let mut sums = vec![(0.0, 0.0); m as usize];
            for_each_chord(&across, step, band, |q, chord| {
                let s = &mut sums[q.rem_euclid(m) as usize];
                s.0 += chord * scale;
                s.1 += (chord * scale).powi(2);
            });
            points(sums, |k| k as f64 * step)
        });
        let core = core_of(&pass);
        Some(Track {
            traverse,
            dents: n,
            runs: runs.len(),
            rate,
            spacing,
            band,
            pass,
            raster,
            core,
        })
    }

    /// One pass's point with the most expected dents (its best line).
    pub fn peak(&self) -> Point {
        least_or_most(&self.pass, |a, b| b.dents > a.dents)
    }

    /// Width (m) of the strip one pass covers to at least `c` (0 < c < 1).
    pub fn width(&self, c: f64) -> f64 {
        let need = -(1.0 - c).ln();
        self.pass.iter().filter(|p| p.dents >= need).count() as f64 * self.spacing
    }

    /// The raster's point with the fewest expected dents, and the mean over the pitch.
    pub fn raster_range(&self) -> Option<(Point, f64)> {
        let r = self.raster.as_ref()?;
        let mean = r.iter().map(|p| p.dents).sum::<f64>() / r.len() as f64;
        Some((least_or_most(r, |a, b| b.dents < a.dents), mean))
    }

    /// The point the coverage target is set on: the raster's least covered, or one
    /// pass's best line.
    pub fn governing(&self) -> Point {
        match self.raster_range() {
            Some((least, _)) => least,
            None => self.peak(),
        }
    }

    /// The fastest traverse (m/s) that reaches full coverage at [`Track::governing`],
    /// and how many passes (rasters) full coverage needs at this traverse's speed
    /// (`None` where no dent reaches).
    pub fn full_coverage(&self) -> Option<(f64, u64)> {
        let n = self.governing().dents;
        (n > 0.0).then(|| {
            (
                self.traverse.speed * n / FULL,
                (FULL / n).ceil().max(1.0) as u64,
            )
        })
    }
}

/// The summed exposure (s) of independent runs of one still nozzle: each run's span of
/// dent times, times `N / (N - 1)` (the mean gap between `N` dents of a steady stream
/// added once). `None` unless every run has two dents at distinct times.
pub(super) fn exposure(runs: &[&[Dent]]) -> Option<f64> {
    let mut exposure = 0.0;
    for dents in runs {
        let (t_lo, t_hi) = dents
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |a, d| {
                (a.0.min(d.t), a.1.max(d.t))
            });
        let n = dents.len();
        if n < 2 || t_hi <= t_lo {
            return None;
        }
        exposure += (t_hi - t_lo) * n as f64 / (n - 1) as f64;
    }
    Some(exposure)
}

/// The offsets between which `pass` holds all but 1 % of its dents on either side.
fn core_of(pass: &[Point]) -> (f64, f64) {
    let total: f64 = pass.iter().map(|p| p.dents).sum();
    let mut sum = 0.0;
    let (mut lo, mut hi) = (None, 0.0);
    for p in pass {
        sum += p.dents;
        if sum >= 0.01 * total && lo.is_none() {
            lo = Some(p.offset);
        }
        if sum <= 0.99 * total {
            hi = p.offset;
        }
    }
    let lo = lo.unwrap_or(0.0);
    (lo, f64::max(hi, lo))
}

/// The profile's points from their sums `(dents, squares)`, at offsets `at(k)`.
pub(super) fn points(sums: Vec<(f64, f64)>, at: impl Fn(usize) -> f64) -> Vec<Point> {
    sums.into_iter()
        .enumerate()
        .map(|(k, (n, sq))| Point {
            offset: at(k),
            dents: n,
            se: sq.sqrt(),
        })
        .collect()
}

/// The first point no other `better` beats.
pub(super) fn least_or_most(pts: &[Point], better: impl Fn(&Point, &Point) -> bool) -> Point {
    let first = pts.first().copied().unwrap_or(Point {
        offset: 0.0,
        dents: 0.0,
        se: 0.0,
    });
    pts.iter()
        .fold(first, |a, p| if better(&a, p) { *p } else { a })
}

/// A dent seen across the track: its lateral offset `w`, the half-width `half` of its
/// shadow across the track, and the ratio `stretch` of its chords along the track to
/// those of the disc of radius `half`. An ellipse with semi-axes `a_x`, `a_y` is the
/// image of that disc under a shear-and-stretch along the track: its half-width across
/// the direction of travel `(c, s)` is `W = sqrt((a_x s)^2 + (a_y c)^2)` and its chord
/// at offset `d` is `(a_x a_y / W^2) 2 sqrt(W^2 - d^2)` (the chords still sum to its
/// area, `pi a_x a_y`). A disc has `W = r` and `stretch = 1`.
#[derive(Debug, Clone, Copy)]
pub(super) struct Across {
    pub(super) w: f64,
    pub(super) half: f64,
    pub(super) stretch: f64,
}

impl Across {
    /// Dent `d` across a track along `(c, s)` (cosine and sine of the direction).
    pub(super) fn of(d: &Dent, s: f64, c: f64) -> Across {
        let w = -d.x * s + d.y * c;
        if d.rx == d.ry {
            return Across {
                w,
                half: d.rx,
                stretch: 1.0,
            };
        }
        let half = (d.rx * s).hypot(d.ry * c);
        Across {
            w,
            half,
            stretch: d.rx * d.ry / (half * half),
        }
    }
}

/// Calls `add(q, chord)` for every point `q spacing` of the line whose band (`band` m
/// wide, centred on it) meets a dent, with the dent's chord along the traverse averaged
/// over the band (the chord through the point itself for `band = 0`; `across`: each
/// dent as the track sees it).
pub(super) fn for_each_chord(
    across: &[Across],
    spacing: f64,
    band: f64,
    mut add: impl FnMut(i64, f64),
) {
    let half = 0.5 * band;
    for a in across {
        let (w, r) = (a.w, a.half);
        let q_lo = ((w - r - half) / spacing).ceil() as i64;
        let q_hi = ((w + r + half) / spacing).floor() as i64;
        for q in q_lo..=q_hi {
            let d = q as f64 * spacing - w;
            let disc = if band > 0.0 {
                (disc_below(d + half, r) - disc_below(d - half, r)) / band
            } else {
                2.0 * (r * r - d * d).max(0.0).sqrt()
            };
            let chord = a.stretch * disc;
            if chord > 0.0 {
                add(q, chord);
            }
        }
    }
}

/// Area of a disc of radius `r` on one side of a line at `u` from its centre (the part
/// with offsets below `u`).
fn disc_below(u: f64, r: f64) -> f64 {
    let u = u.clamp(-r, r);
    r * r * ((u / r).asin() + std::f64::consts::FRAC_PI_2) + u * (r * r - u * u).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dent(x: f64, y: f64, r: f64, t: f64) -> Dent {
        Dent::disc(x, y, r, t)
    }

    #[test]
    fn one_dent_gives_its_chord_over_the_speed_and_the_span() {
        // Two dents at the same place 10 ms apart: rate 100 /s, each standing for 50 /s.
        let ds = [dent(0.0, 0.0, 1e-3, 0.0), dent(0.0, 0.0, 1e-3, 0.01)];
        let tr = Traverse {
            speed: 0.02,
            direction: 0.0,
            pitch: None,
        };
        let t = Track::new(&ds, tr, 1e-5, 0.0).unwrap();
        assert!((t.rate - 100.0).abs() < 1e-9);
        for p in &t.pass {
            let chord = 2.0 * (1e-6 - p.offset * p.offset).max(0.0).sqrt();
            assert!((p.dents - 100.0 * chord / 0.02).abs() < 1e-9, "{p:?}");
            // Two draws of half each: the standard error is the mean over sqrt(2).
            assert!((p.se - p.dents / 2f64.sqrt()).abs() < 1e-9, "{p:?}");
        }
        // The centre line: 100 dents/s x 2 mm / 20 mm/s = 10 dents.
        let p = t.peak();
        assert!(p.offset.abs() < 1e-12 && (p.dents - 10.0).abs() < 1e-9);
        // Travelling along y, the lateral offset is -x: a dent at x = 1 mm sits at -1 mm.
        let moved = [dent(1e-3, 0.0, 1e-3, 0.0), dent(1e-3, 0.0, 1e-3, 0.01)];
        let along_y = Traverse {
            direction: std::f64::consts::FRAC_PI_2,
            ..tr
        };
        let w = Track::new(&moved, along_y, 1e-5, 0.0)
            .unwrap()
            .peak()
            .offset;
        assert!((w + 1e-3).abs() < 1e-9, "{w}");
        // Full coverage on the centre line: 10 / ln 50 times faster, or one pass.
        let (v, passes) = t.full_coverage().unwrap();
        assert!((v - 0.02 * 10.0 / FULL).abs() < 1e-12 && passes == 1);
    }

    #[test]
    fn a_band_averages_the_chords_and_keeps_the_disc_area() {
        let ds = [dent(0.0, 0.0, 1e-3, 0.0), dent(0.0, 0.0, 1e-3, 1.0)];
        let tr = Traverse {
            speed: 1.0,
            direction: 0.0,
            pitch: None,
        };
        // Rate 1 /s and speed 1 m/s: the profile is the mean chord itself, m.
        let t = Track::new(&ds, tr, 1e-6, 2e-3).unwrap();
        // A band as wide as the disc, centred on it: its area over its width, pi r / 2.
        let p = t.peak();
        assert!(p.offset.abs() < 1e-12);
        assert!(
            (p.dents / (std::f64::consts::PI * 1e-3 / 2.0) - 1.0).abs() < 1e-9,
            "{p:?}"
        );
        // Summed across the track, the averaged chords still give the disc's area.
        let area: f64 = t.pass.iter().map(|p| p.dents).sum::<f64>() * t.spacing;
        assert!(
            (area / (std::f64::consts::PI * 1e-6) - 1.0).abs() < 1e-6,
            "{area}"
        );
        // A band of nothing is the chord.
        let narrow = Track::new(&ds, tr, 1e-6, 1e-12).unwrap().peak();
        assert!((narrow.dents - 2e-3).abs() < 1e-9, "{narrow:?}");
    }

    #[test]
    fn pooled_runs_keep_the_rate_and_shrink_the_error() {
        let run: Vec<Dent> = (0..50)
            .map(|k| dent(1e-4 * (k % 7) as f64, 0.0, 1e-3, 1e-3 * k as f64))
            .collect();
        let tr = Traverse {
            speed: 0.05,
            direction: 0.0,
            pitch: Some(2e-3),
        };
        let one = Track::new(&run, tr, 1e-5, 0.0).unwrap();
        let two = Track::pooled(&[&run, &run], tr, 1e-5, 0.0).unwrap();
        assert_eq!((two.dents, two.runs), (100, 2));
        assert!((two.rate / one.rate - 1.0).abs() < 1e-12);
        for (a, b) in one.pass.iter().zip(&two.pass) {
            assert!((a.dents - b.dents).abs() <= 1e-12 * a.dents.max(1.0));
            assert!((a.se - b.se * 2f64.sqrt()).abs() <= 1e-12 * a.se.max(1.0));
        }
        assert!(Track::pooled(&[&run, &run[..1]], tr, 1e-5, 0.0).is_none());
    }

    #[test]
    fn a_raster_folds_the_passes_onto_one_pitch() {
        // Dents of radius 1 mm at one place, 1 /s; passes 0.5 mm apart: every point lies
        // within the disc on three or four passes, whose chords sum to the disc's area
        // over the pitch, pi r^2 / p, on average over the pitch (5.46 mm to 6.52 mm).
        let ds = [dent(0.0, 0.0, 1e-3, 0.0), dent(0.0, 0.0, 1e-3, 1.0)];
        let tr = Traverse {
            speed: 1e-3,
            direction: 0.3,
            pitch: Some(0.5e-3),
        };
        let t = Track::new(&ds, tr, 1e-6, 0.0).unwrap();
        let (least, mean) = t.raster_range().unwrap();
        let expect = std::f64::consts::PI * 1e-6 / 0.5e-3 / 1e-3;
        assert!(
            (mean / expect - 1.0).abs() < 1e-3,
            "{mean} against {expect}"
        );
        // The least, on a pass's line: 2 (1 + 2 sqrt(0.75)) mm of chords.
        let on_line = 2.0 * (1.0 + 2.0 * 0.75f64.sqrt()) * 1e-3 / 1e-3;
        assert!(least.offset.abs() < 1e-9, "{least:?}");
        assert!(
            (least.dents / on_line - 1.0).abs() < 1e-3,
            "{least:?} against {on_line}"
        );
    }

    /// An elliptic dent (a bar's or a groove's) across a track at 30 degrees: each
    /// point's profile is the chord of the line through it along the track, found here
    /// by solving the line-ellipse quadratic; band-averaged, the chords still sum to the
    /// ellipse's area.
    #[test]
    fn an_elliptic_dent_gives_its_chords_along_the_track() {
        let (rx, ry) = (1e-3, 0.4e-3);
        let e = |t| Dent {
            x: 0.0,
            y: 0.0,
            rx,
            ry,
            t,
        };
        let ds = [e(0.0), e(1.0)];
        let dir = 30f64.to_radians();
        let tr = Traverse {
            speed: 1.0,
            direction: dir,
            pitch: None,
        };
        // Rate 1 /s and speed 1 m/s: the profile is the chord itself, m.
        let t = Track::new(&ds, tr, 1e-6, 0.0).unwrap();
        let (s, c) = dir.sin_cos();
        let mut checked = 0;
        for p in &t.pass {
            // Points w (-s, c) + tau (c, s) with (x/rx)^2 + (y/ry)^2 = 1.
            let (px, py) = (-p.offset * s, p.offset * c);
            let a = (c / rx).powi(2) + (s / ry).powi(2);
            let b = 2.0 * (px * c / (rx * rx) + py * s / (ry * ry));
            let k = (px / rx).powi(2) + (py / ry).powi(2) - 1.0;
            let disc = b * b - 4.0 * a * k;
            let chord = if disc > 0.0 { disc.sqrt() / a } else { 0.0 };
            assert!((p.dents - chord).abs() < 1e-12, "{p:?} against {chord}");
            checked += (chord > 0.0) as usize;
        }
        assert!(checked > 500, "{checked}");
        let area: f64 = Track::new(&ds, tr, 1e-6, 0.3e-3)
            .unwrap()
            .pass
            .iter()
            .map(|p| p.dents)
            .sum::<f64>()
            * 1e-6;
        let expect = std::f64::consts::PI * rx * ry;
        assert!(
            (area / expect - 1.0).abs() < 1e-6,
            "{area} against {expect}"
        );
    }
}
