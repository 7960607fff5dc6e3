//! The chart kit of the figures: the font, the palette, one rendering into SVG and PNG, axes,
//! ticks, legends and colour scales. Each figure is a [`Plot`] drawn by [`render`].

use crate::error::{Error, Result};
use crate::integrate::Trajectory;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use std::sync::Once;

/// Font family written into the SVG files and name under which the embedded font is registered.
pub const FONT: &str = "DejaVu Sans, sans-serif";
pub(super) static FONT_BYTES: &[u8] = include_bytes!("../../../assets/fonts/DejaVuSans.ttf");

/// Size of the SVG figures in CSS pixels; the PNG files are twice as large.
pub const FIGURE_SIZE: (u32, u32) = (900, 560);
/// PNG pixels per SVG pixel.
pub const PNG_SCALE: f64 = 2.0;

/// Colour of blocks sliding forward (Okabe–Ito blue; colour-blind safe with [`BACKWARD`]).
pub const FORWARD: RGBColor = RGBColor(0, 114, 178);
/// Colour of blocks sliding backward (Okabe–Ito vermillion).
pub const BACKWARD: RGBColor = RGBColor(213, 94, 0);
pub(super) const STICK: RGBColor = RGBColor(110, 110, 110);
pub(super) const ORBIT: RGBColor = RGBColor(0, 158, 115);
pub(super) const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
];

pub(super) fn link_colour(l: usize) -> RGBColor {
    PALETTE[l % PALETTE.len()]
}

pub(super) fn ensure_font() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        // The bytes are a valid TrueType font checked by the tests; failing here would be a
        // build defect, and text would then be missing rather than the program crashing.
        let _ = plotters::style::register_font(FONT, FontStyle::Normal, FONT_BYTES);
    });
}

/// One rendered figure.
#[derive(Debug, Clone)]
pub struct Figure {
    /// File stem, e.g. `spacetime` (files `spacetime.svg` and `spacetime.png`).
    pub name: String,
    /// One sentence saying what the figure shows (used as the report's caption).
    pub caption: String,
    /// The SVG document.
    pub svg: String,
    /// The PNG file.
    pub png: Vec<u8>,
}

/// Scale of one rendering (1 for SVG, [`PNG_SCALE`] for PNG).
#[derive(Clone, Copy)]
pub(super) struct Sty {
    pub(super) s: f64,
}

impl Sty {
    pub(super) fn px(&self, v: f64) -> u32 {
        (v * self.s).round() as u32
    }
    pub(super) fn text(&self, size: f64) -> TextStyle<'static> {
        TextStyle::from((FONT, size * self.s).into_font())
    }
    pub(super) fn text_c(&self, size: f64, c: RGBColor) -> TextStyle<'static> {
        (FONT, size * self.s).into_font().color(&c)
    }
    pub(super) fn line(&self, c: RGBColor, w: f64) -> ShapeStyle {
        c.stroke_width(self.px(w).max(1))
    }
}

pub(super) type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

/// Something that draws itself on a drawing area of any backend.
pub(super) trait Plot {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static;
}

pub(super) fn render<P: Plot>(
    name: &str,
    caption: String,
    size: (u32, u32),
    plot: &P,
) -> Result<Figure> {
    ensure_font();
    let fail = |e: Box<dyn std::error::Error>| {
        Error::Numerical(format!("figure {name}: drawing failed: {e}"))
    };
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(e.into()))?;
        plot.draw(&root, Sty { s: 1.0 }).map_err(fail)?;
        root.present().map_err(|e| fail(e.into()))?;
    }
    let (w, h) = (
        (size.0 as f64 * PNG_SCALE) as u32,
        (size.1 as f64 * PNG_SCALE) as u32,
    );
    let mut rgb = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut rgb, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| fail(e.into()))?;
        plot.draw(&root, Sty { s: PNG_SCALE }).map_err(fail)?;
        root.present().map_err(|e| fail(e.into()))?;
    }
    let png = encode_png(&rgb, w, h).map_err(|e| fail(e.into()))?;
    Ok(Figure {
        name: name.into(),
        caption,
        svg,
        png,
    })
}

pub(super) fn encode_png(
    rgb: &[u8],
    w: u32,
    h: u32,
) -> std::result::Result<Vec<u8>, png::EncodingError> {
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(png::BitDepth::Eight);
        let mut writer = enc.write_header()?;
        writer.write_image_data(rgb)?;
    }
    Ok(out)
}

/// `[lo, hi]` of finite values, widened by `pad` of the span (or by 1 when empty or flat).
pub(super) fn range_of<'a>(values: impl IntoIterator<Item = &'a f64>, pad: f64) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for &v in values {
        if v.is_finite() {
            lo = lo.min(v);
            hi = hi.max(v);
        }
    }
    if lo > hi {
        return (-1.0, 1.0);
    }
    let span = hi - lo;
    let d = if span > 1e-12 * (lo.abs() + hi.abs()).max(1e-300) {
        pad * span
    } else {
        0.5 * lo.abs().max(1.0)
    };
    (lo - d, hi + d)
}

pub(super) type Chart2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A chart with the team's axes: labels with units, light grid, the embedded font.
pub(super) fn chart<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    s: Sty,
    title: &str,
    x: (f64, f64),
    y: (f64, f64),
    xlabel: &str,
    ylabel: &str,
) -> std::result::Result<Chart2d<'a, DB>, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    chart_x(area, s, title, x, y, xlabel, ylabel, false)
}

/// [`chart`], with tick labels on the x axis at integers only when `integer_x` (e.g. `m`).
#[allow(clippy::too_many_arguments)]
pub(super) fn chart_x<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    s: Sty,
    title: &str,
    x: (f64, f64),
    y: (f64, f64),
    xlabel: &str,
    ylabel: &str,
    integer_x: bool,
) -> std::result::Result<Chart2d<'a, DB>, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    // plotters' tick search does not end on spans that overflow; such axes are not drawable.
    for (name, (lo, hi)) in [("x", x), ("y", y)] {
        let span = hi - lo;
        if !(span.is_finite() && span > 0.0 && lo.abs().max(hi.abs()) <= 1e100) {
            return Err(
                format!("{title}: the {name} axis range [{lo:e}, {hi:e}] cannot be drawn").into(),
            );
        }
    }
    let x_ticks = if integer_x {
        ((x.1.floor() - x.0.ceil()) as usize + 1).clamp(2, 16)
    } else {
        8
    };
    let x_fmt = |v: &f64| {
        if integer_x {
            if (v - v.round()).abs() < 1e-9 {
                format!("{}", v.round() as i64)
            } else {
                String::new()
            }
        } else {
            tick(*v, x.1 - x.0)
        }
    };
    let mut c = ChartBuilder::on(area)
        .caption(title, s.text(18.0))
        .margin(s.px(10.0))
        .margin_right(s.px(18.0))
        .x_label_area_size(s.px(46.0))
        .y_label_area_size(s.px(70.0))
        .build_cartesian_2d(x.0..x.1, y.0..y.1)?;
    c.configure_mesh()
        .x_desc(xlabel)
        .y_desc(ylabel)
        .label_style(s.text(14.0))
        .axis_desc_style(s.text(15.0))
        .light_line_style(RGBColor(235, 235, 235))
        .bold_line_style(RGBColor(215, 215, 215))
        .x_labels(x_ticks)
        .y_labels(7)
        .x_label_formatter(&x_fmt)
        .y_label_formatter(&|v| tick(*v, y.1 - y.0))
        .draw()?;
    Ok(c)
}

/// A tick label: `0` for values negligible against the axis span, else up to four decimals
/// without trailing zeros.
pub(super) fn tick(v: f64, span: f64) -> String {
    if v.abs() <= 1e-9 * span.abs() {
        return "0".into();
    }
    let digits = (2.0 - (span.abs() / 8.0).log10().floor()).clamp(0.0, 8.0) as usize;
    let s = format!("{v:.digits$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    s.replace('-', "−")
}

/// The points without consecutive repetitions (event-driven samples repeat a point at an event;
/// thick polylines through a zero-length segment are drawn wrongly).
/// Interior points of straight runs are dropped as well: plotters mitres every joint of a thick
/// polyline, and a joint between collinear segments comes out as a hollow double line.
/// Points closer than 1/2000 of the extent of the whole polyline count as repeated (they would
/// fall on the same pixel).
pub(super) fn dedup(pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    let (xr, yr) = (
        range_of(pts.iter().map(|p| &p.0), 0.0),
        range_of(pts.iter().map(|p| &p.1), 0.0),
    );
    let (ex, ey) = (5e-4 * (xr.1 - xr.0), 5e-4 * (yr.1 - yr.0));
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(pts.len());
    for p in pts {
        if let Some(q) = out.last() {
            if (p.0 - q.0).abs() <= ex && (p.1 - q.1).abs() <= ey {
                continue;
            }
        }
        if out.len() >= 2 {
            let (a, b) = (out[out.len() - 2], out[out.len() - 1]);
            let (u, v) = ((b.0 - a.0, b.1 - a.1), (p.0 - b.0, p.1 - b.1));
            let cross = u.0 * v.1 - u.1 * v.0;
            let dot = u.0 * v.0 + u.1 * v.1;
            let scale = u.0.hypot(u.1) * v.0.hypot(v.1);
            if dot > 0.0 && cross.abs() <= 1e-9 * scale {
                out.pop();
            }
        }
        out.push(p);
    }
    out
}

/// A thick polyline. plotters mitres the joints of a thick polyline, and two cases come out
/// wrong in the bitmap: a segment of zero length in pixels (a spike shooting out of the plot) and
/// a turn back on itself (a hollow double line), both common on orbits running along the faces of
/// C. So points falling on the pixel of their predecessor are dropped, and a polyline with turns
/// sharper than 120° is drawn as separate segments with round joints.
pub(super) fn draw_thick<'a, DB: DrawingBackend + 'a>(
    c: &mut Chart2d<'a, DB>,
    pts: &[(f64, f64)],
    colour: RGBColor,
    width: f64,
    s: Sty,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    let mut kept: Vec<(f64, f64)> = Vec::with_capacity(pts.len());
    let mut last_px = None;
    for &p in pts {
        let q = c.backend_coord(&p);
        if last_px != Some(q) {
            kept.push(p);
            last_px = Some(q);
        }
    }
    let pts = dedup(kept);
    let (xr, yr) = (c.x_range(), c.y_range());
    let (w, h) = c.plotting_area().dim_in_pixel();
    let (kx, ky) = (
        w as f64 / (xr.end - xr.start),
        h as f64 / (yr.end - yr.start),
    );
    let sharp = pts.windows(3).any(|w| {
        let u = (kx * (w[1].0 - w[0].0), ky * (w[1].1 - w[0].1));
        let v = (kx * (w[2].0 - w[1].0), ky * (w[2].1 - w[1].1));
        let n = u.0.hypot(u.1) * v.0.hypot(v.1);
        n > 0.0 && (u.0 * v.0 + u.1 * v.1) < -0.5 * n
    });
    if !sharp {
        c.draw_series(std::iter::once(PathElement::new(
            pts,
            s.line(colour, width),
        )))?;
        return Ok(());
    }
    c.draw_series(
        pts.windows(2)
            .map(|w| PathElement::new(vec![w[0], w[1]], s.line(colour, width))),
    )?;
    let r = (s.px(width) / 2).max(1);
    c.draw_series(pts.iter().map(|&p| Circle::new(p, r, colour.filled())))?;
    Ok(())
}

/// The axes of a heat map's colour bar in `area`: values from `-vmax` to `vmax` on the right,
/// named `desc`; the caller draws the bands.
pub(super) fn colour_bar<'a, DB: DrawingBackend>(
    area: &'a DrawingArea<DB, Shift>,
    s: Sty,
    vmax: f64,
    desc: &str,
) -> std::result::Result<Chart2d<'a, DB>, Box<dyn std::error::Error>>
where
    DB::ErrorType: 'static,
{
    let mut cb = ChartBuilder::on(area)
        .margin_top(s.px(40.0))
        .margin_bottom(s.px(56.0))
        .margin_left(s.px(8.0))
        .margin_right(s.px(10.0))
        .y_label_area_size(s.px(0.0))
        .right_y_label_area_size(s.px(70.0))
        .build_cartesian_2d(0.0..1.0, -vmax..vmax)?;
    let span = 2.0 * vmax;
    cb.configure_mesh()
        .disable_x_mesh()
        .disable_y_mesh()
        .disable_x_axis()
        .y_label_formatter(&|v| tick(*v, span))
        .y_desc(desc)
        .label_style(s.text(12.0))
        .axis_desc_style(s.text(13.0))
        .draw()?;
    Ok(cb)
}

pub(super) fn legend<'a, DB: DrawingBackend + 'a>(
    c: &mut Chart2d<'a, DB>,
    s: Sty,
    pos: SeriesLabelPosition,
) -> DrawResult
where
    DB::ErrorType: 'static,
{
    c.configure_series_labels()
        .position(pos)
        .background_style(WHITE.mix(0.9))
        .border_style(RGBColor(180, 180, 180))
        .label_font(s.text(13.0))
        .margin(s.px(8.0))
        .draw()?;
    Ok(())
}

pub(super) fn legend_line(c: RGBColor, w: u32) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
    move |(x, y)| PathElement::new(vec![(x, y), (x + 22, y)], c.stroke_width(w))
}

/// Unicode subscript of a (1-based) index, e.g. 12 -> "₁₂".
pub fn sub(i: usize) -> String {
    i.to_string()
        .chars()
        .map(|c| char::from_u32(0x2080 + c.to_digit(10).unwrap_or(0)).unwrap_or(c))
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Actuation L(t) and rate u(t)

/// Room at the top of a panel for a legend of `entries` lines (it must not hide the curves).
pub(super) fn headroom((lo, hi): (f64, f64), entries: usize) -> (f64, f64) {
    (lo, hi + (hi - lo) * (0.1 + 0.09 * entries.min(6) as f64))
}

/// Colour steps on each side of zero in the v_m heat map.
pub(super) const LEVELS: i32 = 12;

pub(super) fn diverging(t: f64) -> RGBColor {
    // t in [-1, 1]: vermillion (backward) - white - blue (forward).
    let t = t.clamp(-1.0, 1.0);
    let (c, w) = if t >= 0.0 {
        (FORWARD, t)
    } else {
        (BACKWARD, -t)
    };
    let w = w.powf(0.8);
    let mix = |a: u8| (255.0 + w * (a as f64 - 255.0)).round() as u8;
    RGBColor(mix(c.0), mix(c.1), mix(c.2))
}

pub(super) fn check_trajectory(traj: &Trajectory) -> Result<()> {
    let ok = traj.t.len() >= 2
        && traj.positions.len() == traj.t.len()
        && traj.x.len() == traj.t.len()
        && traj.slip.len() == traj.t.len()
        && traj.barycentre.len() == traj.t.len()
        && !traj.positions[0].is_empty();
    if ok {
        Ok(())
    } else {
        Err(Error::invalid(
            "trajectory",
            format!("{} samples", traj.t.len()),
            "a figure needs at least two samples with positions, states and slip states",
        ))
    }
}

pub(super) fn fmt_num(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let a = v.abs();
    if (1e-3..1e5).contains(&a) {
        let s = format!("{v:.4}");
        let s = s.trim_end_matches('0').trim_end_matches('.');
        s.replace('-', "−")
    } else {
        format!("{v:.3e}").replace('-', "−")
    }
}
