//! The report's charts, drawn with `plotters` as SVG: text is left to the
//! browser's fonts, so no font files or system libraries are needed. This
//! module holds what several figures share: the canvas, the method
//! colours, grouped bars (Fig. 4 and 5 and their avatar counterpart) and
//! the colour scale's legend.

use super::colour_map::{SCALE_MAX_MM, error_colour};
use plotters::coord::Shift;
use plotters::prelude::*;

/// What drawing a chart can fail with.
pub type ChartResult<T> = Result<T, Box<dyn std::error::Error>>;

/// A drawing area on an SVG canvas.
pub type Area<'a> = DrawingArea<SVGBackend<'a>, Shift>;

/// The font of every chart (the browser's sans-serif).
pub const FONT: &str = "sans-serif";

/// The colours of the four methods of Fig. 4 and 5, as the paper draws
/// the first three (DT blue, EBFR orange, the paper's fit green) and the
/// product's method purple.
pub const DT: RGBColor = RGBColor(31, 119, 180);
/// EBFR (see [`DT`]).
pub const EBFR: RGBColor = RGBColor(255, 127, 14);
/// The paper's fit (see [`DT`]).
pub const PAPER: RGBColor = RGBColor(44, 160, 44);
/// The product's method (see [`DT`]).
pub const PRODUCT: RGBColor = RGBColor(148, 103, 189);
/// Red, for the true peak and other marks.
pub const MARK: RGBColor = RGBColor(214, 39, 40);
/// Grey, for grid-like marks.
pub const GREY: RGBColor = RGBColor(140, 140, 140);

/// A `width × height` SVG on a white background, drawn by `draw`.
pub fn svg(
    width: u32,
    height: u32,
    draw: impl FnOnce(&Area<'_>) -> ChartResult<()>,
) -> ChartResult<String> {
    let mut text = String::new();
    {
        let root = SVGBackend::with_string(&mut text, (width, height)).into_drawing_area();
        root.fill(&WHITE)?;
        draw(&root)?;
        root.present()?;
    }
    Ok(text)
}

/// The legend of `chart`'s labelled series, in the report's style: a
/// light box with a grey border at `position`.
pub fn legend<'b, CT: plotters::coord::CoordTranslate>(
    chart: &mut ChartContext<'b, SVGBackend<'b>, CT>,
    position: SeriesLabelPosition,
) -> ChartResult<()> {
    chart
        .configure_series_labels()
        .position(position)
        .background_style(WHITE.mix(0.9))
        .border_style(GREY)
        .label_font((FONT, 15))
        .draw()?;
    Ok(())
}

/// One series of a grouped bar chart: its name, colour and one value per
/// category.
pub struct Bars<'a> {
    /// The legend's name.
    pub name: &'a str,
    /// The bars' colour.
    pub colour: RGBColor,
    /// One value per category.
    pub values: &'a [f64],
}

/// Grouped bars: for each category (numbered 1… on the x axis) one bar
/// per series, side by side; `y_desc` names the axis.
pub fn grouped_bars(
    width: u32,
    height: u32,
    y_desc: &str,
    x_desc: &str,
    series: &[Bars<'_>],
) -> ChartResult<String> {
    let categories = series.iter().map(|s| s.values.len()).max().unwrap_or(0);
    let top = series
        .iter()
        .flat_map(|s| s.values.iter().copied())
        .filter(|v| v.is_finite())
        .fold(0.0f64, f64::max);
    svg(width, height, |root| {
        let mut chart = ChartBuilder::on(root)
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(56)
            .build_cartesian_2d(0.5..categories as f64 + 0.5, 0.0..top * LEGEND_ROOM + 1e-9)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .bold_line_style(RULE)
            .light_line_style(WHITE)
            .x_labels(categories + 1)
            .x_label_formatter(&|x| integer_label(*x))
            .x_desc(x_desc)
            .y_desc(y_desc)
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 16))
            .draw()?;
        let width = 0.8 / series.len().max(1) as f64;
        for (s, bars) in series.iter().enumerate() {
            let colour = bars.colour;
            chart
                .draw_series(bars.values.iter().enumerate().map(|(i, v)| {
                    let left = i as f64 + 1.0 - 0.4 + s as f64 * width;
                    Rectangle::new([(left, 0.0), (left + width, *v)], colour.filled())
                }))?
                .label(bars.name)
                .legend(move |(x, y)| {
                    Rectangle::new([(x, y - 5), (x + 12, y + 5)], colour.filled())
                });
        }
        legend(&mut chart, SeriesLabelPosition::UpperRight)?;
        Ok(())
    })
}

/// The y range of bar charts over their tallest bar: the top third of the
/// plot is left for the legend.
const LEGEND_ROOM: f64 = 1.6;

/// The colour of grid lines.
pub const RULE: RGBColor = RGBColor(225, 225, 225);

/// `x` as an integer when it is one (axis ticks of numbered categories),
/// else nothing.
fn integer_label(x: f64) -> String {
    if (x - x.round()).abs() < 1e-6 && x >= 1.0 {
        format!("{}", x.round() as i64)
    } else {
        String::new()
    }
}

/// The colour scale of every error map: 0 to [`SCALE_MAX_MM`] mm, the
/// last tick reading "≥ 5".
pub fn colour_bar(width: u32, height: u32) -> ChartResult<String> {
    svg(width, height, |root| {
        let mut chart = ChartBuilder::on(root)
            .margin_left(16)
            .margin_right(24)
            .margin_top(6)
            .x_label_area_size(34)
            .build_cartesian_2d(0.0..SCALE_MAX_MM, 0.0..1.0)?;
        let steps = 100;
        chart.draw_series((0..steps).map(|i| {
            let a = SCALE_MAX_MM * i as f64 / steps as f64;
            let b = SCALE_MAX_MM * (i + 1) as f64 / steps as f64;
            // The first strip shows 0 mm, the last 5 mm, exactly.
            let [r, g, bl] = error_colour(SCALE_MAX_MM * i as f64 / (steps - 1) as f64);
            Rectangle::new([(a, 0.0), (b, 1.0)], RGBColor(r, g, bl).filled())
        }))?;
        chart
            .configure_mesh()
            .disable_mesh()
            .disable_y_axis()
            .x_labels(6)
            .x_label_formatter(&|x| {
                if (*x - SCALE_MAX_MM).abs() < 1e-9 {
                    format!("≥ {SCALE_MAX_MM}")
                } else {
                    format!("{x}")
                }
            })
            .x_desc("error (mm)")
            .label_style((FONT, 15))
            .axis_desc_style((FONT, 16))
            .draw()?;
        Ok(())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bars_and_the_colour_bar_are_svg_of_the_stated_size() {
        let a = [1.0, 2.0, 0.5];
        let b = [0.7, 1.1, 0.2];
        let text = grouped_bars(
            400,
            200,
            "RMSE (mm)",
            "test",
            &[
                Bars {
                    name: "dt",
                    colour: DT,
                    values: &a,
                },
                Bars {
                    name: "ebfr",
                    colour: EBFR,
                    values: &b,
                },
            ],
        )
        .unwrap();
        assert!(text.contains(r#"width="400""#) && text.contains(r#"height="200""#));
        assert!(text.contains("ebfr") && text.contains("RMSE (mm)"));
        let bar = colour_bar(300, 60).unwrap();
        assert!(bar.contains("≥ 5"), "{bar}");
        assert!(
            bar.contains("#FF0000") || bar.contains("#ff0000"),
            "red end"
        );
    }

    #[test]
    fn integer_ticks_only() {
        assert_eq!(integer_label(3.0), "3");
        assert_eq!(integer_label(2.5), "");
        assert_eq!(integer_label(0.0), "");
    }
}
