//! The report's figures: line plots and stacked bars, each drawn twice from
//! the same code, as SVG (text stays text) and as PNG (text rasterized with
//! the embedded DejaVu Sans, so a PNG looks the same on every machine).
//!
//! Bad input (no data, non-finite or out-of-domain values, ragged layers)
//! is an [`Error::Options`], never a panic: the report calls this with whatever
//! a benchmark produced.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use plotters::style::{register_font, FontStyle, FontTransform, RGBColor};

use crate::error::{Error, Result};

/// One line of a line plot.
#[derive(Clone, Debug, Default)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

#[derive(Clone, Copy, Debug, Default)]
pub struct LinePlot<'a> {
    pub title: &'a str,
    pub x_label: &'a str,
    pub y_label: &'a str,
    pub series: &'a [Series],
    pub log_x: bool,
    pub log_y: bool,
}

/// Stacked bars: one bar per category, one stacked segment per layer.
#[derive(Clone, Copy, Debug, Default)]
pub struct StackedBars<'a> {
    pub title: &'a str,
    pub y_label: &'a str,
    pub categories: &'a [String],
    /// `layers[i].1[j]` = value of layer i in category j; layer 0 at the bottom.
    pub layers: &'a [(String, Vec<f64>)],
}

/// A figure rendered both ways.
#[derive(Clone, Debug)]
pub struct Figure {
    pub svg: String,
    pub png: Vec<u8>,
    pub size: (u32, u32),
}

impl Figure {
    /// Writes DIR/STEM.svg and DIR/STEM.png (creating DIR), returns both paths.
    pub fn save(&self, dir: &Path, stem: &str) -> Result<(PathBuf, PathBuf)> {
        // A stem with a separator would write outside DIR.
        if stem.is_empty() || stem.contains(['/', '\\']) || stem == "." || stem == ".." {
            return Err(Error::Options(format!("figure file stem '{stem}' must be a plain file name")));
        }
        std::fs::create_dir_all(dir).map_err(|source| Error::Write { path: dir.to_path_buf(), source })?;
        let svg = dir.join(format!("{stem}.svg"));
        let png = dir.join(format!("{stem}.png"));
        std::fs::write(&svg, &self.svg).map_err(|source| Error::Write { path: svg.clone(), source })?;
        std::fs::write(&png, &self.png).map_err(|source| Error::Write { path: png.clone(), source })?;
        Ok((svg, png))
    }
}

/// Tableau 10 plus black and dark teal: twelve colours that stay apart on
/// white; beyond twelve they repeat.
const PALETTE: [RGBColor; 12] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
    RGBColor(0, 0, 0),
    RGBColor(0, 95, 95),
];

/// A stable colour per series index, distinguishable for 12 series (method
/// lines keep their colour across plots when the caller passes them in the
/// same order).
pub fn color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

const FONT: &str = "sans-serif";
const TITLE_PX: u32 = 20;
const LABEL_PX: u32 = 13;
const DESC_PX: u32 = 15;
const LEGEND_PX: u32 = 14;
/// Series with at most this many points get a marker per point: sparse data
/// (and a single point) would otherwise be hard to see or invisible.
const MARKERS_UP_TO: usize = 25;
/// Outside these the layout has no room, or the bitmap gets absurd.
const MIN_SIZE: (u32, u32) = (200, 150);
const MAX_SIDE: u32 = 8192;

/// plotters' ab_glyph text needs its fonts registered by name, once per process.
fn ensure_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED.get_or_init(|| register_font(FONT, FontStyle::Normal, include_bytes!("../../assets/fonts/DejaVuSans.ttf")).is_ok());
    if ok {
        Ok(())
    } else {
        Err(Error::Options("the embedded font assets/fonts/DejaVuSans.ttf is not a valid font".into()))
    }
}

type DrawResult<DB> = std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// A figure drawable on any plotters backend, so SVG and PNG share one code path.
trait Draw {
    fn title(&self) -> &str;
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB>;
}

fn render(d: &impl Draw, size: (u32, u32)) -> Result<Figure> {
    let (w, h) = size;
    if w < MIN_SIZE.0 || h < MIN_SIZE.1 || w > MAX_SIDE || h > MAX_SIDE {
        return Err(Error::Options(format!("figure '{}': size {w}x{h} outside {}x{}..={MAX_SIDE}x{MAX_SIDE}", d.title(), MIN_SIZE.0, MIN_SIZE.1)));
    }
    ensure_font()?;
    let fail = |e: String| Error::Options(format!("cannot draw figure '{}': {e}", d.title()));
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        d.draw(&root).map_err(|e| fail(e.to_string()))?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    let mut rgb = vec![255u8; w as usize * h as usize * 3];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area();
        d.draw(&root).map_err(|e| fail(e.to_string()))?;
        root.present().map_err(|e| fail(e.to_string()))?;
    }
    let mut png = Vec::new();
    image::ImageEncoder::write_image(image::codecs::png::PngEncoder::new(&mut png), &rgb, w, h, image::ExtendedColorType::Rgb8).map_err(|e| fail(e.to_string()))?;
    Ok(Figure { svg, png, size })
}

/// Tick and value labels: three or four significant digits, no trailing
/// zeros, scientific when the axis spans huge or tiny magnitudes.
fn number(v: f64, sci: bool) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let trim = |s: &str| if s.contains('.') { s.trim_end_matches('0').trim_end_matches('.').to_string() } else { s.to_string() };
    if sci {
        let s = format!("{v:.2e}");
        match s.split_once('e') {
            Some((m, e)) => format!("{}e{e}", trim(m)),
            None => s,
        }
    } else {
        let decimals = (3 - v.abs().log10().floor() as i32).clamp(0, 8) as usize;
        trim(&format!("{v:.decimals$}"))
    }
}

/// Whether an axis over `lo..hi` labels its ticks in scientific notation.
fn wants_sci(lo: f64, hi: f64) -> bool {
    let m = lo.abs().max(hi.abs());
    !(1e-3..1e5).contains(&m)
}

/// Padded axis range over the data's `lo..=hi` (5% each side; a single
/// value still gets a range). Non-negative data keeps a non-negative axis.
fn linear_range(lo: f64, hi: f64) -> (f64, f64) {
    let pad = if hi > lo {
        (hi - lo) * 0.05
    } else if lo != 0.0 {
        lo.abs() * 0.1
    } else {
        1.0
    };
    let start = if lo >= 0.0 { (lo - pad).max(0.0) } else { lo - pad };
    (start, hi + pad)
}

/// Log-axis version of [`linear_range`]: padding is 5% of the decades, and
/// the range always holds a power of ten, since plotters' log axis only
/// places ticks from one.
fn log_range(lo: f64, hi: f64) -> (f64, f64) {
    let pad = if hi > lo { (hi / lo).ln() * 0.05 } else { 2f64.ln() };
    let (mut start, end) = (lo * (-pad).exp(), hi * pad.exp());
    if 10f64.powf(start.log10().ceil()) > end {
        start = 10f64.powf(start.log10().floor());
    }
    (start, end)
}

fn text_style(px: u32) -> TextStyle<'static> {
    (FONT, px).into_font().color(&BLACK)
}

/// Legend in its own panel beside the plot, so it never hides data.
enum Swatch {
    Line,
    Box,
}

/// Width of the legend panel for these names (capped so the plot keeps most
/// of the figure).
fn legend_width<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, names: &[&str]) -> std::result::Result<u32, DrawingAreaErrorKind<DB::ErrorType>> {
    let style = text_style(LEGEND_PX);
    let mut widest = 0;
    for n in names {
        widest = widest.max(root.estimate_text_size(n, &style)?.0);
    }
    Ok((widest + 56).min(root.dim_in_pixel().0 * 2 / 5))
}

fn draw_legend<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[(&str, RGBColor)], swatch: Swatch, top: i32) -> DrawResult<DB> {
    let (w, h) = area.dim_in_pixel();
    let (w, h) = (w as i32, h as i32);
    // Shrink rows rather than run off the bottom when there are many entries.
    let row = ((h - top - 10) / entries.len().max(1) as i32).clamp(8, 22);
    let frame_bottom = (top + row * entries.len() as i32 + 8).min(h - 1);
    area.draw(&Rectangle::new([(4, top), (w - 6, frame_bottom)], BLACK.mix(0.3)))?;
    let style = text_style(LEGEND_PX).pos(Pos::new(HPos::Left, VPos::Center));
    for (k, (name, c)) in entries.iter().enumerate() {
        let y = top + 4 + row * k as i32 + row / 2;
        match swatch {
            Swatch::Line => area.draw(&PathElement::new(vec![(12, y), (36, y)], c.stroke_width(2)))?,
            Swatch::Box => area.draw(&Rectangle::new([(18, y - 6), (30, y + 6)], c.filled()))?,
        }
        area.draw(&Text::new(name.to_string(), (44, y), style.clone()))?;
    }
    Ok(())
}

/// White page, title on top, legend panel on the right: (plot area, legend area).
type Areas<DB> = (DrawingArea<DB, Shift>, DrawingArea<DB, Shift>);
fn layout<DB: DrawingBackend>(root: &DrawingArea<DB, Shift>, title: &str, names: &[&str]) -> std::result::Result<Areas<DB>, DrawingAreaErrorKind<DB::ErrorType>> {
    root.fill(&WHITE)?;
    let body = root.titled(title, text_style(TITLE_PX))?;
    let lw = legend_width(root, names)?;
    Ok(body.split_horizontally(body.dim_in_pixel().0.saturating_sub(lw)))
}

/// A line plot with its points already filtered and its ranges chosen.
struct Lines<'a> {
    p: &'a LinePlot<'a>,
    /// Per series (same order, so colours stay put): its drawable points.
    points: Vec<Vec<(f64, f64)>>,
    x: (f64, f64),
    y: (f64, f64),
}

impl Lines<'_> {
    fn chart<DB, X, Y>(&self, area: &DrawingArea<DB, Shift>, xs: X, ys: Y) -> DrawResult<DB>
    where
        DB: DrawingBackend,
        X: AsRangedCoord<Value = f64>,
        Y: AsRangedCoord<Value = f64>,
        X::CoordDescType: ValueFormatter<f64>,
        Y::CoordDescType: ValueFormatter<f64>,
    {
        let mut chart = ChartBuilder::on(area).margin(12).x_label_area_size(48).y_label_area_size(64).build_cartesian_2d(xs, ys)?;
        let (x_sci, y_sci) = (wants_sci(self.x.0, self.x.1), wants_sci(self.y.0, self.y.1));
        let fx = |v: &f64| number(*v, x_sci);
        let fy = |v: &f64| number(*v, y_sci);
        chart
            .configure_mesh()
            .x_desc(self.p.x_label)
            .y_desc(self.p.y_label)
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .label_style(text_style(LABEL_PX))
            .axis_desc_style(text_style(DESC_PX))
            .draw()?;
        for (i, pts) in self.points.iter().enumerate() {
            let c = color(i);
            chart.draw_series(LineSeries::new(pts.iter().copied(), c.stroke_width(2)))?;
            if pts.len() <= MARKERS_UP_TO {
                chart.draw_series(pts.iter().map(|&p| Circle::new(p, 3, c.filled())))?;
            }
        }
        Ok(())
    }
}

impl Draw for Lines<'_> {
    fn title(&self) -> &str {
        self.p.title
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let names: Vec<&str> = self.p.series.iter().map(|s| s.name.as_str()).collect();
        let (plot, legend) = layout(root, self.p.title, &names)?;
        let (x, y) = (self.x.0..self.x.1, self.y.0..self.y.1);
        match (self.p.log_x, self.p.log_y) {
            (false, false) => self.chart(&plot, x, y)?,
            (true, false) => self.chart(&plot, x.log_scale(), y)?,
            (false, true) => self.chart(&plot, x, y.log_scale())?,
            (true, true) => self.chart(&plot, x.log_scale(), y.log_scale())?,
        }
        let entries: Vec<(&str, RGBColor)> = names.iter().enumerate().map(|(i, n)| (*n, color(i))).collect();
        draw_legend(&legend, &entries, Swatch::Line, 12)
    }
}

/// Draws a line plot. Points that are not finite, or not positive on a log
/// axis, are skipped; it is an error if no series has a point left.
pub fn line_plot(p: &LinePlot, size: (u32, u32)) -> Result<Figure> {
    if p.series.is_empty() {
        return Err(Error::Options(format!("line plot '{}': no series", p.title)));
    }
    let keep = |&(x, y): &(f64, f64)| x.is_finite() && y.is_finite() && (!p.log_x || x > 0.0) && (!p.log_y || y > 0.0);
    let points: Vec<Vec<(f64, f64)>> = p.series.iter().map(|s| s.points.iter().copied().filter(keep).collect()).collect();
    let all = || points.iter().flatten();
    let (mut x, mut y) = ((f64::INFINITY, f64::NEG_INFINITY), (f64::INFINITY, f64::NEG_INFINITY));
    for &(px, py) in all() {
        x = (x.0.min(px), x.1.max(px));
        y = (y.0.min(py), y.1.max(py));
    }
    if all().next().is_none() {
        let domain = if p.log_x || p.log_y { " (positive on the log axes)" } else { "" };
        return Err(Error::Options(format!("line plot '{}': no finite points{domain}", p.title)));
    }
    let x = if p.log_x { log_range(x.0, x.1) } else { linear_range(x.0, x.1) };
    let y = if p.log_y { log_range(y.0, y.1) } else { linear_range(y.0, y.1) };
    // Data near f64::MAX can pad past it.
    if ![x.0, x.1, y.0, y.1].iter().all(|v| v.is_finite()) {
        return Err(Error::Options(format!("line plot '{}': values too large to plot", p.title)));
    }
    render(&Lines { p, points, x, y }, size)
}

/// Stacked bars with validated values (non-finite ones count as 0).
struct Bars<'a> {
    p: &'a StackedBars<'a>,
    /// values[i][j]: layer i in category j.
    values: Vec<Vec<f64>>,
    y_max: f64,
}

impl Draw for Bars<'_> {
    fn title(&self) -> &str {
        self.p.title
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DrawResult<DB> {
        let names: Vec<&str> = self.p.layers.iter().map(|(n, _)| n.as_str()).collect();
        let (plot, legend) = layout(root, self.p.title, &names)?;

        // Category names go under their bars; turned vertical when the
        // widest would not fit in a bar's slot.
        let n = self.p.categories.len();
        let label = text_style(LABEL_PX);
        let mut widest = 0;
        let mut tallest = 0;
        for c in self.p.categories {
            let (w, h) = root.estimate_text_size(c, &label)?;
            widest = widest.max(w);
            tallest = tallest.max(h);
        }
        let (margin, y_area) = (12u32, 64u32);
        let slot = plot.dim_in_pixel().0.saturating_sub(2 * margin + y_area) / n as u32;
        let vertical = widest + 8 > slot;
        let x_area = if vertical { (widest + 14).min(plot.dim_in_pixel().1 / 3) } else { tallest + 16 };

        let mut chart = ChartBuilder::on(&plot).margin(margin).x_label_area_size(x_area).y_label_area_size(y_area).build_cartesian_2d(0.0..n as f64, 0.0..self.y_max)?;
        let sci = wants_sci(0.0, self.y_max);
        let fy = |v: &f64| number(*v, sci);
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .y_desc(self.p.y_label)
            .y_label_formatter(&fy)
            .label_style(text_style(LABEL_PX))
            .axis_desc_style(text_style(DESC_PX))
            .draw()?;

        for j in 0..n {
            let (x0, x1) = (j as f64 + 0.15, j as f64 + 0.85);
            let mut base = 0.0;
            for (i, layer) in self.values.iter().enumerate() {
                let top = base + layer[j];
                if layer[j] > 0.0 {
                    chart.draw_series(std::iter::once(Rectangle::new([(x0, base), (x1, top)], color(i).filled())))?;
                }
                base = top;
            }
            // Absolute pixel positions: `root` is the whole backend.
            let (cx, total_y) = chart.backend_coord(&(j as f64 + 0.5, base));
            root.draw(&Text::new(number(base, sci), (cx, total_y - 3), label.pos(Pos::new(HPos::Center, VPos::Bottom))))?;
            let (_, axis_y) = chart.backend_coord(&(j as f64 + 0.5, 0.0));
            let name = self.p.categories[j].clone();
            let text = if vertical {
                Text::new(name, (cx, axis_y + 6), label.pos(Pos::new(HPos::Left, VPos::Center)).transform(FontTransform::Rotate90))
            } else {
                Text::new(name, (cx, axis_y + 6), label.pos(Pos::new(HPos::Center, VPos::Top)))
            };
            root.draw(&text)?;
        }

        // Top layer first, as the segments are stacked on screen.
        let entries: Vec<(&str, RGBColor)> = names.iter().enumerate().rev().map(|(i, n)| (*n, color(i))).collect();
        draw_legend(&legend, &entries, Swatch::Box, 12)
    }
}

/// Draws stacked bars. Non-finite values are drawn as 0; it is an error if
/// none is finite, if any is negative, or if a layer's length differs from
/// the number of categories.
pub fn stacked_bars(p: &StackedBars, size: (u32, u32)) -> Result<Figure> {
    let bad = |msg: String| Err(Error::Options(format!("stacked bars '{}': {msg}", p.title)));
    if p.categories.is_empty() {
        return bad("no categories".into());
    }
    if p.layers.is_empty() {
        return bad("no layers".into());
    }
    if let Some((name, v)) = p.layers.iter().find(|(_, v)| v.len() != p.categories.len()) {
        return bad(format!("layer '{name}' has {} values for {} categories", v.len(), p.categories.len()));
    }
    if let Some((name, v)) = p.layers.iter().find_map(|(n, v)| v.iter().find(|x| **x < 0.0).map(|x| (n, x))) {
        return bad(format!("layer '{name}' has negative value {v}"));
    }
    if !p.layers.iter().flat_map(|(_, v)| v).any(|x| x.is_finite()) {
        return bad("no finite values".into());
    }
    let values: Vec<Vec<f64>> = p.layers.iter().map(|(_, v)| v.iter().map(|&x| if x.is_finite() { x } else { 0.0 }).collect()).collect();
    let max_total = (0..p.categories.len()).map(|j| values.iter().map(|l| l[j]).sum::<f64>()).fold(0.0, f64::max);
    if !max_total.is_finite() {
        return bad("values too large to plot".into());
    }
    // Headroom for the totals printed above the bars.
    let y_max = if max_total > 0.0 { max_total * 1.12 } else { 1.0 };
    render(&Bars { p, values, y_max }, size)
}

#[cfg(test)]
mod tests;
