//! A rotation drawn: the fixed basis {Eᵢ}, the rotated basis {R Eᵢ} and the axis of R
//! in an oblique 3D view.

use crate::plot::{with_png, FONT, PALETTE};
use crate::{err, Result};
use plotters::prelude::*;
use rotations::{AxisAngle, Rotation3, Vector3};
use std::path::Path;

/// Plotters' 3D coordinates of a vector: its y axis is vertical.
fn view(v: &Vector3<f64>) -> (f64, f64, f64) {
    (v.x, v.z, -v.y)
}

/// An oblique 3D view of {Eᵢ} and {R Eᵢ} and the axis of R.
///
/// # Errors
/// When the PNG cannot be written.
pub fn draw_basis(path: &Path, r: &Rotation3<f64>) -> Result<()> {
    let axis = AxisAngle::from_rotation(r).axis.into_inner();
    with_png(path, (640, 560), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Rotated basis eᵢ = R Eᵢ (grey: Eᵢ; components on Eᵢ, unit vectors)",
                (FONT, 18),
            )
            .margin(10)
            .build_cartesian_3d(-1.1..1.1, -1.1..1.1, -1.1..1.1)
            .map_err(err)?;
        chart.with_projection(|mut p| {
            p.yaw = 0.6;
            p.pitch = 0.35;
            p.scale = 0.85;
            p.into_matrix()
        });
        chart
            .configure_axes()
            .label_style((FONT, 12))
            .draw()
            .map_err(err)?;
        let names = ["1", "2", "3"];
        for (i, name) in names.iter().enumerate() {
            let mut e = Vector3::zeros();
            e[i] = 1.0;
            let re = r * e;
            // plotters' 3D y axis is vertical: map (x, y, z) -> (x, z, -y), a proper rotation
            // (a swap of y and z would mirror the picture).
            let fixed = [(0.0, 0.0, 0.0), view(&e)];
            let moved = [(0.0, 0.0, 0.0), view(&re)];
            chart
                .draw_series(LineSeries::new(
                    fixed,
                    RGBColor(150, 150, 150).stroke_width(2),
                ))
                .map_err(err)?;
            chart
                .draw_series(LineSeries::new(moved, PALETTE[i].stroke_width(3)))
                .map_err(err)?
                .label(format!("e{name}"))
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 18, y)], PALETTE[i].stroke_width(3))
                });
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("E{name}"),
                    view(&e),
                    (FONT, 16),
                )))
                .map_err(err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("e{name}"),
                    view(&re),
                    (FONT, 16).into_font().color(&PALETTE[i]),
                )))
                .map_err(err)?;
        }
        let ends = [view(&-axis), view(&axis)];
        chart
            .draw_series(LineSeries::new(ends, BLACK.stroke_width(1)))
            .map_err(err)?
            .label("axis s")
            .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], BLACK));
        chart
            .configure_series_labels()
            .label_font((FONT, 14))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        Ok(())
    })
}
