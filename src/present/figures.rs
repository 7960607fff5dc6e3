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

mod actuation;
mod adjoint;
pub mod fit;
mod general;
mod jm;
mod kit;
mod panel;
mod polytope;
mod spacetime;
pub mod sweep;
mod vm;

pub use actuation::{actuation_figure, ActuationSeries};
pub use adjoint::{adjoint_figure, AdjointSeries};
pub use general::{
    general_polytope_figure, time_series_figure, IntervalEndData, SeriesLine, StatePanel,
    StateSpace, TimeSeries,
};
pub use jm::{convergence_figure, jm_figure, JmSeries};
pub use kit::{sub, Figure, BACKWARD, FIGURE_SIZE, FONT, FORWARD, PNG_SCALE};
// The kit for the figures' modules (`super::chart`, ...).
use kit::*;
pub use panel::{Edge, Projection};
pub use polytope::{polytope_figure, projection, projection_pairs, InC};
pub use spacetime::{display_spacing, spacetime_figure, SpaceTime};
pub use vm::{vm_figure, vm_zero_directions, VmMap};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrate::Trajectory;
    use crate::model::Crawler;
    use spacetime::nice_ceil;

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
