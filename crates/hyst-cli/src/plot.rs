//! Shared plotting helpers: figures of one or more panels, each with line, dashed and scatter
//! series, axis labels (with units), a legend and optional horizontal lines (error bounds),
//! written (atomically) as PNG and SVG with the embedded DejaVu Sans font (no system font
//! library).
//!
//! ```ignore
//! let panel = Panel::new("Compensation error", "time t (s)", "error (normalised flux)")
//!     .series(Series::line("u_d − Φ", points))
//!     .bound("bound Δb = ±0.03", 0.03);
//! let written = Figure::row(vec![panel]).save(Path::new("out"), "fig5")?; // fig5.png, fig5.svg
//! ```

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use anyhow::{anyhow, Context, Result};
use image::codecs::png::PngEncoder;
use image::{ColorType, ImageEncoder};
use plotters::backend::RGBPixel;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle, RGBColor};

/// DejaVu Sans 2.37 (see `assets/README.md` for its origin and licence).
static FONT: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the embedded font as plotters' "sans-serif" family, once.
fn ensure_font() -> Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok =
        *REGISTERED.get_or_init(|| register_font("sans-serif", FontStyle::Normal, FONT).is_ok());
    if ok {
        Ok(())
    } else {
        Err(anyhow!("the embedded font could not be loaded"))
    }
}

/// Colours of series, in order of use (colour-blind friendly, after Okabe and Ito).
pub const PALETTE: [RGBColor; 8] = [
    RGBColor(0, 114, 178),   // blue
    RGBColor(213, 94, 0),    // vermillion
    RGBColor(0, 158, 115),   // green
    RGBColor(204, 121, 167), // purple
    RGBColor(230, 159, 0),   // orange
    RGBColor(86, 180, 233),  // sky blue
    RGBColor(120, 120, 120), // grey
    RGBColor(0, 0, 0),       // black
];

/// How a series is drawn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Style {
    /// A solid line through the points in order.
    Line,
    /// A dashed line through the points in order.
    Dashed,
    /// One dot per point.
    Points,
}

/// One data series of a panel.
#[derive(Clone, Debug)]
pub struct Series {
    /// Legend text (empty: not in the legend).
    pub label: String,
    /// (x, y) points in data units; non-finite points are skipped.
    pub points: Vec<(f64, f64)>,
    /// Line, dashed line or points.
    pub style: Style,
    /// Index into [`PALETTE`]; `None` takes the next colour.
    pub color: Option<usize>,
    /// Line width or dot radius, in pixels.
    pub width: u32,
}

impl Series {
    fn new(label: &str, points: Vec<(f64, f64)>, style: Style, width: u32) -> Self {
        Self {
            label: label.to_string(),
            points,
            style,
            color: None,
            width,
        }
    }
    /// A solid line.
    pub fn line(label: &str, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Line, 2)
    }
    /// A dashed line.
    pub fn dashed(label: &str, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Dashed, 2)
    }
    /// A scatter of dots.
    pub fn scatter(label: &str, points: Vec<(f64, f64)>) -> Self {
        Self::new(label, points, Style::Points, 2)
    }
    /// Picks the colour (index into [`PALETTE`], wrapping).
    #[must_use]
    pub fn color(mut self, index: usize) -> Self {
        self.color = Some(index);
        self
    }
    /// Sets the line width or dot radius in pixels.
    #[must_use]
    pub fn width(mut self, pixels: u32) -> Self {
        self.width = pixels.max(1);
        self
    }
}

/// A horizontal reference line (an error bound, say), drawn dashed across the panel.
#[derive(Clone, Debug)]
pub struct HLine {
    /// Legend text (shared by lines with the same label: it appears once).
    pub label: String,
    /// Height in data units.
    pub y: f64,
    /// Index into [`PALETTE`].
    pub color: usize,
}

/// Where the legend goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Legend {
    /// Top left corner.
    UpperLeft,
    /// Top right corner.
    UpperRight,
    /// Bottom left corner.
    LowerLeft,
    /// Bottom right corner.
    LowerRight,
    /// In a strip below the panel, outside the plot area: covers no data, for panels whose
    /// data fill every corner.
    Below,
}

/// One chart: a title, labelled axes, series, horizontal lines and a legend. The axes span the
/// data (x exactly, y padded by 6 % and including the horizontal lines).
#[derive(Clone, Debug)]
pub struct Panel {
    /// Title above the chart.
    pub title: String,
    /// X axis label, with units, e.g. "time t (s)".
    pub x_label: String,
    /// Y axis label, with units.
    pub y_label: String,
    /// The data.
    pub series: Vec<Series>,
    /// Horizontal lines.
    pub hlines: Vec<HLine>,
    /// Legend position.
    pub legend: Legend,
}

impl Panel {
    /// An empty panel with a title and axis labels (put the units in the labels).
    pub fn new(title: &str, x_label: &str, y_label: &str) -> Self {
        Self {
            title: title.to_string(),
            x_label: x_label.to_string(),
            y_label: y_label.to_string(),
            series: Vec::new(),
            hlines: Vec::new(),
            legend: Legend::UpperRight,
        }
    }
    /// Adds a series.
    #[must_use]
    pub fn series(mut self, series: Series) -> Self {
        self.series.push(series);
        self
    }
    /// Adds a horizontal line at `y` (black dashed unless recoloured with [`Panel::hline_color`]).
    #[must_use]
    pub fn hline(self, label: &str, y: f64) -> Self {
        self.hline_color(label, y, 7)
    }
    /// Adds a horizontal line at `y` with a palette colour.
    #[must_use]
    pub fn hline_color(mut self, label: &str, y: f64, color: usize) -> Self {
        self.hlines.push(HLine {
            label: label.to_string(),
            y,
            color,
        });
        self
    }
    /// Adds the pair of horizontal lines ±`bound` (one legend entry).
    #[must_use]
    pub fn bound(self, label: &str, bound: f64) -> Self {
        self.hline(label, bound).hline(label, -bound)
    }
    /// Moves the legend.
    #[must_use]
    pub fn legend(mut self, legend: Legend) -> Self {
        self.legend = legend;
        self
    }

    fn data_range(&self) -> ((f64, f64), (f64, f64)) {
        let mut x = (f64::INFINITY, f64::NEG_INFINITY);
        let mut y = (f64::INFINITY, f64::NEG_INFINITY);
        for (px, py) in self
            .series
            .iter()
            .flat_map(|s| s.points.iter().copied())
            .filter(|(a, b)| a.is_finite() && b.is_finite())
        {
            x = (x.0.min(px), x.1.max(px));
            y = (y.0.min(py), y.1.max(py));
        }
        for h in self.hlines.iter().filter(|h| h.y.is_finite()) {
            y = (y.0.min(h.y), y.1.max(h.y));
        }
        (pad(x, 0.0), pad(y, 0.06))
    }
}

/// Widens a range by `fraction` of its span on each side; guards empty and zero-width ranges.
fn pad((lo, hi): (f64, f64), fraction: f64) -> (f64, f64) {
    if !(lo.is_finite() && hi.is_finite()) {
        return (0.0, 1.0);
    }
    let span = hi - lo;
    if span <= f64::EPSILON * lo.abs().max(hi.abs()).max(1e-300) {
        let d = if lo == 0.0 { 1.0 } else { 0.1 * lo.abs() };
        return (lo - d, hi + d);
    }
    (lo - fraction * span, hi + fraction * span)
}

/// Size of one panel in pixels (width, height).
const PANEL_SIZE: (u32, u32) = (720, 540);

/// A figure: panels side by side in one row, [`PANEL_SIZE`] pixels each.
#[derive(Clone, Debug)]
pub struct Figure {
    /// The panels, left to right.
    pub panels: Vec<Panel>,
}

impl Figure {
    /// Panels side by side in one row.
    pub fn row(panels: Vec<Panel>) -> Self {
        Self { panels }
    }

    /// Number of panels, at least 1 (an empty figure is one blank panel wide).
    fn columns(&self) -> usize {
        self.panels.len().max(1)
    }

    /// Size of the whole figure in pixels.
    fn size(&self) -> (u32, u32) {
        (PANEL_SIZE.0 * self.columns() as u32, PANEL_SIZE.1)
    }

    /// Writes `dir/stem.png` and `dir/stem.svg` (creating `dir`), each atomically with
    /// [`hyst_io::write_atomic`], returning both paths.
    ///
    /// # Errors
    /// When the directory cannot be created or a file cannot be drawn or written.
    pub fn save(&self, dir: &Path, stem: &str) -> Result<Vec<PathBuf>> {
        ensure_font()?;
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create directory {}", dir.display()))?;
        let png = dir.join(format!("{stem}.png"));
        let svg = dir.join(format!("{stem}.svg"));
        let (width, height) = self.size();

        let mut rgb = vec![0; 3 * width as usize * height as usize];
        {
            let root = BitMapBackend::<RGBPixel>::with_buffer_and_format(&mut rgb, (width, height))
                .map_err(|e| anyhow!("{e}"))
                .and_then(|backend| {
                    let root = backend.into_drawing_area();
                    self.draw(&root)?;
                    root.present().map_err(|e| anyhow!("{e}"))
                });
            root.with_context(|| format!("cannot draw {}", png.display()))?;
        }
        let mut encoded = Vec::new();
        PngEncoder::new(&mut encoded)
            .write_image(&rgb, width, height, ColorType::Rgb8)
            .with_context(|| format!("cannot encode {}", png.display()))?;
        hyst_io::write_atomic(&png, &encoded)?;

        let mut text = String::new();
        {
            let root = SVGBackend::with_string(&mut text, (width, height)).into_drawing_area();
            self.draw(&root)
                .and_then(|()| root.present().map_err(|e| anyhow!("{e}")))
                .with_context(|| format!("cannot draw {}", svg.display()))?;
        }
        hyst_io::write_atomic(&svg, text.as_bytes())?;
        Ok(vec![png, svg])
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<()> {
        root.fill(&WHITE).map_err(|e| anyhow!("{e}"))?;
        let areas = root.split_evenly((1, self.columns()));
        for (panel, area) in self.panels.iter().zip(areas.iter()) {
            draw_panel(panel, area)?;
        }
        Ok(())
    }
}

/// Height in pixels of the legend strip of [`Legend::Below`].
const LEGEND_STRIP: u32 = 34;

/// One legend entry drawn by hand (for [`Legend::Below`]).
struct Entry<'a> {
    label: &'a str,
    color: RGBColor,
    style: Style,
}

/// Draws `entries` in one centred row in `area` (a strip below the chart).
fn draw_strip<DB: DrawingBackend>(area: &DrawingArea<DB, Shift>, entries: &[Entry]) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("{e}");
    let font: TextStyle = ("sans-serif", 16).into();
    let (width, height) = area.dim_in_pixel();
    let swatch = 26_i32;
    let gap = 22_i32;
    let mut widths = Vec::with_capacity(entries.len());
    for e in entries {
        let (w, _) = area.estimate_text_size(e.label, &font).map_err(err)?;
        widths.push(w as i32);
    }
    let total: i32 = widths.iter().map(|w| swatch + 6 + w).sum::<i32>()
        + gap * (entries.len() as i32 - 1).max(0);
    let mut x = ((width as i32 - total) / 2).max(4);
    let y = height as i32 / 2;
    for (e, w) in entries.iter().zip(&widths) {
        match e.style {
            Style::Line => area
                .draw(&PathElement::new(
                    vec![(x, y), (x + swatch - 4, y)],
                    e.color.stroke_width(3),
                ))
                .map_err(err)?,
            Style::Dashed => {
                area.draw(&PathElement::new(
                    vec![(x, y), (x + 9, y)],
                    e.color.stroke_width(2),
                ))
                .map_err(err)?;
                area.draw(&PathElement::new(
                    vec![(x + 14, y), (x + swatch - 4, y)],
                    e.color.stroke_width(2),
                ))
                .map_err(err)?;
            }
            Style::Points => area
                .draw(&Circle::new((x + 11, y), 4, e.color.filled()))
                .map_err(err)?,
        }
        area.draw(&Text::new(
            e.label.to_string(),
            (x + swatch + 2, y - 9),
            font.clone(),
        ))
        .map_err(err)?;
        x += swatch + 6 + w + gap;
    }
    Ok(())
}

/// A tick label: rounded to a millionth of the axis span, so values that are zero up to rounding
/// print as "0" (never "-0.0"), in the shortest form that reads back to the rounded value.
fn tick_label(v: f64, span: f64) -> String {
    let quantum = if span.is_finite() && span > 0.0 {
        10f64.powf((span * 1e-6).log10().floor())
    } else {
        1e-12
    };
    let r = (v / quantum).round() * quantum;
    let r = if r == 0.0 { 0.0 } else { r };
    // Trim the binary noise of the rounding (0.30000000000000004 -> 0.3).
    let digits = (-quantum.log10()).ceil().clamp(0.0, 15.0) as usize;
    let text = format!("{r:.digits$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    };
    if text == "-0" {
        "0".to_string()
    } else {
        text
    }
}

/// The chart of a panel: data coordinates on both axes.
type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

fn draw_panel<DB: DrawingBackend>(panel: &Panel, whole: &DrawingArea<DB, Shift>) -> Result<()> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("{e}");
    let ((x0, x1), (y0, y1)) = panel.data_range();
    let (area, strip) = if panel.legend == Legend::Below {
        let height = whole.dim_in_pixel().1;
        let (top, bottom) = whole.split_vertically(height.saturating_sub(LEGEND_STRIP));
        (top, Some(bottom))
    } else {
        (whole.clone(), None)
    };
    let mut entries: Vec<Entry> = Vec::new();
    let area = &area;
    let mut chart = ChartBuilder::on(area)
        .caption(&panel.title, ("sans-serif", 22))
        .margin(12)
        .x_label_area_size(52)
        .y_label_area_size(78)
        .build_cartesian_2d(x0..x1, y0..y1)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(panel.x_label.as_str())
        .y_desc(panel.y_label.as_str())
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 15))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(205, 205, 205))
        .x_labels(7)
        .y_labels(7)
        .x_label_formatter(&|v| tick_label(*v, x1 - x0))
        .y_label_formatter(&|v| tick_label(*v, y1 - y0))
        .draw()
        .map_err(err)?;

    let series_labelled = draw_series(&mut chart, panel, &mut entries)?;
    let lines_labelled = draw_hlines(&mut chart, panel, (x0, x1), &mut entries)?;
    let any_label = series_labelled || lines_labelled;
    let position = match panel.legend {
        Legend::UpperLeft => Some(SeriesLabelPosition::UpperLeft),
        Legend::UpperRight => Some(SeriesLabelPosition::UpperRight),
        Legend::LowerLeft => Some(SeriesLabelPosition::LowerLeft),
        Legend::LowerRight => Some(SeriesLabelPosition::LowerRight),
        Legend::Below => None,
    };
    if let (Some(strip), true) = (&strip, any_label) {
        draw_strip(strip, &entries)?;
    }
    if let (Some(position), true) = (position, any_label) {
        chart
            .configure_series_labels()
            .position(position)
            .label_font(("sans-serif", 16))
            .background_style(WHITE.mix(0.85))
            .border_style(RGBColor(150, 150, 150))
            .margin(10)
            .draw()
            .map_err(err)?;
    }
    Ok(())
}

/// Draws the series of `panel` on `chart`, each in its colour (the palette's next unless
/// given), and adds the labelled ones to the legend and to `entries`; whether any is labelled.
fn draw_series<'a, 'p, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    panel: &'p Panel,
    entries: &mut Vec<Entry<'p>>,
) -> Result<bool> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("{e}");
    let mut next = 0usize;
    let mut any_label = false;
    for s in &panel.series {
        let index = s.color.unwrap_or_else(|| {
            let i = next;
            next += 1;
            i
        });
        let color = PALETTE[index % PALETTE.len()];
        let pts = s
            .points
            .iter()
            .copied()
            .filter(|(a, b)| a.is_finite() && b.is_finite());
        let w = s.width;
        let anno = match s.style {
            Style::Line => chart
                .draw_series(LineSeries::new(pts, color.stroke_width(w)))
                .map_err(err)?,
            Style::Dashed => chart
                .draw_series(DashedLineSeries::new(
                    pts.collect::<Vec<_>>(),
                    10,
                    6,
                    color.stroke_width(w),
                ))
                .map_err(err)?,
            Style::Points => chart
                .draw_series(pts.map(|p| Circle::new(p, w, color.filled())))
                .map_err(err)?,
        };
        if !s.label.is_empty() {
            any_label = true;
            entries.push(Entry {
                label: s.label.as_str(),
                color,
                style: s.style,
            });
            let anno = anno.label(s.label.as_str());
            if s.style == Style::Points {
                anno.legend(move |(x, y)| {
                    EmptyElement::at((x, y)) + Circle::new((10, 0), 4, color.filled())
                });
            } else {
                anno.legend(move |(x, y)| {
                    EmptyElement::at((x, y))
                        + PathElement::new(vec![(0, 0), (22, 0)], color.stroke_width(3))
                });
            }
        }
    }
    Ok(any_label)
}

/// Draws the horizontal lines of `panel` across the chart's x range `(x0, x1)`, dashed, and
/// adds each label once to the legend and to `entries`; whether any is labelled.
fn draw_hlines<'a, 'p, DB: DrawingBackend + 'a>(
    chart: &mut Chart<'a, DB>,
    panel: &'p Panel,
    (x0, x1): (f64, f64),
    entries: &mut Vec<Entry<'p>>,
) -> Result<bool> {
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| anyhow!("{e}");
    let mut any_label = false;
    let mut seen: Vec<&str> = Vec::new();
    for h in &panel.hlines {
        let color = PALETTE[h.color % PALETTE.len()];
        let anno = chart
            .draw_series(DashedLineSeries::new(
                vec![(x0, h.y), (x1, h.y)],
                8,
                6,
                color.stroke_width(2),
            ))
            .map_err(err)?;
        if !h.label.is_empty() && !seen.contains(&h.label.as_str()) {
            seen.push(h.label.as_str());
            any_label = true;
            entries.push(Entry {
                label: h.label.as_str(),
                color,
                style: Style::Dashed,
            });
            anno.label(h.label.as_str()).legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(vec![(0, 0), (8, 0)], color.stroke_width(2))
                    + PathElement::new(vec![(13, 0), (22, 0)], color.stroke_width(2))
            });
        }
    }
    Ok(any_label)
}

#[cfg(test)]
mod tests {
    #[test]
    fn tick_labels_are_short_and_never_negative_zero() {
        assert_eq!(super::tick_label(-1e-18, 0.3), "0");
        assert_eq!(super::tick_label(0.1 + 0.2, 1.0), "0.3");
        assert_eq!(super::tick_label(-0.05, 0.3), "-0.05");
        assert_eq!(super::tick_label(20.0, 60.0), "20");
        assert_eq!(super::tick_label(2.5e-5, 1e-4), "0.000025");
    }

    use super::*;

    #[test]
    fn writes_png_and_svg() -> Result<()> {
        let dir = std::env::temp_dir().join(format!("hyst-plot-test-{}", std::process::id()));
        let pts: Vec<(f64, f64)> = (0..100)
            .map(|i| (i as f64, (i as f64 * 0.1).sin()))
            .collect();
        let fig = Figure::row(vec![
            Panel::new("sine", "time t (s)", "y (1)")
                .series(Series::line("sin", pts.clone()))
                .bound("±0.5", 0.5),
            Panel::new("dots", "x (1)", "y (1)")
                .series(Series::scatter("pts", pts))
                .legend(Legend::LowerLeft),
            Panel::new("strip", "x (1)", "y (1)")
                .series(Series::dashed("legend below", vec![(0.0, 0.0), (1.0, 1.0)]))
                .bound("bound", 0.5)
                .legend(Legend::Below),
        ]);
        let files = fig.save(&dir, "t")?;
        for f in &files {
            let len = std::fs::metadata(f)?.len();
            assert!(len > 1000, "{} has {len} bytes", f.display());
        }
        let png = std::fs::read(&files[0])?;
        assert_eq!(png[..8], *b"\x89PNG\r\n\x1a\n");
        // IHDR: width and height of three 720 x 540 panels in a row.
        assert_eq!(png[16..24], [0, 0, 0x08, 0x70, 0, 0, 0x02, 0x1c]);
        let svg = std::fs::read_to_string(&files[1])?;
        assert!(
            svg.starts_with("<svg width=\"2160\" height=\"540\""),
            "{}",
            &svg[..80]
        );
        assert!(svg.trim_end().ends_with("</svg>"));
        assert!(svg.contains("time t (s)"));
        assert!(svg.contains("legend below"));
        let mut names: Vec<_> = std::fs::read_dir(&dir)?
            .map(|e| e.map(|e| e.file_name()))
            .collect::<std::io::Result<_>>()?;
        names.sort();
        assert_eq!(names, ["t.png", "t.svg"], "temporary files left behind");
        std::fs::remove_dir_all(&dir)?;
        Ok(())
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        assert_eq!(pad((1.0, 1.0), 0.0), (0.9, 1.1));
        assert_eq!(pad((0.0, 0.0), 0.0), (-1.0, 1.0));
        assert_eq!(pad((f64::INFINITY, f64::NEG_INFINITY), 0.1), (0.0, 1.0));
    }
}
