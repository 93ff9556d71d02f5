//! Plots as PNG and SVG (plotters). Text is set in DejaVu Sans, embedded by the `dejavu`
//! crate, so no system font or fontconfig is needed on the machine.

use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;
use thiserror::Error;

/// Plotting errors.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum PlotError {
    /// Drawing or writing failed.
    #[error("{path}: cannot draw the plot: {message}")]
    Draw {
        /// File.
        path: String,
        /// Cause.
        message: String,
    },
}

/// One named curve.
#[derive(Debug, Clone)]
pub struct Series {
    /// Legend label.
    pub name: String,
    /// Points `(x, y)`.
    pub points: Vec<(f64, f64)>,
}

/// A named set of bars on shared categories (a grouped bar chart / histogram).
#[derive(Debug, Clone)]
pub struct Bars {
    /// Legend label.
    pub name: String,
    /// One value per category.
    pub values: Vec<f64>,
}

fn register_fonts() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let _ = plotters::style::register_font(
            "sans-serif",
            FontStyle::Normal,
            dejavu::sans::regular(),
        );
        let _ = plotters::style::register_font("sans-serif", FontStyle::Bold, dejavu::sans::bold());
    });
}

const COLORS: [RGBColor; 6] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(255, 127, 14),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
];

/// A figure rendered in memory: `(extension, bytes)` of its PNG and its SVG.
pub type Rendered = [(&'static str, Vec<u8>); 2];

/// Renders `draw(root, args...)` on a drawing area of `size` pixels of each backend, in
/// memory: `Result<Rendered, String>`.
macro_rules! render_both {
    ($size:expr, $draw:ident($($arg:expr),*)) => {{
        register_fonts();
        (|| -> Result<Rendered, Box<dyn std::error::Error>> {
            let (w, h): (u32, u32) = $size;
            let mut rgb = vec![0u8; w as usize * h as usize * 3];
            $draw(BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area(), $($arg),*)?;
            let mut png = Vec::new();
            image::ImageEncoder::write_image(
                image::codecs::png::PngEncoder::new(&mut png),
                &rgb,
                w,
                h,
                image::ColorType::Rgb8,
            )?;
            let mut svg = String::new();
            $draw(SVGBackend::with_string(&mut svg, (w, h)).into_drawing_area(), $($arg),*)?;
            Ok([("png", png), ("svg", svg.into_bytes())])
        })()
        .map_err(|e| e.to_string())
    }};
}

/// Renders as [`render_both`] and writes `stem.png` and `stem.svg` (see [`write`]).
macro_rules! draw_both {
    ($stem:expr, $size:expr, $draw:ident($($arg:expr),*)) => {
        render_both!($size, $draw($($arg),*))
            .map_err(|message| PlotError::Draw {
                path: $stem.display().to_string(),
                message,
            })
            .and_then(|r| write($stem, &r))
    };
}

type DResult = Result<(), Box<dyn std::error::Error>>;

/// Axis label: plain for ordinary magnitudes, `1e-6` style otherwise.
fn short(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-2..1e4).contains(&a) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        format!("{v:.0e}")
    }
}

/// A log axis' label: as [`short`], but an axis that reaches below 1e-2 writes all its
/// labels under 1 as `5e-3`, `1e-2`, `2e-2` rather than a mix such as `5e-3`, `0.01`.
fn log_label(v: f64, lo: f64) -> String {
    if lo < 1e-2 && v.abs() < 1.0 {
        format!("{v:.0e}")
    } else {
        short(v)
    }
}

/// Labelled and light ticks of a log axis over `[lo, hi]` (`0 < lo < hi`): labels on
/// the decades, or on 1 and 3, or 1, 2 and 5, or every digit of each decade, whichever
/// comes first with four labels or more; light lines on every digit of every decade. (plotters' own log ticks crowd an
/// axis spanning about one decade: overlapping labels and minor lines packed together.)
fn log_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    let within = |digits: &[f64]| -> Vec<f64> {
        (k0..=k1)
            .flat_map(|k| digits.iter().map(move |d| d * 10f64.powi(k)))
            .filter(|v| (lo..=hi).contains(v))
            .collect()
    };
    let all = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0];
    let bold = [&[1.0][..], &[1.0, 3.0], &[1.0, 2.0, 5.0], &all]
        .into_iter()
        .map(&within)
        .find(|b| b.len() >= 4)
        .unwrap_or_else(|| within(&all));
    let light = within(&all)
        .into_iter()
        .filter(|v| !bold.contains(v))
        .collect();
    (bold, light)
}

/// A curve's point markers: none on a dense curve (a profile of many points), where they
/// would merge into a thick band.
fn markers(
    points: &[(f64, f64)],
    color: RGBColor,
) -> impl Iterator<Item = Circle<(f64, f64), i32>> + '_ {
    let shown = if points.len() <= MARKED_POINTS {
        points
    } else {
        &[]
    };
    shown
        .iter()
        .map(move |&q| Circle::new(q, 4, color.filled()))
}

/// Most points a curve may have and still carry markers.
const MARKED_POINTS: usize = 60;

fn draw_lines<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    (xl, yl): (&str, &str),
    series: &[Series],
    log: bool,
    spans: &[(f64, f64, &str)],
) -> DResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let pts = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| !log || (p.0 > 0.0 && p.1 > 0.0));
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for p in pts {
        x0 = x0.min(p.0);
        x1 = x1.max(p.0);
        y0 = y0.min(p.1);
        y1 = y1.max(p.1);
    }
    if !x0.is_finite() {
        (x0, x1, y0, y1) = (1.0, 10.0, 1.0, 10.0);
    }
    let mut builder = ChartBuilder::on(&root);
    let chart = builder
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(72);
    if log {
        let (x0, x1) = (x0 / 1.5, x1 * 1.5);
        let (y0, y1) = (y0 / 2.0, y1 * 2.0);
        let axis = |lo: f64, hi: f64| {
            let (bold, light) = log_ticks(lo, hi);
            (lo..hi)
                .log_scale()
                .with_key_points(bold)
                .with_light_points(light)
        };
        let mut c = chart.build_cartesian_2d(axis(x0, x1), axis(y0, y1))?;
        c.configure_mesh()
            .x_desc(xl)
            .y_desc(yl)
            .x_label_formatter(&|v| log_label(*v, x0))
            .y_label_formatter(&|v| log_label(*v, y0))
            .label_style(("sans-serif", 15))
            .draw()?;
        for (k, s) in series.iter().enumerate() {
            let color = COLORS[k % COLORS.len()];
            let p: Vec<(f64, f64)> = s
                .points
                .iter()
                .copied()
                .filter(|p| p.0 > 0.0 && p.1 > 0.0)
                .collect();
            c.draw_series(LineSeries::new(p.clone(), color.stroke_width(2)))?
                .label(s.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            c.draw_series(markers(&p, color))?;
        }
        let norm = |v: f64, lo: f64, hi: f64| (v / lo).ln() / (hi / lo).ln();
        let curves: Vec<Vec<(f64, f64)>> = series
            .iter()
            .map(|s| {
                let p = s.points.iter().filter(|p| p.0 > 0.0 && p.1 > 0.0);
                p.map(|p| (norm(p.0, x0, x1), norm(p.1, y0, y1))).collect()
            })
            .collect();
        c.configure_series_labels()
            .position(legend_corner(&curves))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
            .draw()?;
    } else {
        let pad = 0.05 * (y1 - y0).abs().max(1e-12);
        let (ylo, yhi) = (
            y0 - pad,
            y1 + pad + if spans.is_empty() { 0.0 } else { 2.0 * pad },
        );
        let mut c = chart.build_cartesian_2d(x0..x1, ylo..yhi)?;
        c.configure_mesh()
            .x_desc(xl)
            .y_desc(yl)
            .label_style(("sans-serif", 15))
            .draw()?;
        for &(a, b, name) in spans {
            if a > x0 {
                c.draw_series(DashedLineSeries::new(
                    [(a, ylo), (a, yhi)],
                    6,
                    4,
                    BLACK.mix(0.6).stroke_width(1),
                ))?;
            }
            let width = (b.min(x1) - a.max(x0)) / (x1 - x0) * 780.0;
            if width > 7.5 * name.len() as f64 {
                c.draw_series(std::iter::once(Text::new(
                    name.to_string(),
                    (0.5 * (a.max(x0) + b.min(x1)), yhi - 0.01 * (yhi - ylo)),
                    ("sans-serif", 13).into_font().color(&BLACK).pos(
                        plotters::style::text_anchor::Pos::new(
                            plotters::style::text_anchor::HPos::Center,
                            plotters::style::text_anchor::VPos::Top,
                        ),
                    ),
                )))?;
            }
        }
        for (k, s) in series.iter().enumerate() {
            let color = COLORS[k % COLORS.len()];
            c.draw_series(LineSeries::new(s.points.clone(), color.stroke_width(2)))?
                .label(s.name.clone())
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], color.stroke_width(2))
                });
            c.draw_series(markers(&s.points, color))?;
        }
        c.configure_series_labels()
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 15))
            .draw()?;
    }
    root.present()?;
    Ok(())
}

fn draw_bars<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    (xl, yl): (&str, &str),
    categories: &[String],
    bars: &[Bars],
) -> DResult
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let n = categories.len().max(1);
    let (corner, y1) = bar_legend_place(bars, n, root.dim_in_pixel().1);
    let mut c = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(48)
        .y_label_area_size(64)
        .build_cartesian_2d(0.0..n as f64, 0.0..y1)?;
    let cats = categories.to_vec();
    // Many long labels would run into each other: label every other bar.
    let widest = cats.iter().map(|c| c.chars().count()).max().unwrap_or(0);
    let every = if n > 12 && widest > 2 { 2 } else { 1 };
    let whole = bars
        .iter()
        .flat_map(|b| b.values.iter())
        .all(|v| v.fract() == 0.0);
    c.configure_mesh()
        .disable_x_mesh()
        .light_line_style(WHITE)
        .bold_line_style(BLACK.mix(0.12))
        .x_desc(xl)
        .y_desc(yl)
        .x_labels(n + 1)
        .y_label_formatter(&|v| {
            // Counts read as counts: whole numbers only, without ".0".
            match (whole, v.fract() == 0.0) {
                (true, true) => format!("{v:.0}"),
                (true, false) => String::new(),
                (false, _) => short(*v),
            }
        })
        .x_label_formatter(&move |x| {
            // Ticks sit on bin edges: label each with its bin's lower edge.
            if (x - x.round()).abs() < 1e-6 && (x.round() as usize).is_multiple_of(every) {
                cats.get(x.round() as usize).cloned().unwrap_or_default()
            } else {
                String::new()
            }
        })
        .label_style(("sans-serif", 13))
        .draw()?;
    let m = bars.len().max(1) as f64;
    for (j, b) in bars.iter().enumerate() {
        let color = COLORS[j % COLORS.len()];
        let w = 0.8 / m;
        c.draw_series(b.values.iter().enumerate().map(|(k, &v)| {
            let x0 = k as f64 + 0.1 + j as f64 * w;
            Rectangle::new([(x0, 0.0), (x0 + w * 0.95, v)], color.filled())
        }))?
        .label(b.name.clone())
        .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 14, y + 5)], color.filled()));
    }
    c.configure_series_labels()
        .position(corner)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()?;
    root.present()?;
    Ok(())
}

/// Where a bar chart's legend goes and the top of its value axis: the upper corner
/// above the lower bars, with the axis raised so that no bar reaches into the legend's
/// band (`height` is the chart area's height in pixels; the legend is about 20 px per
/// entry and covers about a third of the bins on its side).
fn bar_legend_place(bars: &[Bars], n: usize, height: u32) -> (SeriesLabelPosition, f64) {
    let side = |range: std::ops::Range<usize>| {
        bars.iter()
            .flat_map(|b| b.values.get(range.clone()).unwrap_or(&[]).iter())
            .cloned()
            .fold(0.0, f64::max)
    };
    let third = n.div_ceil(3).min(n);
    let (left, right) = (side(0..third), side(n - third..n));
    let highest = bars
        .iter()
        .flat_map(|b| b.values.iter())
        .cloned()
        .fold(0.0, f64::max)
        .max(1e-12);
    let (corner, under) = if right <= left {
        (SeriesLabelPosition::UpperRight, right)
    } else {
        (SeriesLabelPosition::UpperLeft, left)
    };
    // The plot's height: the area less its caption, margins and x labels.
    let plot = (f64::from(height) - 110.0).max(60.0);
    let band = ((bars.len() as f64 * 20.0 + 24.0) / plot).min(0.6);
    (corner, (highest * 1.15).max(under / (1.0 - band) * 1.05))
}

/// Writes a rendered figure to `stem.png` and `stem.svg`, each under a temporary name
/// renamed into place once complete (a failed write leaves no half-written figure).
pub fn write(stem: &Path, figure: &Rendered) -> Result<(), PlotError> {
    for (ext, bytes) in figure {
        let p = stem.with_extension(ext);
        crate::output::write_atomic(&p, bytes).map_err(|e| PlotError::Draw {
            path: p.display().to_string(),
            message: e.to_string(),
        })?;
    }
    Ok(())
}

/// The first corner of the plot (upper right, upper left, lower right, lower left) that
/// no curve passes through, for the legend (curves in coordinates normalised to
/// `[0, 1]` over the axes); the middle of the right side if every corner is taken.
fn legend_corner(curves: &[Vec<(f64, f64)>]) -> SeriesLabelPosition {
    let corners = [
        (SeriesLabelPosition::UpperRight, (0.6, 1.0), (0.8, 1.0)),
        (SeriesLabelPosition::UpperLeft, (0.0, 0.4), (0.8, 1.0)),
        (SeriesLabelPosition::LowerRight, (0.6, 1.0), (0.0, 0.2)),
        (SeriesLabelPosition::LowerLeft, (0.0, 0.4), (0.0, 0.2)),
    ];
    let inside = |(u, v): (f64, f64), (ulo, uhi): (f64, f64), (vlo, vhi): (f64, f64)| {
        u >= ulo && u <= uhi && v >= vlo && v <= vhi
    };
    for (pos, us, vs) in corners {
        let hit = curves.iter().any(|c| {
            c.iter().any(|&p| inside(p, us, vs))
                || c.windows(2).any(|w| {
                    (1..20).any(|k| {
                        let f = k as f64 / 20.0;
                        let p = (
                            w[0].0 + f * (w[1].0 - w[0].0),
                            w[0].1 + f * (w[1].1 - w[0].1),
                        );
                        inside(p, us, vs)
                    })
                })
        });
        if !hit {
            return pos;
        }
    }
    SeriesLabelPosition::MiddleRight
}

/// Writes `stem.png` and `stem.svg`: curves, log-log when `log`.
pub fn lines(
    stem: &Path,
    title: &str,
    labels: (&str, &str),
    series: &[Series],
    log: bool,
) -> Result<(), PlotError> {
    draw_both!(
        stem,
        (900, 600),
        draw_lines(title, labels, series, log, &[])
    )
}

/// [`lines`] on linear axes with spans of x `(from, to, name)` marked (a groove's zones):
/// a dashed line where each starts inside the frame, the name along the top.
pub fn lines_marked(
    stem: &Path,
    title: &str,
    labels: (&str, &str),
    series: &[Series],
    spans: &[(f64, f64, &str)],
) -> Result<(), PlotError> {
    draw_both!(
        stem,
        (900, 600),
        draw_lines(title, labels, series, false, spans)
    )
}

/// Writes `stem.png` and `stem.svg`: grouped bars over `categories`.
pub fn bars(
    stem: &Path,
    title: &str,
    labels: (&str, &str),
    categories: &[String],
    bars: &[Bars],
) -> Result<(), PlotError> {
    draw_both!(stem, (900, 600), draw_bars(title, labels, categories, bars))
}

/// A scalar field on a regular grid, for [`heatmap`].
#[derive(Debug, Clone)]
pub struct Field<'a> {
    /// `[x0, x1, y0, y1]` in plot units.
    pub extent: [f64; 4],
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Row-major values (`ny` rows of `nx`), row 0 at `y0`.
    pub values: &'a [f64],
    /// Colour-bar label.
    pub label: &'a str,
    /// Spans of x `(from, to, name)` to mark (a groove's zones): a dashed line where
    /// each starts inside the frame, the name along the top.
    pub spans: &'a [(f64, f64, &'a str)],
}

/// Most cells drawn per axis: finer grids are averaged into blocks (SVG size).
const HEATMAP_CELLS: usize = 200;

/// Writes `stem.png` and `stem.svg`: the field in viridis colours, zero in white, with a
/// colour bar. Grids finer than 200 cells per axis are drawn as block averages.
pub fn heatmap(
    stem: &Path,
    title: &str,
    labels: (&str, &str),
    field: &Field<'_>,
) -> Result<(), PlotError> {
    draw_both!(stem, (820, 700), draw_heatmap(title, labels, field))
}

fn draw_heatmap<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    (xl, yl): (&str, &str),
    f: &Field<'_>,
) -> DResult
where
    DB::ErrorType: 'static,
{
    use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
    root.fill(&WHITE)?;
    // Block-average to at most HEATMAP_CELLS per axis.
    let (bx, by) = (f.nx.div_ceil(HEATMAP_CELLS), f.ny.div_ceil(HEATMAP_CELLS));
    let (mx, my) = (f.nx.div_ceil(bx), f.ny.div_ceil(by));
    let mut blocks = vec![0.0; mx * my];
    let mut counts = vec![0usize; mx * my];
    for j in 0..f.ny {
        for i in 0..f.nx {
            let k = (j / by) * mx + i / bx;
            blocks[k] += f.values[j * f.nx + i];
            counts[k] += 1;
        }
    }
    for (b, c) in blocks.iter_mut().zip(&counts) {
        *b /= (*c).max(1) as f64;
    }
    let vmax = blocks.iter().cloned().fold(0.0, f64::max).max(1e-300);
    let (main, bar) = root.split_horizontally(700);
    let [x0, x1, y0, y1] = f.extent;
    let mut c = ChartBuilder::on(&main)
        .caption(title, ("sans-serif", 20))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    c.configure_mesh()
        .disable_mesh()
        .x_desc(xl)
        .y_desc(yl)
        .label_style(("sans-serif", 14))
        .draw()?;
    let (dx, dy) = ((x1 - x0) / mx as f64, (y1 - y0) / my as f64);
    c.draw_series((0..my).flat_map(|j| {
        let blocks = &blocks;
        (0..mx).map(move |i| {
            let v = blocks[j * mx + i];
            let color = if v <= 0.0 {
                WHITE
            } else {
                ViridisRGB.get_color((v / vmax) as f32)
            };
            let (ax, ay) = (x0 + i as f64 * dx, y0 + j as f64 * dy);
            Rectangle::new([(ax, ay), (ax + dx, ay + dy)], color.filled())
        })
    }))?;
    for &(a, b, name) in f.spans {
        if a > x0 {
            c.draw_series(DashedLineSeries::new(
                [(a, y0), (a, y1)],
                6,
                4,
                BLACK.mix(0.6).stroke_width(1),
            ))?;
        }
        // The name when the span is wide enough to hold it.
        let width = (b - a) / (x1 - x0) * 620.0;
        if width > 7.5 * name.len() as f64 {
            c.draw_series(std::iter::once(Text::new(
                name.to_string(),
                (0.5 * (a + b), y1 - 0.02 * (y1 - y0)),
                ("sans-serif", 13).into_font().color(&BLACK).pos(
                    plotters::style::text_anchor::Pos::new(
                        plotters::style::text_anchor::HPos::Center,
                        plotters::style::text_anchor::VPos::Top,
                    ),
                ),
            )))?;
        }
    }
    colour_bar(&bar, f.label, vmax)?;
    root.present()?;
    Ok(())
}

/// A viridis colour bar from 0 to `vmax` on `area`, captioned `label`.
fn colour_bar<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, label: &str, vmax: f64) -> DResult
where
    DB::ErrorType: 'static,
{
    use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
    let mut cb = ChartBuilder::on(area)
        .margin_top(50)
        .margin_bottom(56)
        .margin_right(8)
        .y_label_area_size(52)
        .caption(label, ("sans-serif", 13))
        .build_cartesian_2d(0.0..1.0, 0.0..vmax)?;
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_label_formatter(&|v| short(*v))
        .label_style(("sans-serif", 12))
        .draw()?;
    let steps = 100;
    cb.draw_series((0..steps).map(|k| {
        let (a, b) = (
            vmax * k as f64 / steps as f64,
            vmax * (k + 1) as f64 / steps as f64,
        );
        let color = ViridisRGB.get_color(((k as f64 + 0.5) / steps as f64) as f32);
        Rectangle::new([(0.0, a), (1.0, b)], color.filled())
    }))?;
    Ok(())
}

/// One point of a [`Map`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapPoint {
    /// Position in plot units.
    pub x: f64,
    /// Position in plot units.
    pub y: f64,
    /// Value shown by the point's colour.
    pub value: f64,
    /// Drawn filled (else as a ring).
    pub filled: bool,
}

/// Points on a square frame, coloured by a value, for [`map_with_bars`].
#[derive(Debug, Clone)]
pub struct Map<'a> {
    /// Panel title.
    pub title: &'a str,
    /// Axis labels.
    pub labels: (&'a str, &'a str),
    /// `[x0, x1, y0, y1]`, plot units.
    pub extent: [f64; 4],
    /// The points; those outside the frame are not drawn.
    pub points: &'a [MapPoint],
    /// Context drawn first, as small grey dots (e.g. the impacts not selected).
    pub background: &'a [(f64, f64)],
    /// Colour-bar label.
    pub value_label: &'a str,
    /// Top of the colour scale (its bottom is 0).
    pub value_max: f64,
    /// Legend entries of the filled and the ringed points.
    pub kinds: (&'a str, &'a str),
    /// A marked place `(x, y, label)`, drawn as a cross.
    pub cross: Option<(f64, f64, &'a str)>,
    /// Rectangles `[x0, x1, y0, y1]` drawn as outlines, with their legend labels.
    pub outlines: &'a [([f64; 4], &'a str)],
}

/// One panel of grouped bars, for [`map_with_bars`].
#[derive(Debug, Clone)]
pub struct BarPanel<'a> {
    /// Panel title.
    pub title: &'a str,
    /// Axis labels.
    pub labels: (&'a str, &'a str),
    /// Lower edges of the bins.
    pub categories: &'a [String],
    /// The bar sets.
    pub bars: &'a [Bars],
}

/// Writes `stem.png` and `stem.svg`: a map on the left, the bar panels stacked on the
/// right, under one title.
pub fn map_with_bars(
    stem: &Path,
    title: &str,
    map: &Map<'_>,
    panels: &[BarPanel<'_>],
) -> Result<(), PlotError> {
    draw_both!(stem, (1400, 760), draw_map_with_bars(title, map, panels))
}

/// [`map_with_bars`] rendered in memory.
pub fn render_map_with_bars(
    title: &str,
    map: &Map<'_>,
    panels: &[BarPanel<'_>],
) -> Result<Rendered, PlotError> {
    render_both!((1400, 760), draw_map_with_bars(title, map, panels)).map_err(|message| {
        PlotError::Draw {
            path: title.to_string(),
            message,
        }
    })
}

fn draw_map_with_bars<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    title: &str,
    m: &Map<'_>,
    panels: &[BarPanel<'_>],
) -> DResult
where
    DB::ErrorType: 'static,
{
    use plotters::style::colors::colormaps::{ColorMap, ViridisRGB};
    root.fill(&WHITE)?;
    let body = root.titled(title, ("sans-serif", 22))?;
    let (left, right) = body.split_horizontally(830);
    let (frame, bar) = left.split_horizontally(710);
    let [x0, x1, y0, y1] = m.extent;
    let mut c = ChartBuilder::on(&frame)
        .caption(m.title, ("sans-serif", 17))
        .margin(12)
        .x_label_area_size(44)
        .y_label_area_size(60)
        .build_cartesian_2d(x0..x1, y0..y1)?;
    c.configure_mesh()
        .x_desc(m.labels.0)
        .y_desc(m.labels.1)
        .x_label_formatter(&|v| short(*v))
        .y_label_formatter(&|v| short(*v))
        .light_line_style(WHITE)
        .bold_line_style(BLACK.mix(0.12))
        .label_style(("sans-serif", 14))
        .draw()?;
    let vmax = m.value_max.max(1e-300);
    let colour = |v: f64| ViridisRGB.get_color((v / vmax).clamp(0.0, 1.0) as f32);
    let inside = |q: &&MapPoint| q.x >= x0 && q.x <= x1 && q.y >= y0 && q.y <= y1;
    if !m.background.is_empty() {
        let grey = BLACK.mix(0.25);
        c.draw_series(
            m.background
                .iter()
                .filter(|q| q.0 >= x0 && q.0 <= x1 && q.1 >= y0 && q.1 <= y1)
                .map(|&q| Circle::new(q, 2, grey.filled())),
        )?
        .label("all impacts")
        .legend(move |(x, y)| Circle::new((x + 7, y), 2, grey.filled()));
    }
    for (k, (r, label)) in m.outlines.iter().enumerate() {
        let colour = COLORS[(k + 3) % COLORS.len()];
        let corners = vec![
            (r[0], r[2]),
            (r[1], r[2]),
            (r[1], r[3]),
            (r[0], r[3]),
            (r[0], r[2]),
        ];
        c.draw_series([PathElement::new(corners, colour.stroke_width(2))])?
            .label(*label)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 14, y)], colour.stroke_width(2))
            });
    }
    // Small points when there are many.
    let r = if m.points.len() > 2000 { 2 } else { 3 };
    // Rings first, so the filled points stay visible where both fall; within each kind
    // the highest values last, on top.
    for filled in [false, true] {
        let mut pts: Vec<&MapPoint> = m
            .points
            .iter()
            .filter(inside)
            .filter(|q| q.filled == filled)
            .collect();
        pts.sort_by(|a, b| a.value.total_cmp(&b.value));
        let grey = BLACK.mix(0.55);
        let (name, style) = if filled {
            (m.kinds.0, grey.filled())
        } else {
            (m.kinds.1, grey.stroke_width(1))
        };
        if pts.is_empty() {
            continue;
        }
        c.draw_series(pts.into_iter().map(|q| {
            let style = if q.filled {
                colour(q.value).filled()
            } else {
                colour(q.value).stroke_width(1)
            };
            Circle::new((q.x, q.y), r, style)
        }))?
        .label(name)
        .legend(move |(x, y)| Circle::new((x + 7, y), 4, style));
    }
    // The mark on top, open in the middle: a point on it stays visible.
    if let Some((cx, cy, label)) = m.cross {
        let (s, g) = (0.025 * (x1 - x0), 0.008 * (x1 - x0));
        let red = RGBColor(214, 39, 40).stroke_width(2);
        c.draw_series(
            [(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0)].map(|(u, v)| {
                PathElement::new(
                    vec![(cx + g * u, cy + g * v), (cx + s * u, cy + s * v)],
                    red,
                )
            }),
        )?
        .label(label)
        .legend(move |(x, y)| {
            PathElement::new(
                vec![(x, y), (x + 14, y)],
                RGBColor(214, 39, 40).stroke_width(2),
            )
        });
    }
    let labelled = m.cross.is_some()
        || !m.outlines.is_empty()
        || !m.background.is_empty()
        || m.points.iter().any(|q| inside(&q));
    if labelled {
        c.configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 13))
            .draw()?;
    }
    colour_bar(&bar, m.value_label, vmax)?;
    let rows = panels.len().max(1);
    for (area, p) in right.split_evenly((rows, 1)).into_iter().zip(panels) {
        draw_bars(area, p.title, p.labels, p.categories, p.bars)?;
    }
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corner(curves: &[Vec<(f64, f64)>]) -> String {
        format!("{:?}", legend_corner(curves))
    }

    #[test]
    fn log_axes_get_a_few_readable_labels() {
        // Many decades: the decades only.
        let (bold, light) = log_ticks(3e-9, 2e-2);
        assert_eq!(bold.len(), 7);
        assert!(
            bold.iter()
                .all(|v| (v.log10() - v.log10().round()).abs() < 1e-12)
        );
        assert!(light.len() > 40 && light.iter().all(|v| !bold.contains(v)));
        // Three and a half decades (a single shot's wall times): 1 and 3.
        let (bold, _) = log_ticks(2e-5, 8e-2);
        let want = [3e-5, 1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2];
        assert_eq!(bold.len(), want.len());
        assert!(
            bold.iter()
                .zip(want)
                .all(|(a, b)| (a / b - 1.0).abs() < 1e-12)
        );
        // About one decade (the history-law study's errors): 1, 2 and 5 of each decade.
        let (bold, _) = log_ticks(4e-4, 2.5e-2);
        let want = [5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 2e-2];
        assert_eq!(bold.len(), want.len());
        assert!(
            bold.iter()
                .zip(want)
                .all(|(a, b)| (a / b - 1.0).abs() < 1e-12)
        );
        // Less than a factor 4: every digit.
        let (bold, light) = log_ticks(1.5e-3, 5.5e-3);
        assert_eq!(bold.len(), 4);
        assert!(light.is_empty());
    }

    #[test]
    fn a_bar_charts_legend_sits_above_the_lower_bars() {
        let set = |v: &[f64]| Bars {
            name: String::new(),
            values: v.to_vec(),
        };
        // The tall bar on the right (the default scene's speeds): the legend goes left,
        // and the left bars stay below its band of a 370 px panel (260 px of plot).
        let tall_right = [
            set(&[1.0, 0.0, 1.0, 1.0, 2.0, 14.0]),
            set(&[0.0, 4.0, 3.0, 1.0, 0.0, 0.0]),
        ];
        let (corner, top) = bar_legend_place(&tall_right, 6, 370);
        assert_eq!(format!("{corner:?}"), "UpperLeft");
        let band = (2.0 * 20.0 + 24.0) / 260.0;
        assert!(
            4.0 < top * (1.0 - band),
            "left bars 4 reach the legend: top {top}"
        );
        assert!(
            (top - 14.0 * 1.15).abs() < 1e-12,
            "no more room than needed: {top}"
        );
        // The tall bar on the left (angles): right, and the axis raised only as needed.
        let tall_left = [set(&[15.0, 1.0, 1.0, 1.0, 1.0, 13.0])];
        let (corner, top) = bar_legend_place(&tall_left, 6, 370);
        assert_eq!(format!("{corner:?}"), "UpperRight");
        let band = (20.0 + 24.0) / 260.0;
        assert!(
            13.0 < top * (1.0 - band),
            "right bar 13 reaches the legend: top {top}"
        );
    }

    #[test]
    fn the_legend_goes_to_a_corner_no_curve_crosses() {
        // Error against cost: both curves fall to the right; the upper right is free.
        let falling = vec![vec![(0.0, 0.9), (0.3, 0.1)], vec![(0.5, 0.7), (1.0, 0.2)]];
        assert_eq!(corner(&falling), "UpperRight");
        // Rising (speed against pressure): upper left.
        let rising = vec![vec![(0.0, 0.0), (1.0, 1.0)]];
        assert_eq!(corner(&rising), "UpperLeft");
        // A segment crossing the upper right without a point in it still counts.
        let crossing = vec![vec![(0.5, 1.0), (1.0, 0.5)], vec![(0.0, 1.0), (0.3, 0.0)]];
        assert_eq!(corner(&crossing), "LowerRight");
        // Every corner taken: the middle of the right side.
        let all = vec![vec![(0.0, 0.0), (0.0, 1.0), (1.0, 1.0), (1.0, 0.0)]];
        assert_eq!(corner(&all), "MiddleRight");
    }
}
