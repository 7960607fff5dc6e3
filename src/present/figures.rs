//! The figures: plain data in, SVG text and PNG bytes out.
//!
//! Every figure is drawn twice by the same code, with `plotters`: once into an SVG document (text
//! stays text, so the SVG can be searched, restyled and put in a paper) and once into an RGB
//! bitmap at twice the size (encoded as PNG with the `png` crate), for slides and quick looks.
//! Text is laid out and rasterised with the DejaVu Sans font compiled into the binary
//! (`assets/fonts/`), so no system font is needed; the SVG asks for "DejaVu Sans" with a
//! sans-serif fallback.
//!
//! Units: the model's units are any consistent set (README), so axes name the dimension in
//! brackets: `[length]`, `[force]`, `[time]`, `[force/time]`.
//!
//! The data types ([`ActuationSeries`], [`SpaceTime`], ...) are plain arrays, so that a figure can
//! be drawn from any source: a simulation, a gait result, or another program's numbers (the
//! adjoint of a certificate).

use crate::error::{Error, Result};
use crate::integrate::Trajectory;
use crate::model::Crawler;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::sync::Once;

pub mod fit;
pub mod sweep;

/// Font family written into the SVG files and name under which the embedded font is registered.
pub const FONT: &str = "DejaVu Sans, sans-serif";
static FONT_BYTES: &[u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");

/// Size of the SVG figures in CSS pixels; the PNG files are twice as large.
pub const FIGURE_SIZE: (u32, u32) = (900, 560);
/// PNG pixels per SVG pixel.
pub const PNG_SCALE: f64 = 2.0;

/// Colour of blocks sliding forward (Okabe–Ito blue; colour-blind safe with [`BACKWARD`]).
pub const FORWARD: RGBColor = RGBColor(0, 114, 178);
/// Colour of blocks sliding backward (Okabe–Ito vermillion).
pub const BACKWARD: RGBColor = RGBColor(213, 94, 0);
const STICK: RGBColor = RGBColor(110, 110, 110);
const ORBIT: RGBColor = RGBColor(0, 158, 115);
const PALETTE: [RGBColor; 6] = [
    RGBColor(0, 114, 178),
    RGBColor(213, 94, 0),
    RGBColor(0, 158, 115),
    RGBColor(204, 121, 167),
    RGBColor(230, 159, 0),
    RGBColor(86, 180, 233),
];

fn link_colour(l: usize) -> RGBColor {
    PALETTE[l % PALETTE.len()]
}

fn ensure_font() {
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
struct Sty {
    s: f64,
}

impl Sty {
    fn px(&self, v: f64) -> u32 {
        (v * self.s).round() as u32
    }
    fn text(&self, size: f64) -> TextStyle<'static> {
        TextStyle::from((FONT, size * self.s).into_font())
    }
    fn text_c(&self, size: f64, c: RGBColor) -> TextStyle<'static> {
        (FONT, size * self.s).into_font().color(&c)
    }
    fn line(&self, c: RGBColor, w: f64) -> ShapeStyle {
        c.stroke_width(self.px(w).max(1))
    }
}

type DrawResult = std::result::Result<(), Box<dyn std::error::Error>>;

/// Something that draws itself on a drawing area of any backend.
trait Plot {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static;
}

fn render<P: Plot>(name: &str, caption: String, size: (u32, u32), plot: &P) -> Result<Figure> {
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

fn encode_png(rgb: &[u8], w: u32, h: u32) -> std::result::Result<Vec<u8>, png::EncodingError> {
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
fn range_of<'a>(values: impl IntoIterator<Item = &'a f64>, pad: f64) -> (f64, f64) {
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

type Chart2d<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

/// A chart with the team's axes: labels with units, light grid, the embedded font.
fn chart<'a, DB: DrawingBackend>(
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
fn chart_x<'a, DB: DrawingBackend>(
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
fn tick(v: f64, span: f64) -> String {
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
fn dedup(pts: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
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
fn draw_thick<'a, DB: DrawingBackend + 'a>(
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
fn colour_bar<'a, DB: DrawingBackend>(
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

fn legend<'a, DB: DrawingBackend + 'a>(
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

fn legend_line(c: RGBColor, w: u32) -> impl Fn((i32, i32)) -> PathElement<(i32, i32)> {
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
fn headroom((lo, hi): (f64, f64), entries: usize) -> (f64, f64) {
    (lo, hi + (hi - lo) * (0.1 + 0.09 * entries.min(6) as f64))
}

/// A piecewise-linear actuation over one period: `L` at the knots and `u = K L'` on the pieces.
#[derive(Debug, Clone, PartialEq)]
pub struct ActuationSeries {
    /// Knot times from 0 to the period `T` inclusive.
    pub times: Vec<f64>,
    /// `L(t_j)` at every knot, one row per knot (`times.len()` rows).
    pub lengths: Vec<Vec<f64>>,
    /// `u_j = K (L_{j+1} - L_j) / (t_{j+1} - t_j)` on every piece (`times.len() - 1` rows).
    pub controls: Vec<Vec<f64>>,
    /// Rate bounds `a_l` of the gait problem, drawn as the bang-bang levels `±a_l`.
    pub rate_bound: Option<Vec<f64>>,
}

impl ActuationSeries {
    /// From knots over one period (`times` from 0 to `T` inclusive, one row of lengths per knot)
    /// and the stiffnesses: the controls are the slopes times `k_l`. Zero-length pieces are
    /// dropped.
    pub fn from_knots(
        times: &[f64],
        lengths: &[Vec<f64>],
        stiffness: &[f64],
        rate_bound: Option<Vec<f64>>,
    ) -> Result<Self> {
        if times.len() < 2 || times.len() != lengths.len() {
            return Err(Error::invalid(
                "actuation knots",
                format!("{} times, {} rows", times.len(), lengths.len()),
                "need at least two knots and one row of lengths per knot",
            ));
        }
        let (mut t, mut l, mut u) = (vec![times[0]], vec![lengths[0].clone()], Vec::new());
        for j in 1..times.len() {
            let dt = times[j] - times[j - 1];
            if dt.is_nan() || dt <= 0.0 {
                continue;
            }
            u.push(
                (0..stiffness.len())
                    .map(|i| stiffness[i] * (lengths[j][i] - lengths[j - 1][i]) / dt)
                    .collect(),
            );
            t.push(times[j]);
            l.push(lengths[j].clone());
        }
        if u.is_empty() {
            return Err(Error::invalid(
                "actuation knots",
                "no piece of positive duration",
                "need increasing times",
            ));
        }
        Ok(ActuationSeries {
            times: t,
            lengths: l,
            controls: u,
            rate_bound,
        })
    }
}

impl Plot for ActuationSeries {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let n = self.lengths[0].len();
        let period = *self.times.last().unwrap_or(&1.0);
        let (top, bottom) = root.split_vertically(root.dim_in_pixel().1 / 2);
        let lr = headroom(range_of(self.lengths.iter().flatten(), 0.08), n);
        let mut c = chart(
            &top,
            s,
            "Actuation over one period",
            (0.0, period),
            lr,
            "time t [time]",
            "actuator length L [length]",
        )?;
        for l in 0..n {
            let pts: Vec<(f64, f64)> = self
                .times
                .iter()
                .zip(&self.lengths)
                .map(|(&t, row)| (t, row[l]))
                .collect();
            draw_thick(&mut c, &pts, link_colour(l), 2.2, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label(format!("L{}(t)", sub(l + 1)))
                .legend(legend_line(link_colour(l), s.px(2.5)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        let mut urange: Vec<f64> = self.controls.iter().flatten().copied().collect();
        if let Some(a) = &self.rate_bound {
            urange.extend(a.iter().flat_map(|a| [*a, -*a]));
        }
        let ur = headroom(range_of(&urange, 0.12), n);
        let mut c = chart(
            &bottom,
            s,
            if self.rate_bound.is_some() {
                "Rate u = k L′ (bang-bang arcs sit on the dashed bounds ±a)"
            } else {
                "Rate u = k L′"
            },
            (0.0, period),
            ur,
            "time t [time]",
            "rate u [force/time]",
        )?;
        if let Some(a) = &self.rate_bound {
            for (l, &a) in a.iter().enumerate() {
                for v in [a, -a] {
                    c.draw_series(DashedLineSeries::new(
                        vec![(0.0, v), (period, v)],
                        s.px(6.0),
                        s.px(4.0),
                        s.line(RGBColor(150, 150, 150), 1.0),
                    ))?;
                }
                if l == 0 {
                    c.draw_series(std::iter::once(Text::new(
                        "±a",
                        (period * 0.005, a),
                        s.text_c(12.0, RGBColor(110, 110, 110))
                            .pos(Pos::new(HPos::Left, VPos::Bottom)),
                    )))?;
                }
            }
        }
        for l in 0..n {
            let mut pts = Vec::with_capacity(2 * self.controls.len());
            for (j, u) in self.controls.iter().enumerate() {
                pts.push((self.times[j], u[l]));
                pts.push((self.times[j + 1], u[l]));
            }
            draw_thick(&mut c, &pts, link_colour(l), 2.2, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label(format!("u{}(t)", sub(l + 1)))
                .legend(legend_line(link_colour(l), s.px(2.5)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}

/// Figure `actuation`: `L_l(t)` and `u_l(t)` over a period.
pub fn actuation_figure(a: &ActuationSeries) -> Result<Figure> {
    render(
        "actuation",
        format!(
            "Actuator lengths L(t) and rates u(t) = k L′(t) over one period{}.",
            if a.rate_bound.is_some() {
                "; dashed: the rate bounds ±a"
            } else {
                ""
            }
        ),
        (FIGURE_SIZE.0, 640),
        a,
    )
}

// ---------------------------------------------------------------------------------------------
// Space-time diagram

/// Drawing offset between consecutive blocks (a rest length for display only: the model's shape
/// `z` is measured from an arbitrary rest length), large enough that blocks never overlap in a
/// picture of `traj`.
pub fn display_spacing(traj: &Trajectory) -> f64 {
    let (mut zmin, mut zmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for p in &traj.positions {
        for w in p.windows(2) {
            let z = w[1] - w[0];
            zmin = zmin.min(z);
            zmax = zmax.max(z);
        }
    }
    if !(zmin.is_finite() && zmax.is_finite()) {
        return 1.0;
    }
    let span = (zmax - zmin).max(1e-9 * zmax.abs().max(1.0));
    nice_ceil((-zmin).max(0.0) + 1.5 * span.max(0.25 * zmax.abs()))
}

/// The smallest of 1, 2, 2.5, 5 times a power of ten at or above `v > 0`.
fn nice_ceil(v: f64) -> f64 {
    if !(v > 0.0 && v.is_finite()) {
        return 1.0;
    }
    let p = 10f64.powf(v.log10().floor());
    for m in [1.0, 2.0, 2.5, 5.0, 10.0] {
        if m * p >= v * (1.0 - 1e-12) {
            return m * p;
        }
    }
    10.0 * p
}

/// The blocks' positions over several periods with their slip states and the barycentre.
pub struct SpaceTime<'a> {
    /// The recorded motion (`t`, `positions`, `barycentre`, `slip`).
    pub trajectory: &'a Trajectory,
    /// The period `T` (period boundaries are marked).
    pub period: f64,
}

impl Plot for SpaceTime<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let tr = self.trajectory;
        let nb = tr.positions[0].len();
        let d = display_spacing(tr);
        let off = |b: usize| b as f64 * d;
        let t_end = *tr.t.last().unwrap_or(&1.0);
        let t0 = tr.t[0];
        let ys: Vec<f64> = tr
            .positions
            .iter()
            .flat_map(|p| p.iter().enumerate().map(|(b, x)| x + off(b)))
            .collect();
        let yr = range_of(&ys, 0.06);
        let title = format!(
            "Space-time diagram: block b drawn at X_b + (b−1)ℓ₀, ℓ₀ = {} (a display rest length)",
            fmt_num(d)
        );
        let mut c = chart(
            root,
            s,
            &title,
            (t0, t_end),
            yr,
            "time t [time]",
            "position [length]",
        )?;
        // Period boundaries.
        let periods = ((t_end - t0) / self.period).round() as usize;
        for k in 1..periods {
            let t = t0 + k as f64 * self.period;
            c.draw_series(DashedLineSeries::new(
                vec![(t, yr.0), (t, yr.1)],
                s.px(3.0),
                s.px(4.0),
                s.line(RGBColor(170, 170, 170), 1.0),
            ))?;
        }
        for b in 0..nb {
            let pts: Vec<(f64, f64)> =
                tr.t.iter()
                    .zip(&tr.positions)
                    .map(|(&t, p)| (t, p[b] + off(b)))
                    .collect();
            draw_thick(&mut c, &pts, STICK, 1.2, s)?;
            if b == 0 {
                c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                    .label("block sticks")
                    .legend(legend_line(STICK, s.px(1.5)));
            }
            // Slipping intervals: slip[i] is the state over (t[i-1], t[i]).
            for (sign, colour) in [(1i8, FORWARD), (-1i8, BACKWARD)] {
                // Maximal runs of consecutive intervals with this slip state, one polyline each.
                let mut runs: Vec<Vec<(f64, f64)>> = Vec::new();
                let mut open = false;
                for i in 1..pts.len() {
                    if tr.slip[i][b] == sign {
                        if !open {
                            runs.push(vec![pts[i - 1]]);
                            open = true;
                        }
                        if let Some(r) = runs.last_mut() {
                            r.push(pts[i]);
                        }
                    } else {
                        open = false;
                    }
                }
                for r in runs {
                    draw_thick(&mut c, &r, colour, 3.2, s)?;
                }
            }
            // At most about 20 block labels (long chains: every k-th block and the front one).
            let every = nb.div_ceil(20);
            if b % every == 0 || b == nb - 1 {
                c.draw_series(std::iter::once(Text::new(
                    format!("block {}", b + 1),
                    (t0 + 0.005 * (t_end - t0), pts[0].1 - 0.012 * (yr.1 - yr.0)),
                    s.text(12.0).pos(Pos::new(HPos::Left, VPos::Top)),
                )))?;
            }
        }
        c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
            .label("slides forward")
            .legend(legend_line(FORWARD, s.px(3.5)));
        c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
            .label("slides backward")
            .legend(legend_line(BACKWARD, s.px(3.5)));
        let mid = off(nb - 1) / 2.0;
        let bary: Vec<(f64, f64)> =
            tr.t.iter()
                .zip(&tr.barycentre)
                .map(|(&t, y)| (t, y + mid))
                .collect();
        c.draw_series(DashedLineSeries::new(
            bary,
            s.px(7.0),
            s.px(4.0),
            s.line(BLACK, 2.0),
        ))?
        .label("barycentre y(t) + (N−1)ℓ₀/2")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 22, y)], BLACK.stroke_width(2)));
        legend(&mut c, s, SeriesLabelPosition::UpperLeft)?;
        Ok(())
    }
}

/// Figure `spacetime`: `X_b(t)` over the recorded periods, slipping intervals coloured by
/// direction, barycentre overlaid.
pub fn spacetime_figure(traj: &Trajectory, period: f64) -> Result<Figure> {
    check_trajectory(traj)?;
    let periods = ((traj.t.last().unwrap_or(&0.0) - traj.t[0]) / period).round();
    render(
        "spacetime",
        format!(
            "Block positions X_b(t) over {periods} periods on the periodic orbit: blue where the block slides forward, \
             vermillion where it slides backward, grey where it sticks; dashed: the barycentre y(t)."
        ),
        FIGURE_SIZE,
        &SpaceTime {
            trajectory: traj,
            period,
        },
    )
}

fn check_trajectory(traj: &Trajectory) -> Result<()> {
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

fn fmt_num(v: f64) -> String {
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

// ---------------------------------------------------------------------------------------------
// The trajectory in C

/// Projection of C onto the link forces `(x_i, x_j)`, `i < j` (0-based): the hexagon
/// `{ a in I_1, b - a in I_2, b in -I_3 }` where `I_1`, `I_2`, `I_3` are the ranges of the summed
/// increments `-F` of the blocks `1..=i+1`, `i+2..=j+1` and `j+2..=N` (paths view of
/// `model::polytope`: the three groups move independently).
#[derive(Debug, Clone, PartialEq)]
pub struct Projection {
    /// Vertices of the polygon, counter-clockwise.
    pub vertices: Vec<(f64, f64)>,
    /// The edges of positive length among the six bounding lines (redundant faces have none).
    pub edges: Vec<Edge>,
}

/// An edge of a projection of C.
#[derive(Debug, Clone, PartialEq)]
pub struct Edge {
    /// The face: `b+` (block `b` slides forward), `b−`, or a group `1–2+`.
    pub label: String,
    /// One end.
    pub from: (f64, f64),
    /// The other end.
    pub to: (f64, f64),
    /// Unit outer normal.
    pub normal: (f64, f64),
}

fn group_label(lo: usize, hi: usize, sign: char) -> String {
    if lo == hi {
        format!("{lo}{sign}")
    } else {
        format!("{lo}–{hi}{sign}")
    }
}

/// The projection of C onto `(x_i, x_j)` (0-based links, `i < j`), with face labels: `b+` is
/// block `b` sliding forward (`F_b = mu_b^+`), `b−` backward; a group `1–2+` slides together.
pub fn projection(crawler: &Crawler, i: usize, j: usize) -> Projection {
    let (mp, mm) = (crawler.mu_forward(), crawler.mu_backward());
    let nb = crawler.blocks();
    let sum = |r: std::ops::Range<usize>| -> (f64, f64) {
        (
            -r.clone().map(|b| mp[b]).sum::<f64>(),
            r.map(|b| mm[b]).sum::<f64>(),
        )
    };
    let (lo1, hi1) = sum(0..i + 1);
    let (lo2, hi2) = sum(i + 1..j + 1);
    let (lo3, hi3) = sum(j + 1..nb);
    // Lines as (normal, offset, label): normal . (a, b) <= offset.
    let lines = [
        ((1.0, 0.0), hi1, group_label(1, i + 1, '−')),
        ((-1.0, 0.0), -lo1, group_label(1, i + 1, '+')),
        ((-1.0, 1.0), hi2, group_label(i + 2, j + 1, '−')),
        ((1.0, -1.0), -lo2, group_label(i + 2, j + 1, '+')),
        ((0.0, 1.0), -lo3, group_label(j + 2, nb, '+')),
        ((0.0, -1.0), hi3, group_label(j + 2, nb, '−')),
    ];
    let mut poly = vec![(lo1, -hi3), (hi1, -hi3), (hi1, -lo3), (lo1, -lo3)];
    for &((na, nbv), off, _) in &lines[2..4] {
        poly = clip(&poly, na, nbv, off);
    }
    let scale = hi1 - lo1 + hi3 - lo3;
    let mut edges = Vec::new();
    for ((na, nbv), off, label) in lines {
        let on: Vec<(f64, f64)> = poly
            .iter()
            .copied()
            .filter(|&(a, b)| (na * a + nbv * b - off).abs() <= 1e-9 * scale)
            .collect();
        if on.len() >= 2 {
            let (p, q) = (on[0], on[on.len() - 1]);
            if (p.0 - q.0).hypot(p.1 - q.1) > 1e-9 * scale {
                let norm = na.hypot(nbv);
                edges.push(Edge {
                    label,
                    from: p,
                    to: q,
                    normal: (na / norm, nbv / norm),
                });
            }
        }
    }
    Projection {
        vertices: poly,
        edges,
    }
}

/// Sutherland–Hodgman: the part of a convex polygon with `na a + nb b <= off`.
fn clip(poly: &[(f64, f64)], na: f64, nb: f64, off: f64) -> Vec<(f64, f64)> {
    let f = |p: (f64, f64)| na * p.0 + nb * p.1 - off;
    let mut out = Vec::new();
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let (fp, fq) = (f(p), f(q));
        if fp <= 0.0 {
            out.push(p);
        }
        if (fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0) {
            let t = fp / (fp - fq);
            out.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
        }
    }
    out
}

/// Which pairs of links a figure of C shows: the polygon for two links, every pair up to four
/// links, consecutive pairs (at most six) beyond.
pub fn projection_pairs(links: usize) -> Vec<(usize, usize)> {
    if links <= 4 {
        let mut v = Vec::new();
        for i in 0..links {
            for j in i + 1..links {
                v.push((i, j));
            }
        }
        v
    } else {
        (0..links.min(7) - 1).map(|i| (i, i + 1)).collect()
    }
}

/// C with an optional trajectory in it.
pub struct InC<'a> {
    /// The crawler.
    pub crawler: &'a Crawler,
    /// The periodic orbit (recorded periods), if any.
    pub orbit: Option<&'a Trajectory>,
    /// The approach to the orbit from rest (states), drawn thin and grey under it.
    pub transient: Option<&'a [Vec<f64>]>,
}

impl InC<'_> {
    fn draw_interval<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let (mp, mm) = (self.crawler.mu_forward(), self.crawler.mu_backward());
        let (lo, hi) = ((-mp[0]).max(-mm[1]), mm[0].min(mp[1]));
        let label_hi = if mm[0] < mp[1] { "1−" } else { "2+" };
        let label_lo = if -mp[0] > -mm[1] { "1+" } else { "2−" };
        let (t0, t1) = match self.orbit {
            Some(o) => (o.t[0], *o.t.last().unwrap_or(&1.0)),
            None => (0.0, 1.0),
        };
        let w = hi - lo;
        let mut c = chart(
            root,
            s,
            "The state x(t) in C = [α, β] (one link)",
            (t0, t1),
            (lo - 0.25 * w, hi + 0.25 * w),
            "time t [time]",
            "link compression x₁ [force]",
        )?;
        c.draw_series(std::iter::once(Rectangle::new(
            [(t0, lo), (t1, hi)],
            RGBColor(0, 114, 178).mix(0.08).filled(),
        )))?;
        for (v, label, what) in [(hi, label_hi, "β"), (lo, label_lo, "α")] {
            c.draw_series(std::iter::once(PathElement::new(
                vec![(t0, v), (t1, v)],
                s.line(BLACK, 1.6),
            )))?;
            let dy = if v == hi { 0.09 * w } else { -0.09 * w };
            c.draw_series(std::iter::once(Text::new(
                format!("face {label}:  x₁ = {what} = {}", fmt_num(v)),
                (t0 + 0.01 * (t1 - t0), v + dy),
                s.text(13.0).pos(Pos::new(HPos::Left, VPos::Center)),
            )))?;
        }
        if let Some(o) = self.orbit {
            let pts: Vec<(f64, f64)> = o.t.iter().zip(&o.x).map(|(&t, x)| (t, x[0])).collect();
            draw_thick(&mut c, &pts, ORBIT, 2.6, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label("x₁(t) on the periodic orbit")
                .legend(legend_line(ORBIT, s.px(3.0)));
            legend(&mut c, s, SeriesLabelPosition::LowerRight)?;
        }
        Ok(())
    }

    fn draw_pair<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        s: Sty,
        (i, j): (usize, usize),
        big: bool,
    ) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let p = projection(self.crawler, i, j);
        // Room around the polygon for the face labels (group labels such as 1–2+ are wide).
        let pad = if big { 0.18 } else { 0.3 };
        let xr = range_of(p.vertices.iter().map(|v| &v.0), pad);
        let yr = range_of(p.vertices.iter().map(|v| &v.1), pad);
        // Equal scales on both axes: widen the shorter range to the plot's aspect ratio.
        let (w, h) = area.dim_in_pixel();
        let (pw, ph) = (
            w as f64 - s.px(70.0 + 28.0) as f64,
            h as f64 - s.px(46.0 + 20.0 + 30.0) as f64,
        );
        let (sx, sy) = ((xr.1 - xr.0) / pw.max(1.0), (yr.1 - yr.0) / ph.max(1.0));
        let k = sx.max(sy);
        let (cx, cy) = ((xr.0 + xr.1) / 2.0, (yr.0 + yr.1) / 2.0);
        let xr = (cx - k * pw / 2.0, cx + k * pw / 2.0);
        let yr = (cy - k * ph / 2.0, cy + k * ph / 2.0);
        let title = if big {
            "The state x(t) in the polytope C (faces: block, sign)".to_string()
        } else {
            format!("C projected on (x{}, x{})", sub(i + 1), sub(j + 1))
        };
        let mut c = chart(
            area,
            s,
            &title,
            xr,
            yr,
            &format!("x{} [force]", sub(i + 1)),
            &format!("x{} [force]", sub(j + 1)),
        )?;
        let mut closed = p.vertices.clone();
        closed.push(p.vertices[0]);
        c.draw_series(std::iter::once(Polygon::new(
            p.vertices.clone(),
            RGBColor(0, 114, 178).mix(0.08).filled(),
        )))?;
        c.draw_series(std::iter::once(PathElement::new(
            closed,
            s.line(BLACK, 1.6),
        )))?;
        let gap = 0.035 * (xr.1 - xr.0);
        for e in &p.edges {
            let (label, a, b, (na, nbv)) = (&e.label, e.from, e.to, &e.normal);
            let m = ((a.0 + b.0) / 2.0, (a.1 + b.1) / 2.0);
            let h = if *na > 0.3 {
                HPos::Left
            } else if *na < -0.3 {
                HPos::Right
            } else {
                HPos::Center
            };
            let v = if *nbv > 0.3 {
                VPos::Bottom
            } else if *nbv < -0.3 {
                VPos::Top
            } else {
                VPos::Center
            };
            c.draw_series(std::iter::once(Text::new(
                label.clone(),
                (m.0 + gap * na, m.1 + gap * nbv),
                s.text_c(if big { 15.0 } else { 14.0 }, RGBColor(60, 60, 60))
                    .pos(Pos::new(h, v)),
            )))?;
        }
        // The origin (unloaded crawler).
        c.draw_series(std::iter::once(Cross::new(
            (0.0, 0.0),
            s.px(4.0),
            s.line(RGBColor(120, 120, 120), 1.0),
        )))?;
        if let Some(tr) = self.transient.filter(|t| t.len() >= 2) {
            let pts: Vec<(f64, f64)> = tr.iter().map(|x| (x[i], x[j])).collect();
            draw_thick(&mut c, &pts, RGBColor(120, 120, 120), 1.2, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label("transient from x = 0")
                .legend(legend_line(RGBColor(120, 120, 120), s.px(1.5)));
        }
        if let Some(o) = self.orbit {
            let pts: Vec<(f64, f64)> = dedup(o.x.iter().map(|x| (x[i], x[j])).collect());
            draw_thick(&mut c, &pts, ORBIT, 2.8, s)?;
            c.draw_series(std::iter::empty::<PathElement<(f64, f64)>>())?
                .label("periodic orbit")
                .legend(legend_line(ORBIT, s.px(3.0)));
            c.draw_series(std::iter::once(Circle::new(
                pts[0],
                s.px(4.5),
                ORBIT.filled(),
            )))?
            .label("x(0)")
            .legend(|(x, y)| Circle::new((x + 11, y), 4, ORBIT.filled()));
            // Direction of travel: an arrow head in the middle of the longest segment.
            let longest = pts.windows(2).map(|w| (w[0], w[1])).max_by(|a, b| {
                let la = (a.1 .0 - a.0 .0).hypot(a.1 .1 - a.0 .1);
                let lb = (b.1 .0 - b.0 .0).hypot(b.1 .1 - b.0 .1);
                la.total_cmp(&lb)
            });
            if let Some((a, b)) = longest {
                let (dx, dy) = (b.0 - a.0, b.1 - a.1);
                let len = dx.hypot(dy);
                if len > 0.0 {
                    let size = 0.035 * (xr.1 - xr.0);
                    let (ux, uy) = (dx / len, dy / len);
                    let tip = (
                        (a.0 + b.0) / 2.0 + 0.5 * size * ux,
                        (a.1 + b.1) / 2.0 + 0.5 * size * uy,
                    );
                    let l = (
                        tip.0 - size * (ux - 0.5 * uy),
                        tip.1 - size * (uy + 0.5 * ux),
                    );
                    let r = (
                        tip.0 - size * (ux + 0.5 * uy),
                        tip.1 - size * (uy - 0.5 * ux),
                    );
                    c.draw_series(std::iter::once(Polygon::new(
                        vec![tip, l, r],
                        ORBIT.filled(),
                    )))?;
                }
            }
            if big {
                legend(&mut c, s, SeriesLabelPosition::LowerRight)?;
            }
        }
        Ok(())
    }
}

impl Plot for InC<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let n = self.crawler.links();
        if n == 1 {
            return self.draw_interval(root, s);
        }
        let pairs = projection_pairs(n);
        if pairs.len() == 1 {
            return self.draw_pair(root, s, pairs[0], true);
        }
        let cols = pairs.len().min(3);
        let rows = pairs.len().div_ceil(cols);
        let areas = root.split_evenly((rows, cols));
        for (area, &pair) in areas.iter().zip(&pairs) {
            self.draw_pair(area, s, pair, false)?;
        }
        Ok(())
    }
}

/// Figure `polytope`: C (interval, polygon with labelled faces, or pairwise projections) with
/// the periodic orbit of `orbit` highlighted over the `transient` that leads to it from rest
/// (states; not drawn for one link, whose figure has time on its axis).
pub fn polytope_figure(
    crawler: &Crawler,
    orbit: Option<&Trajectory>,
    transient: Option<&[Vec<f64>]>,
) -> Result<Figure> {
    if transient.is_some_and(|t| t.iter().any(|x| x.len() != crawler.links())) {
        return Err(Error::invalid(
            "transient",
            "a state of the wrong size",
            format!("one force per link ({})", crawler.links()),
        ));
    }
    if let Some(o) = orbit {
        check_trajectory(o)?;
        if o.x[0].len() != crawler.links() {
            return Err(Error::invalid(
                "trajectory",
                format!("{} link forces", o.x[0].len()),
                format!("the crawler has {} links", crawler.links()),
            ));
        }
    }
    let n = crawler.links();
    let pairs = projection_pairs(n);
    let size = match n {
        1 | 2 => (760, 640),
        _ => {
            let cols = pairs.len().min(3) as u32;
            let rows = pairs.len().div_ceil(3) as u32;
            (cols * 380, rows * 370)
        }
    };
    let what = match n {
        1 => "the interval C = [α, β] of the link force".to_string(),
        2 => "the polygon C in the plane of the link forces (x₁, x₂)".to_string(),
        _ if n <= 4 => "the projections of C on every pair of link forces".to_string(),
        _ => format!(
            "the projections of C on consecutive pairs of link forces (the first {})",
            pairs.len()
        ),
    };
    render(
        "polytope",
        format!(
            "The admissible spring forces: {what}. A face labelled b+ (b−) is where block b slides forward \
             (backward); a range such as 1–2+ is a group of blocks sliding together.{}",
            match (orbit.is_some(), transient.is_some() && crawler.links() > 1) {
                (true, true) => {
                    " Green: the periodic orbit x(t), dot at t = 0, arrow in the direction of travel; \
                     grey: the approach to it from rest (x = 0)."
                }
                (true, false) => {
                    " Green: the periodic orbit x(t), dot at t = 0, arrow in the direction of travel."
                }
                _ => "",
            }
        ),
        size,
        &InC {
            crawler,
            orbit,
            transient,
        },
    )
}

// ---------------------------------------------------------------------------------------------
// v_m over directions (two links)

/// `v_m` on a grid of shape rates for a two-link crawler.
pub struct VmMap<'a> {
    /// The crawler (two links).
    pub crawler: &'a Crawler,
}

/// Directions `theta` in `[0, 2 pi)` of the zero set of `v_m(cos theta, sin theta)` (v_m is
/// positively homogeneous, so its zero set is a union of rays), found by sign changes on a fine
/// grid refined by bisection.
pub fn vm_zero_directions(crawler: &Crawler) -> Vec<f64> {
    let f = |th: f64| crawler.vm(&[th.cos(), th.sin()]);
    let m = 3600;
    let scale = crawler.mu_forward().iter().fold(0.0f64, |a, b| a.max(*b));
    let tol = 1e-12 * scale.max(1.0);
    let mut out: Vec<f64> = Vec::new();
    let step = std::f64::consts::TAU / m as f64;
    for k in 0..m {
        let (a, b) = (k as f64 * step, (k + 1) as f64 * step);
        let (fa, fb) = (f(a), f(b));
        if fa.abs() <= tol {
            out.push(a);
        } else if fa * fb < 0.0 {
            let (mut lo, mut hi, mut flo) = (a, b, fa);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                let fm = f(mid);
                if (fm < 0.0) == (flo < 0.0) {
                    lo = mid;
                    flo = fm;
                } else {
                    hi = mid;
                }
            }
            out.push(0.5 * (lo + hi));
        }
    }
    out
}

/// Colour steps on each side of zero in the v_m heat map.
const LEVELS: i32 = 12;

fn diverging(t: f64) -> RGBColor {
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

impl Plot for VmMap<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let (main, bar) = root.split_horizontally(root.dim_in_pixel().0 - s.px(120.0));
        let g = 120;
        let mut vmax = 0.0f64;
        let mut cells = Vec::with_capacity(g * g);
        for iy in 0..g {
            for ix in 0..g {
                let z = (
                    -1.0 + 2.0 * (ix as f64 + 0.5) / g as f64,
                    -1.0 + 2.0 * (iy as f64 + 0.5) / g as f64,
                );
                let v = self.crawler.vm(&[z.0, z.1]);
                vmax = vmax.max(v.abs());
                cells.push((ix, iy, v));
            }
        }
        let vmax = if vmax > 0.0 { vmax } else { 1.0 };
        let mut c = chart(
            &main,
            s,
            "Barycentre velocity vₘ(z′) over shape rates (two links)",
            (-1.0, 1.0),
            (-1.0, 1.0),
            "shape rate z′₁ [length/time]",
            "shape rate z′₂ [length/time]",
        )?;
        // Colours quantised to LEVELS steps, equal neighbours in a row merged into one rectangle
        // (keeps the SVG small; the colour bar shows the same steps).
        let h = 2.0 / g as f64;
        let q = |v: f64| ((v / vmax) * LEVELS as f64).round() as i32;
        let mut rects = Vec::new();
        for iy in 0..g {
            let row = &cells[iy * g..(iy + 1) * g];
            let mut start = 0;
            for ix in 1..=g {
                if ix == g || q(row[ix].2) != q(row[start].2) {
                    let level = q(row[start].2);
                    let (x0, x1) = (-1.0 + start as f64 * h, -1.0 + ix as f64 * h);
                    let y0 = -1.0 + iy as f64 * h;
                    rects.push(Rectangle::new(
                        [(x0, y0), (x1, y0 + h)],
                        diverging(level as f64 / LEVELS as f64).filled(),
                    ));
                    start = ix;
                }
            }
        }
        c.draw_series(rects)?;
        let zeros = vm_zero_directions(self.crawler);
        for (k, th) in zeros.iter().enumerate() {
            // A ray from 0 to the square's boundary.
            let (cx, cy) = (th.cos(), th.sin());
            let r = 1.0 / cx.abs().max(cy.abs());
            let series = c.draw_series(std::iter::once(PathElement::new(
                vec![(0.0, 0.0), (r * cx, r * cy)],
                s.line(BLACK, 2.0),
            )))?;
            if k == 0 {
                series
                    .label("zero set vₘ = 0")
                    .legend(legend_line(BLACK, s.px(2.0)));
            }
        }
        legend(&mut c, s, SeriesLabelPosition::UpperLeft)?;
        let mut cb = colour_bar(&bar, s, vmax, "vₘ [length/time]")?;
        let steps = 2 * LEVELS + 1;
        cb.draw_series((0..steps).map(|k| {
            let level = k as f64 - LEVELS as f64;
            let a = vmax * (level - 0.5) / LEVELS as f64;
            let b = vmax * (level + 0.5) / LEVELS as f64;
            Rectangle::new(
                [(0.0, a.max(-vmax)), (1.0, b.min(vmax))],
                diverging(level / LEVELS as f64).filled(),
            )
        }))?;
        cb.draw_series(std::iter::once(Rectangle::new(
            [(0.0, -vmax), (1.0, vmax)],
            s.line(BLACK, 1.0),
        )))?;
        Ok(())
    }
}

/// Figure `vm`: the heat map of `v_m` over shape rates for a two-link crawler, with its zero
/// set (for mild anisotropy the six rays of Remark 3.3's monkey saddle).
pub fn vm_figure(crawler: &Crawler) -> Result<Figure> {
    if crawler.links() != 2 {
        return Err(Error::invalid(
            "crawler.blocks",
            crawler.blocks(),
            "the v_m heat map is drawn for two links (three blocks) only",
        ));
    }
    crawler.require_unique()?;
    let rays = vm_zero_directions(crawler).len();
    render(
        "vm",
        format!(
            "The displacement function vₘ(z′) for shape rates z′ = (z′₁, z′₂): blue moves the crawler forward, \
             vermillion backward. vₘ is positively homogeneous, so its zero set is {rays} ray(s) from the origin{}.",
            if rays >= 6 {
                " (a monkey saddle, paper Remark 3.3)"
            } else {
                ""
            }
        ),
        (762, 640),
        &VmMap { crawler },
    )
}

// ---------------------------------------------------------------------------------------------
// J_m against m

/// Optimal values of the discrete problems P_m against m, with the continuous-time value.
pub struct JmSeries<'a> {
    /// The `m` values.
    pub m: &'a [u32],
    /// `J_m`.
    pub values: &'a [f64],
    /// The continuous-time optimum (or the best phase gait), drawn as a line.
    pub continuous: Option<f64>,
}

impl Plot for JmSeries<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let ms: Vec<f64> = self.m.iter().map(|&m| m as f64).collect();
        let lo = ms.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = ms.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let xr = (lo - 0.5, hi + 0.5);
        let mut ys = self.values.to_vec();
        ys.extend(self.continuous);
        let yr = range_of(&ys, 0.15);
        let mut c = chart_x(
            root,
            s,
            "Convergence of the discrete optima Jₘ",
            xr,
            yr,
            "m  (Pₘ has 2^m steps per period)",
            "optimal value J [length]",
            true,
        )?;
        if let Some(v) = self.continuous {
            c.draw_series(DashedLineSeries::new(
                vec![(xr.0, v), (xr.1, v)],
                s.px(8.0),
                s.px(5.0),
                s.line(BLACK, 1.6),
            ))?
            .label("continuous time")
            .legend(legend_line(BLACK, s.px(1.6)));
        }
        let pts: Vec<(f64, f64)> = ms
            .iter()
            .copied()
            .zip(self.values.iter().copied())
            .collect();
        c.draw_series(LineSeries::new(pts.clone(), s.line(FORWARD, 2.0)))?
            .label("Jₘ (global optimum of Pₘ)")
            .legend(legend_line(FORWARD, s.px(2.0)));
        c.draw_series(
            pts.iter()
                .map(|&p| Circle::new(p, s.px(5.0), FORWARD.filled())),
        )?;
        legend(&mut c, s, SeriesLabelPosition::LowerRight)?;
        Ok(())
    }
}

/// Figure `jm`: `J_m` against `m` with the continuous-time value as a line.
pub fn jm_figure(m: &[u32], values: &[f64], continuous: Option<f64>) -> Result<Figure> {
    if m.is_empty() || m.len() != values.len() {
        return Err(Error::invalid(
            "J_m table",
            format!("{} m values, {} J values", m.len(), values.len()),
            "needs one J value per m, at least one",
        ));
    }
    if values.iter().chain(&continuous).any(|v| !v.is_finite()) {
        return Err(Error::invalid(
            "J_m table",
            "a non-finite value",
            "needs finite values",
        ));
    }
    render(
        "jm",
        "Optimal values Jₘ of the discrete problems Pₘ (2^m steps) against m; dashed: the continuous-time value."
            .into(),
        (780, 520),
        &JmSeries {
            m,
            values,
            continuous,
        },
    )
}

// ---------------------------------------------------------------------------------------------
// Adjoint of a certificate

/// The adjoint state of the necessary conditions (theory §8) with the control it selects.
pub struct AdjointSeries<'a> {
    /// Sample times.
    pub t: &'a [f64],
    /// `p(t)`, one row per sample.
    pub p: &'a [Vec<f64>],
    /// `p(t) + omega`, one row per sample.
    pub p_plus_omega: &'a [Vec<f64>],
    /// `u(t)`, one row per sample.
    pub u: &'a [Vec<f64>],
}

impl Plot for AdjointSeries<'_> {
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>, s: Sty) -> DrawResult
    where
        DB::ErrorType: 'static,
    {
        let n = self.p[0].len();
        let tr = (self.t[0], *self.t.last().unwrap_or(&1.0));
        let (top, bottom) = root.split_vertically(root.dim_in_pixel().1 / 2);
        let mut all: Vec<f64> = self.p.iter().flatten().copied().collect();
        all.extend(self.p_plus_omega.iter().flatten());
        all.push(0.0);
        let mut c = chart(
            &top,
            s,
            "Adjoint p(t) and switching function p(t) + ω",
            tr,
            range_of(&all, 0.1),
            "time t [time]",
            "adjoint [length/force]",
        )?;
        c.draw_series(std::iter::once(PathElement::new(
            vec![(tr.0, 0.0), (tr.1, 0.0)],
            s.line(RGBColor(150, 150, 150), 1.0),
        )))?;
        for l in 0..n {
            let col = link_colour(l);
            let p: Vec<(f64, f64)> = self.t.iter().zip(self.p).map(|(&t, r)| (t, r[l])).collect();
            c.draw_series(LineSeries::new(p, s.line(col, 2.0)))?
                .label(format!("p{}(t)", sub(l + 1)))
                .legend(legend_line(col, s.px(2.0)));
            let q: Vec<(f64, f64)> = self
                .t
                .iter()
                .zip(self.p_plus_omega)
                .map(|(&t, r)| (t, r[l]))
                .collect();
            c.draw_series(DashedLineSeries::new(
                q,
                s.px(7.0),
                s.px(4.0),
                s.line(col, 2.0),
            ))?
            .label(format!("p{0}(t) + ω{0}", sub(l + 1)))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 9, y)], col.stroke_width(2)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        let mut c = chart(
            &bottom,
            s,
            "Control u(t) (bang-bang: u = −a sign(p + ω))",
            tr,
            range_of(self.u.iter().flatten(), 0.15),
            "time t [time]",
            "rate u [force/time]",
        )?;
        for l in 0..n {
            let col = link_colour(l);
            let u: Vec<(f64, f64)> = self.t.iter().zip(self.u).map(|(&t, r)| (t, r[l])).collect();
            c.draw_series(LineSeries::new(u, s.line(col, 2.2)))?
                .label(format!("u{}(t)", sub(l + 1)))
                .legend(legend_line(col, s.px(2.2)));
        }
        legend(&mut c, s, SeriesLabelPosition::UpperRight)?;
        Ok(())
    }
}

/// Figure `adjoint`: `p(t)`, `p(t) + omega` and `u(t)` of a certificate (plain arrays, one row
/// per sample; draw jumps as two samples at the same time).
pub fn adjoint_figure(
    t: &[f64],
    p: &[Vec<f64>],
    p_plus_omega: &[Vec<f64>],
    u: &[Vec<f64>],
) -> Result<Figure> {
    let n = p.first().map_or(0, Vec::len);
    let ok = t.len() >= 2
        && n > 0
        && [p.len(), p_plus_omega.len(), u.len()]
            .iter()
            .all(|&l| l == t.len())
        && p.iter()
            .chain(p_plus_omega)
            .chain(u)
            .all(|r| r.len() == n && r.iter().all(|v| v.is_finite()))
        && t.iter().all(|v| v.is_finite());
    if !ok {
        return Err(Error::invalid(
            "adjoint",
            format!("{} times", t.len()),
            "needs at least two samples and, per sample, one finite value per link in p, p + omega and u",
        ));
    }
    render(
        "adjoint",
        "The adjoint p(t) (solid) and p(t) + ω (dashed) of the necessary conditions, with the control u(t) they select."
            .into(),
        (FIGURE_SIZE.0, 640),
        &AdjointSeries {
            t,
            p,
            p_plus_omega,
            u,
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn png_size(png: &[u8]) -> (u32, u32, usize) {
        let dec = png::Decoder::new(png);
        let mut reader = dec.read_info().expect("a valid PNG");
        let mut buf = vec![0; reader.output_buffer_size()];
        let info = reader.next_frame(&mut buf).expect("a frame");
        let ink = buf[..info.buffer_size()]
            .chunks(3)
            .filter(|p| p.iter().any(|&c| c < 200))
            .count();
        (info.width, info.height, ink)
    }

    fn check_figure(f: &Figure, size: (u32, u32), texts: &[&str]) {
        assert!(f.svg.contains("<svg"), "{}", &f.svg[..100]);
        assert!(f.svg.contains(&format!("width=\"{}\"", size.0)));
        assert!(f.svg.contains(FONT), "the SVG names the embedded font");
        for t in texts {
            assert!(f.svg.contains(t), "{}: missing {t:?}", f.name);
        }
        let (w, h, ink) = png_size(&f.png);
        assert_eq!((w, h), (2 * size.0, 2 * size.1));
        // Text and lines drawn: a blank or text-less bitmap would have far fewer dark pixels.
        assert!(ink > 20_000, "{}: only {ink} dark pixels", f.name);
    }

    #[test]
    fn the_two_link_polygon_is_c_with_its_six_faces_labelled() {
        let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
        let p = projection(&c, 0, 1);
        assert_eq!(p.vertices.len(), 6);
        for v in &p.vertices {
            let (viol, _) = c.violation(&[v.0, v.1]);
            assert!(viol <= 1e-12, "vertex {v:?} outside C");
        }
        let mut labels: Vec<&str> = p.edges.iter().map(|e| e.label.as_str()).collect();
        labels.sort();
        assert_eq!(labels, ["1+", "1−", "2+", "2−", "3+", "3−"]);
        // Face 1− is x_1 = mu_1^- = 1.5.
        let e = p.edges.iter().find(|e| e.label == "1−").unwrap();
        assert_eq!((e.from.0, e.to.0), (1.5, 1.5));
    }

    #[test]
    fn redundant_faces_get_no_label() {
        // mu_2^+ = 10 exceeds the other blocks' mu^- sum: face 2+ is not a facet.
        let c = Crawler::new(vec![1.0, 1.0], vec![1.0, 10.0, 1.0], vec![1.5, 1.5, 1.5]).unwrap();
        let p = projection(&c, 0, 1);
        assert!(p.edges.iter().all(|e| e.label != "2+"), "{:?}", p.edges);
        assert_eq!(p.edges.len(), 5);
    }

    #[test]
    fn projection_pairs_cover_all_pairs_up_to_four_links() {
        assert_eq!(projection_pairs(2), vec![(0, 1)]);
        assert_eq!(projection_pairs(3).len(), 3);
        assert_eq!(projection_pairs(4).len(), 6);
        assert_eq!(
            projection_pairs(9),
            (0..6).map(|i| (i, i + 1)).collect::<Vec<_>>()
        );
    }

    #[test]
    fn the_monkey_saddle_has_six_zero_rays_and_the_convex_class_none() {
        // Remark 3.3, N = 3, equal friction: mild anisotropy -> neither (monkey saddle).
        let mild = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
        assert_eq!(vm_zero_directions(&mild).len(), 6);
        // mu- > 2 mu+: convex and positive off 0.
        let convex = Crawler::uniform(3, 1.0, 1.0, 2.5).unwrap();
        assert_eq!(vm_zero_directions(&convex).len(), 0);
        let f = vm_figure(&mild).unwrap();
        check_figure(
            &f,
            (762, 640),
            &[
                "shape rate z′₁ [length/time]",
                "vₘ [length/time]",
                "zero set",
            ],
        );
        assert!(f.caption.contains("6 ray(s)") && f.caption.contains("monkey saddle"));
        assert!(
            f.svg.len() < 600_000,
            "heat map SVG of {} bytes",
            f.svg.len()
        );
        assert!(vm_figure(&Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap()).is_err());
    }

    #[test]
    fn the_polytope_figure_labels_axes_and_faces() {
        let c = Crawler::uniform(3, 1.0, 1.0, 1.5).unwrap();
        let f = polytope_figure(&c, None, None).unwrap();
        check_figure(
            &f,
            (760, 640),
            &["x₁ [force]", "x₂ [force]", "\n1+\n", "\n3−\n", "\n2+\n"],
        );
        let c4 = Crawler::uniform(4, 1.0, 1.0, 3.3).unwrap();
        let f = polytope_figure(&c4, None, None).unwrap();
        check_figure(&f, (1140, 370), &["C projected on (x₁, x₃)", "x₃ [force]"]);
        let c1 = Crawler::uniform(2, 1.0, 1.0, 2.0).unwrap();
        let f = polytope_figure(&c1, None, None).unwrap();
        check_figure(
            &f,
            (760, 640),
            &["face 2+", "face 1+", "link compression x₁ [force]"],
        );
    }

    #[test]
    fn the_actuation_figure_shows_lengths_rates_and_bounds() {
        let a = ActuationSeries::from_knots(
            &[0.0, 5.0, 5.0, 10.0],
            &[vec![0.0], vec![5.0], vec![5.0], vec![0.0]],
            &[2.0],
            Some(vec![2.0]),
        )
        .unwrap();
        // The zero-length piece is dropped; u = k L'.
        assert_eq!(a.controls, vec![vec![2.0], vec![-2.0]]);
        let f = actuation_figure(&a).unwrap();
        check_figure(
            &f,
            (900, 640),
            &[
                "actuator length L [length]",
                "rate u [force/time]",
                "time t [time]",
                "L₁(t)",
                "±a",
            ],
        );
        assert!(ActuationSeries::from_knots(&[0.0], &[vec![0.0]], &[1.0], None).is_err());
    }

    fn synthetic_trajectory() -> Trajectory {
        // Two blocks, one period of length 2 played twice: block 2 slides forward, then block 1.
        let mut tr = Trajectory::default();
        let pts = [
            (0.0, [0.0, 1.0], [0, 0]),
            (0.5, [0.0, 2.0], [0, 1]),
            (1.0, [0.0, 2.0], [0, 0]),
            (1.5, [1.0, 2.0], [1, 0]),
            (2.0, [1.0, 2.0], [0, 0]),
            (2.5, [1.0, 3.0], [0, 1]),
            (3.0, [1.0, 3.0], [0, 0]),
            (3.5, [2.0, 3.0], [1, 0]),
            (4.0, [2.0, 3.0], [0, 0]),
        ];
        for (t, x, s) in pts {
            tr.t.push(t);
            tr.positions.push(x.to_vec());
            tr.barycentre.push((x[0] + x[1]) / 2.0);
            tr.x.push(vec![0.0]);
            tr.slip.push(s.to_vec());
        }
        tr
    }

    #[test]
    fn the_spacetime_figure_colours_slips_and_overlays_the_barycentre() {
        let tr = synthetic_trajectory();
        let f = spacetime_figure(&tr, 2.0).unwrap();
        check_figure(
            &f,
            FIGURE_SIZE,
            &[
                "time t [time]",
                "position [length]",
                "barycentre y(t)",
                "block 2",
            ],
        );
        assert!(f.svg.contains("#0072B2"), "forward slips in blue");
        assert!(f.caption.contains("2 periods"));
        let mut bad = tr;
        bad.slip.pop();
        assert!(spacetime_figure(&bad, 2.0).is_err());
    }

    #[test]
    fn the_jm_and_adjoint_figures_take_plain_arrays() {
        let f = jm_figure(&[1, 2, 3, 4], &[2.0, 2.5, 2.8, 2.95], Some(3.0)).unwrap();
        check_figure(
            &f,
            (780, 520),
            &["continuous time", "optimal value J [length]"],
        );
        assert!(jm_figure(&[1, 2], &[1.0], None).is_err());
        assert!(jm_figure(&[1], &[f64::NAN], None).is_err());

        let t: Vec<f64> = (0..=100).map(|i| i as f64 / 10.0).collect();
        let p: Vec<Vec<f64>> = t.iter().map(|&t| vec![(t / 10.0 * 6.3).sin()]).collect();
        let q: Vec<Vec<f64>> = p.iter().map(|r| vec![r[0] - 0.1]).collect();
        let u: Vec<Vec<f64>> = q.iter().map(|r| vec![-r[0].signum()]).collect();
        let f = adjoint_figure(&t, &p, &q, &u).unwrap();
        check_figure(
            &f,
            (900, 640),
            &["p₁(t)", "p₁(t) + ω₁", "u₁(t)", "adjoint [length/force]"],
        );
        assert!(adjoint_figure(&t, &p[..50], &q, &u).is_err());
    }

    #[test]
    fn ticks_are_short_and_never_negative_zero() {
        assert_eq!(tick(-1e-17, 1.0), "0");
        assert_eq!(tick(2.0, 10.0), "2");
        assert_eq!(tick(-0.25, 2.0), "−0.25");
        assert_eq!(nice_ceil(7.3), 10.0);
        assert_eq!(nice_ceil(0.21), 0.25);
    }
}
