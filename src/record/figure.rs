//! The run's picture, `impacts.png` / `impacts.svg`: where the shots hit the specimen,
//! coloured by normal impact speed, next to the histograms of the normal impact speed and
//! of the impact angle (first hits and rebound hits apart).
//!
//! [`ImpactFigure`] is a [`RunSink`]: it sees every impact as the run hands it over and
//! keeps what the picture needs in bounded memory, so the run still holds only the shots
//! in flight.
//! * The histograms count every impact, in fine bins (0.1 m/s, 1 degree) merged into
//!   at most 25 bars of 1-2-5 widths at the end (5-degree bars for the angle).
//! * The map draws every impact up to [`MAP_POINTS`], then a sample: every second,
//!   fourth, ... impact in the run's (time, shot) order, so the picture does
//!   not depend on the thread count. The title says when it is a sample. Faster impacts
//!   are drawn over slower ones, first hits over rebound hits.
//! * The frame is square, centred on the jet axis' foot when the air jet acts on the shots
//!   (on the middle of the impacts otherwise), and wide enough for the nearest 95 %
//!   of the impacts with a margin: the few far rebounds would otherwise shrink the
//!   pattern to a dot. The panel's title counts the impacts left outside.

use super::Impact;
use crate::contact::specimen::SpecimenShape;
use crate::plot::{self, BarPanel, Bars, Map, MapPoint};
use crate::sim::RunSink;
use crate::state::ShotState;
use std::path::Path;

/// The map draws every impact up to this many, and between half and all of this many
/// beyond.
pub const MAP_POINTS: usize = 10_000;

/// Fine bins of the normal speed, m/s; faster impacts go to an overflow count.
const SPEED_FINE: f64 = 0.1;
const SPEED_FINE_BINS: usize = 10_000;

/// Bars of a histogram at most.
const BARS: usize = 25;

/// Share of the sampled impacts the frame holds at least.
const FRAMED: f64 = 0.95;

/// One sampled impact: position (mm), normal speed (m/s), first hit.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Sampled {
    x: f64,
    y: f64,
    normal: f64,
    first: bool,
}

impl Sampled {
    /// On the specimen's unrolled surface ([`SpecimenShape::unrolled`]; the plane's x, y).
    fn of(i: &Impact, shape: &SpecimenShape) -> Sampled {
        let (x, y) = shape.unrolled(&crate::Vec3::new(i.x_m, i.y_m, i.z_m));
        Sampled {
            x: x * 1e3,
            y: y * 1e3,
            normal: i.normal_speed_m_s,
            first: i.first_hit == 1,
        }
    }
}

/// The map's axis labels: the plane's x and y, or a cylinder's unrolled surface.
fn axis_names(shape: &SpecimenShape) -> (String, String) {
    let (x, y) = shape.unrolled_names();
    (format!("{x}, mm"), format!("{y}, mm"))
}

/// Every impact up to [`MAP_POINTS`], then every second, fourth, ... one.
#[derive(Debug, Clone)]
struct Thinned {
    items: Vec<Sampled>,
    stride: u64,
    seen: u64,
}

impl Default for Thinned {
    fn default() -> Self {
        Thinned {
            items: Vec::new(),
            stride: 1,
            seen: 0,
        }
    }
}

impl Thinned {
    fn offer(&mut self, i: &Impact, shape: &SpecimenShape) {
        if self.seen.is_multiple_of(self.stride) {
            self.items.push(Sampled::of(i, shape));
            if self.items.len() > MAP_POINTS {
                // Keep every second one: the sample stays every `stride`-th impact.
                let mut k = 0;
                self.items.retain(|_| {
                    k += 1;
                    k % 2 == 1
                });
                self.stride *= 2;
            }
        }
        self.seen += 1;
    }

    /// "N impacts", or "1 in S of N impacts (M drawn)".
    fn describe(&self) -> String {
        if self.stride > 1 {
            format!(
                "1 in {} of {} impacts ({} drawn)",
                self.stride,
                self.seen,
                self.items.len()
            )
        } else {
            plural(self.seen, "impact")
        }
    }

    fn points(&self) -> Vec<MapPoint> {
        self.items
            .iter()
            .map(|s| MapPoint {
                x: s.x,
                y: s.y,
                value: s.normal,
                filled: s.first,
            })
            .collect()
    }
}

/// Fine histograms of one group of impacts.
#[derive(Debug, Clone)]
struct Counts {
    speed: Vec<u64>,
    overflow: u64,
    angle: [u64; 90],
}

impl Default for Counts {
    fn default() -> Self {
        Counts {
            speed: vec![0; SPEED_FINE_BINS],
            overflow: 0,
            angle: [0; 90],
        }
    }
}

impl Counts {
    fn add(&mut self, i: &Impact) {
        let k = (i.normal_speed_m_s.max(0.0) / SPEED_FINE) as usize;
        match self.speed.get_mut(k) {
            Some(c) => *c += 1,
            None => self.overflow += 1,
        }
        self.angle[i.angle_deg.clamp(0.0, 89.0) as usize] += 1;
    }

    fn total(&self) -> u64 {
        self.angle.iter().sum()
    }
}

/// The two histogram panels' data: normal speed and impact angle, one bar set per group.
struct Histograms {
    speed_title: String,
    speed_axis: String,
    speed_edges: Vec<String>,
    speed_bars: Vec<Bars>,
    angle_edges: Vec<String>,
    angle_bars: Vec<Bars>,
    y_label: &'static str,
}

impl Histograms {
    /// Bars of `groups` (name, counts), as counts or, with `share`, as per cent of each
    /// group.
    fn of(groups: &[(&str, &Counts)], share: bool) -> Histograms {
        let scale = |c: &Counts| {
            if share {
                100.0 / c.total().max(1) as f64
            } else {
                1.0
            }
        };
        // Normal speed: bars up to the fastest impact within the fine bins.
        let top = groups
            .iter()
            .filter_map(|g| g.1.speed.iter().rposition(|&c| c > 0))
            .max()
            .map_or(1, |i| i + 1);
        let w = bar_width(top);
        let nbars = top.div_ceil(w);
        let bars = |fine: &dyn Fn(&Counts) -> &[u64], merge: usize, n: usize| -> Vec<Bars> {
            groups
                .iter()
                .map(|(name, c)| Bars {
                    name: name.to_string(),
                    values: merged(fine(c), merge, n)
                        .into_iter()
                        .map(|v| v * scale(c))
                        .collect(),
                })
                .collect()
        };
        let overflow: u64 = groups.iter().map(|g| g.1.overflow).sum();
        Histograms {
            speed_title: if overflow > 0 {
                format!(
                    "Normal impact speed ({overflow} above {} m/s not shown)",
                    label(SPEED_FINE * SPEED_FINE_BINS as f64)
                )
            } else {
                "Normal impact speed".to_string()
            },
            speed_axis: format!(
                "normal speed, m/s ({} m/s bins, lower edge)",
                label(w as f64 * SPEED_FINE)
            ),
            speed_edges: (0..nbars)
                .map(|b| label(b as f64 * w as f64 * SPEED_FINE))
                .collect(),
            speed_bars: bars(&|c| &c.speed, w, nbars),
            angle_edges: (0..18).map(|b| (5 * b).to_string()).collect(),
            angle_bars: bars(&|c| &c.angle, 5, 18),
            y_label: if share {
                "share of impacts, %"
            } else {
                "impacts"
            },
        }
    }

    fn panels(&self) -> [BarPanel<'_>; 2] {
        [
            BarPanel {
                title: &self.speed_title,
                labels: (&self.speed_axis, self.y_label),
                categories: &self.speed_edges,
                bars: &self.speed_bars,
            },
            BarPanel {
                title: "Impact angle from the normal",
                labels: ("angle, degrees (5-degree bins, lower edge)", self.y_label),
                categories: &self.angle_edges,
                bars: &self.angle_bars,
            },
        ]
    }
}

/// Collects a run's impacts for its picture (see the module docs).
#[derive(Debug, Clone, Default)]
pub struct ImpactFigure {
    sample: Thinned,
    /// `[first hits, rebound hits]`.
    counts: [Counts; 2],
    /// The specimen's surface: the map is drawn on it, unrolled.
    shape: SpecimenShape,
}

impl ImpactFigure {
    /// The figure of a run on the specimen surface `shape`.
    pub fn on(shape: SpecimenShape) -> Self {
        ImpactFigure {
            shape,
            ..Default::default()
        }
    }
}

impl RunSink for ImpactFigure {
    fn impacts(&mut self, batch: &[Impact]) {
        for i in batch {
            self.counts[usize::from(i.first_hit != 1)].add(i);
            self.sample.offer(i, &self.shape);
        }
    }

    fn shot(&mut self, _shot: &ShotState) {}
}

/// `bins` bars of `fine` counts, `merge` fine bins each, from the first.
fn merged(fine: &[u64], merge: usize, bins: usize) -> Vec<f64> {
    fine.chunks(merge)
        .take(bins)
        .map(|c| c.iter().sum::<u64>() as f64)
        .collect()
}

/// The bar width among 1-2-5 steps (in fine bins) that puts `top` fine bins into at most
/// [`BARS`] bars.
fn bar_width(top: usize) -> usize {
    [1, 2, 5, 10, 20, 50, 100, 200, 500, 1000, 2000, 5000, 10_000]
        .into_iter()
        .find(|w| top.div_ceil(*w) <= BARS)
        .unwrap_or(10_000)
}

/// `n` and `thing`, in the plural unless `n` is 1.
fn plural(n: u64, thing: &str) -> String {
    if n == 1 {
        format!("1 {thing}")
    } else {
        format!("{n} {thing}s")
    }
}

fn label(v: f64) -> String {
    let s = format!("{v:.1}");
    s.trim_end_matches('0').trim_end_matches('.').to_string()
}

/// The square frame `[x0, x1, y0, y1]` (mm) about `centre` (the middle of `points` when
/// `None`) holding the nearest [`FRAMED`] of them with a margin, and the points outside.
fn frame(points: &[Sampled], centre: Option<(f64, f64)>) -> ([f64; 4], usize) {
    let (cx, cy) = centre.unwrap_or_else(|| {
        let mid = |f: fn(&Sampled) -> f64| {
            let mut v: Vec<f64> = points.iter().map(f).collect();
            v.sort_by(f64::total_cmp);
            v.get(v.len() / 2).copied().unwrap_or(0.0)
        };
        (mid(|s| s.x), mid(|s| s.y))
    });
    let mut d: Vec<f64> = points
        .iter()
        .map(|s| (s.x - cx).abs().max((s.y - cy).abs()))
        .collect();
    d.sort_by(f64::total_cmp);
    let half = match d.len() {
        0 => 1.0,
        n => {
            let framed = d[((FRAMED * n as f64).ceil() as usize).clamp(1, n) - 1];
            // A margin of a fifth, but no wider than the farthest impact needs.
            (1.2 * framed).min(1.05 * d[n - 1]).max(0.5)
        }
    };
    let outside = d.iter().filter(|&&v| v > half).count();
    ([cx - half, cx + half, cy - half, cy + half], outside)
}

impl ImpactFigure {
    /// Writes `stem.png` and `stem.svg`. `axis_foot`: where the jet axis meets the
    /// specimen (mm), when the air jet acts on the shots.
    pub fn write(
        &self,
        stem: &Path,
        title: &str,
        axis_foot: Option<(f64, f64)>,
    ) -> Result<(), plot::PlotError> {
        let [firsts, rebounds] = [0, 1].map(|k| self.counts[k].total());
        let mut groups = vec![("first hits", &self.counts[0])];
        if rebounds > 0 {
            groups.push(("rebound hits", &self.counts[1]));
        }
        let hist = Histograms::of(&groups, false);
        let (extent, outside) = frame(&self.sample.items, axis_foot);
        let points = self.sample.points();
        let value_max = points.iter().map(|p| p.value).fold(0.0, f64::max);
        let what = self.sample.describe();
        let names = axis_names(&self.shape);
        let map_title = if outside > 0 {
            format!("Where the shots hit: {what}, {outside} outside the frame")
        } else {
            format!("Where the shots hit: {what}")
        };
        let map = Map {
            title: &map_title,
            labels: (&names.0, &names.1),
            extent,
            points: &points,
            background: &[],
            value_label: "normal speed, m/s",
            value_max,
            kinds: ("first hit", "rebound hit"),
            cross: axis_foot.map(|(x, y)| (x, y, "jet axis")),
            outlines: &[],
        };
        let whole = format!(
            "{title}: {} ({}, {})",
            plural(self.sample.seen, "impact"),
            plural(firsts, "first hit"),
            plural(rebounds, "rebound hit")
        );
        plot::map_with_bars(stem, &whole, &map, &hist.panels())
    }
}

/// The picture of an export's selection (`selection.png` / `.svg`): the selected impacts
/// coloured by normal speed over every impact of the file in grey, with `outlines`
/// (rectangles in mm: the `--window`, the FE target block) and the jet axis' foot;
/// beside them the shares of normal speed and impact angle, selected against all, which
/// show how representative the selection is.
#[allow(clippy::too_many_arguments)]
pub fn selection(
    title: &str,
    shape: &SpecimenShape,
    all: &[Impact],
    selected: &[Impact],
    outlines: &[([f64; 4], &str)],
    axis_foot: Option<(f64, f64)>,
) -> Result<plot::Rendered, plot::PlotError> {
    let (mut every, mut chosen) = (Thinned::default(), Thinned::default());
    let (mut c_all, mut c_sel) = (Counts::default(), Counts::default());
    for i in all {
        every.offer(i, shape);
        c_all.add(i);
    }
    for i in selected {
        chosen.offer(i, shape);
        c_sel.add(i);
    }
    let hist = Histograms::of(&[("all impacts", &c_all), ("selected", &c_sel)], true);
    let names = axis_names(shape);
    // The selection's own frame, widened to hold the outlines, then a quarter more for
    // the impacts around it.
    let ([x0, x1, y0, y1], _) = frame(&chosen.items, None);
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    let half = outlines
        .iter()
        .flat_map(|(r, _)| {
            [
                (r[0] - cx).abs(),
                (r[1] - cx).abs(),
                (r[2] - cy).abs(),
                (r[3] - cy).abs(),
            ]
        })
        .fold(0.5 * (x1 - x0), f64::max)
        * 1.25;
    let extent = [cx - half, cx + half, cy - half, cy + half];
    let inside =
        |s: &&Sampled| s.x >= extent[0] && s.x <= extent[1] && s.y >= extent[2] && s.y <= extent[3];
    let outside = chosen.items.iter().filter(|s| !inside(s)).count();
    let background: Vec<(f64, f64)> = every.items.iter().map(|s| (s.x, s.y)).collect();
    let points = chosen.points();
    let value_max = points.iter().map(|p| p.value).fold(0.0, f64::max);
    let map_title = format!(
        "Selected: {}{}; grey: all {}",
        chosen.describe(),
        if outside > 0 {
            format!(", {outside} outside the frame")
        } else {
            String::new()
        },
        every.describe()
    );
    let map = Map {
        title: &map_title,
        labels: (&names.0, &names.1),
        extent,
        points: &points,
        background: &background,
        value_label: "normal speed, m/s",
        value_max,
        kinds: ("first hit", "rebound hit"),
        cross: axis_foot.map(|(x, y)| (x, y, "jet axis")),
        outlines,
    };
    let whole = format!(
        "{title}: {} of {} selected",
        selected.len(),
        plural(all.len() as u64, "impact")
    );
    plot::render_map_with_bars(&whole, &map, &hist.panels())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Vec3;

    fn impact(k: u32, x_mm: f64, normal: f64, first: bool) -> Impact {
        let v = Vec3::new(0.3 * normal, 0.0, -normal);
        let p = Vec3::new(x_mm * 1e-3, 0.0, 4e-4);
        Impact::new(
            k,
            k as f64 * 1e-6,
            &p,
            &v,
            &Vec3::zeros(),
            4e-4,
            2e-6,
            0,
            first,
        )
    }

    #[test]
    fn the_sample_is_every_stride_th_impact_and_the_histograms_count_all() {
        let mut f = ImpactFigure::default();
        let n = 5 * MAP_POINTS as u32 / 2 + 17;
        let batch: Vec<Impact> = (0..n)
            .map(|k| impact(k, k as f64 * 1e-3, 10.0 + (k % 40) as f64, k % 3 != 0))
            .collect();
        // Handed over in uneven batches, as a run does.
        for part in batch.chunks(777) {
            f.impacts(part);
        }
        assert_eq!(f.sample.seen, n as u64);
        assert!(f.sample.items.len() > MAP_POINTS / 2 && f.sample.items.len() <= MAP_POINTS);
        assert_eq!(f.sample.stride, 4);
        for (j, s) in f.sample.items.iter().enumerate() {
            let k = j as u64 * f.sample.stride;
            assert!(
                (s.x - k as f64 * 1e-3).abs() < 1e-9,
                "sample {j} is impact {k}"
            );
        }
        let all: u64 = f.counts.iter().flat_map(|c| c.speed.iter()).sum::<u64>();
        assert_eq!(all, n as u64);
        let firsts: u64 = f.counts[0].angle.iter().sum();
        assert_eq!(firsts, (0..n).filter(|k| k % 3 != 0).count() as u64);
        // Every impact at atan(0.3) = 16.7 degrees.
        assert_eq!(f.counts[0].angle[16] + f.counts[1].angle[16], n as u64);
    }

    #[test]
    fn shares_add_up_to_a_hundred_per_group() {
        let (mut a, mut b) = (Counts::default(), Counts::default());
        for k in 0..1000u32 {
            a.add(&impact(k, 0.0, (k % 97) as f64, true));
            if k % 7 == 0 {
                b.add(&impact(k, 0.0, 50.0 + (k % 13) as f64, k % 2 == 0));
            }
        }
        let h = Histograms::of(&[("all", &a), ("some", &b)], true);
        for bars in [&h.speed_bars, &h.angle_bars] {
            for g in bars {
                let sum: f64 = g.values.iter().sum();
                assert!((sum - 100.0).abs() < 1e-9, "{}: {sum}", g.name);
            }
        }
        // 96 m/s at most: 5 m/s bars (fine bins of 0.1 m/s, 20 bars).
        assert_eq!(h.speed_edges.len(), 20);
        assert_eq!(h.speed_edges[3], "15");
        assert_eq!(h.y_label, "share of impacts, %");
    }

    #[test]
    fn bars_merge_fine_bins_into_at_most_25() {
        assert_eq!(bar_width(1), 1);
        assert_eq!(bar_width(25), 1);
        assert_eq!(bar_width(26), 2);
        assert_eq!(bar_width(640), 50); // 64 m/s in 5 m/s bars
        assert_eq!(merged(&[1, 2, 3, 4, 5, 6, 7], 3, 3), vec![6.0, 15.0, 7.0]);
    }

    #[test]
    fn the_frame_holds_the_nearest_impacts_and_counts_the_rest() {
        let mut f = ImpactFigure::default();
        // 99 impacts within 5 mm of the axis, one 90 mm away.
        let batch: Vec<Impact> = (0..100)
            .map(|k| {
                impact(
                    k,
                    if k == 50 { 90.0 } else { (k % 11) as f64 - 5.0 },
                    50.0,
                    true,
                )
            })
            .collect();
        f.impacts(&batch);
        let (e, outside) = frame(&f.sample.items, Some((0.0, 0.0)));
        assert_eq!(outside, 1);
        assert!((e[1] - 6.0).abs() < 1e-12, "{e:?}"); // 1.2 x 5 mm
        assert_eq!(e[0], -e[1]);
        // All near: the frame just holds the farthest.
        let g = {
            let mut g = ImpactFigure::default();
            g.impacts(&batch[..50]);
            g
        };
        let (e, outside) = frame(&g.sample.items, Some((0.0, 0.0)));
        assert_eq!(outside, 0);
        assert!((e[1] - 5.25).abs() < 1e-12, "{e:?}");
    }
}
