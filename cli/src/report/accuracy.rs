//! "Accuracy", as the paper's §4.1: each test expression's RMSE (Eq. 5)
//! and maximum error for DT, EBFR, the paper's fit and the product's
//! method (Fig. 4 and 5), the means and ratios that `likeness evaluate`
//! prints, and the λ curve with the chosen λ marked. Every number comes
//! from the evaluation (`crate::personalize::evaluate_session` and
//! `crate::evaluate::EvaluationReport`, what `likeness evaluate --json`
//! prints).

use super::charts::{self, Bars, ChartResult, DT, EBFR, FONT, MARK, PAPER, PRODUCT};
use super::html::{self, Section, escape, number_cell};
use super::output::Files;
use crate::evaluate::{CurvePoint, EvaluationReport};
use crate::personalize::{MethodRun, SessionEvaluation};
use likeness::personalize::Method;
use plotters::prelude::*;
use std::fmt::Write;

/// The size of Fig. 4 and 5.
pub const BARS_SIZE: (u32, u32) = (1100, 340);

/// The size of the λ curve.
pub const LAMBDA_SIZE: (u32, u32) = (1100, 340);

/// The methods of Fig. 4 and 5 and their colours: the paper's three and
/// the product's.
pub fn compared_methods() -> Vec<(Method, RGBColor)> {
    let mut out = vec![
        (Method::Dt, DT),
        (Method::Ebfr, EBFR),
        (Method::Paper, PAPER),
    ];
    if !out.iter().any(|(m, _)| *m == Method::DEFAULT) {
        out.push((Method::DEFAULT, PRODUCT));
    }
    out
}

/// The run of `method`.
pub fn run(evaluation: &SessionEvaluation, method: Method) -> Option<&MethodRun> {
    evaluation.runs.iter().find(|r| r.method == method)
}

/// The accuracy section, from the session's evaluation and the summary
/// that `evaluate --json` prints for it (`summary`).
pub fn section(
    evaluation: &SessionEvaluation,
    summary: &EvaluationReport,
    files: &mut Files,
) -> Result<Section, Box<dyn std::error::Error>> {
    let methods = compared_methods();
    let mut body = String::new();
    let tests = run(evaluation, Method::Dt).map_or(0, |r| r.errors.len());
    let _ = write!(
        body,
        "<p>Each of the session's {tests} held-out test expressions is reconstructed from its \
         tracked weights, <i>B</i>₀ + Σ <i>w<sub>j</sub></i> <i>B<sub>j</sub></i>, and compared with the \
         recorded mesh: the RMSE over the 1,220 vertices (Eq. 5) and the largest vertex error. \
         The product's method is <b>{}</b>.</p>",
        Method::DEFAULT
    );
    for (file, key, what, figure) in [
        ("accuracy/rmse.svg", "rmse", "RMSE (mm)", "Fig. 4"),
        ("accuracy/max.svg", "max", "maximum error (mm)", "Fig. 5"),
    ] {
        let values: Vec<Vec<f64>> = methods
            .iter()
            .map(|(m, _)| {
                run(evaluation, *m).map_or(Vec::new(), |r| {
                    r.errors
                        .iter()
                        .map(|e| if key == "rmse" { e.rmse_mm } else { e.max_mm })
                        .collect()
                })
            })
            .collect();
        let names: Vec<String> = methods
            .iter()
            .map(|(m, _)| {
                if *m == Method::DEFAULT {
                    format!("{m} (product)")
                } else {
                    m.to_string()
                }
            })
            .collect();
        let series: Vec<Bars<'_>> = methods
            .iter()
            .zip(&values)
            .zip(&names)
            .map(|(((_, colour), v), name)| Bars {
                name,
                colour: *colour,
                values: v,
            })
            .collect();
        let svg = charts::grouped_bars(BARS_SIZE.0, BARS_SIZE.1, what, "test expression", &series)?;
        files.add(file, svg.into_bytes());
        body.push_str(&html::figure(
            file,
            BARS_SIZE.0,
            BARS_SIZE.1,
            what,
            &format!("{figure}: the {what} of each test expression against the recorded mesh (numbered as in the table below)."),
        ));
    }
    body.push_str("<h3>Means over the test expressions</h3>");
    body.push_str(&means_table(summary));
    body.push_str(&ratios_table(summary));
    let svg = lambda_svg(summary)?;
    files.add("accuracy/lambda.svg", svg.into_bytes());
    body.push_str("<h3>The regularization weight λ</h3>");
    body.push_str(&html::figure(
        "accuracy/lambda.svg",
        LAMBDA_SIZE.0,
        LAMBDA_SIZE.1,
        "lambda curve",
        "The paper's fit (captures only) for fixed λ: mean RMSE and maximum error against the recorded meshes \
         (solid) and the noise-free faces (dashed, simulated sessions). The red line is the λ chosen for this \
         session by generalized cross-validation on the captures (paper-cv and multi use it); λ = 1 is the paper's.",
    ));
    body.push_str(&lambda_table(summary));
    body.push_str("<h3>Each test expression</h3>");
    body.push_str(&per_expression_table(evaluation, &methods));
    Ok(Section {
        id: "accuracy",
        title: "Accuracy (§4.1)".to_string(),
        body,
    })
}

/// The table of each method's means, as `evaluate` prints it.
fn means_table(summary: &EvaluationReport) -> String {
    let rows: Vec<String> = Method::ALL
        .iter()
        .map(|m| {
            let v = summary.method(*m);
            let lambda = v.and_then(|v| v.lambda.first());
            let rule = v.and_then(|v| v.lambda_rule.as_deref()).unwrap_or("");
            format!(
                "<tr data-method=\"{m}\"><td>{m}{}</td>{}{}{}{}<td class=\"num\">{}</td></tr>",
                if *m == Method::DEFAULT {
                    " (product)"
                } else {
                    ""
                },
                number_cell("rmse_mm", v.map(|v| v.rmse_mm), 3),
                number_cell("max_mm", v.map(|v| v.max_mm), 3),
                number_cell("truth_rmse_mm", v.and_then(|v| v.truth_rmse_mm), 3),
                number_cell("truth_max_mm", v.and_then(|v| v.truth_max_mm), 3),
                lambda.map_or("–".to_string(), |l| format!("{l:.2e} ({rule})")),
            )
        })
        .collect();
    html::table(
        "means",
        &[
            "method",
            "RMSE mm",
            "max mm",
            "truth RMSE mm",
            "truth max mm",
            "λ",
        ],
        &rows,
    )
}

/// The ratios of the paper's §4.1 (the paper reports RMSE 0.58 of EBFR's
/// and 0.45 of DT's, maximum 0.50 and 0.38), in the paper's order.
fn ratios_table(summary: &EvaluationReport) -> String {
    let rows: Vec<String> = summary
        .ratios
        .rows()
        .iter()
        .map(|(key, words, value)| {
            format!(
                "<tr data-ratio=\"{}\"><td>{}</td>{}</tr>",
                escape(key),
                escape(words),
                number_cell(key, value.is_finite().then_some(*value), 3)
            )
        })
        .collect();
    format!(
        "<p>Ratios of the means (the paper reports for its fit: RMSE 0.58 of EBFR's and 0.45 of DT's; maximum 0.50 and 0.38):</p>{}",
        html::table("ratios", &["ratio", "value"], &rows)
    )
}

/// The λ study as a table.
fn lambda_table(summary: &EvaluationReport) -> String {
    let rows: Vec<String> = summary
        .lambda_curve
        .iter()
        .map(|p| {
            let lambda = p.lambda;
            format!(
                "<tr data-lambda=\"{lambda}\"><td class=\"num\">{lambda:e}</td>{}{}{}{}</tr>",
                number_cell("rmse_mm", p.rmse_mm, 3),
                number_cell("max_mm", p.max_mm, 3),
                number_cell("truth_rmse_mm", p.truth_rmse_mm, 3),
                number_cell("truth_max_mm", p.truth_max_mm, 3),
            )
        })
        .collect();
    html::table(
        "lambda-curve",
        &["λ", "RMSE mm", "max mm", "truth RMSE mm", "truth max mm"],
        &rows,
    )
}

/// Each test expression's errors under each compared method.
fn per_expression_table(evaluation: &SessionEvaluation, methods: &[(Method, RGBColor)]) -> String {
    let runs: Vec<&MethodRun> = methods
        .iter()
        .filter_map(|(m, _)| run(evaluation, *m))
        .collect();
    let Some(first) = runs.first() else {
        return String::new();
    };
    let rows: Vec<String> = (0..first.errors.len())
        .map(|k| {
            let mut row = format!(
                "<tr data-test=\"{}\"><td class=\"num\">{}</td><td>{}</td>",
                escape(&first.errors[k].id),
                k + 1,
                escape(&first.errors[k].id)
            );
            for r in &runs {
                row.push_str(&number_cell(
                    &format!("{}_rmse_mm", r.method),
                    Some(r.errors[k].rmse_mm),
                    3,
                ));
            }
            for r in &runs {
                row.push_str(&number_cell(
                    &format!("{}_max_mm", r.method),
                    Some(r.errors[k].max_mm),
                    3,
                ));
            }
            row + "</tr>"
        })
        .collect();
    let mut header = vec!["#".to_string(), "test".to_string()];
    header.extend(runs.iter().map(|r| format!("RMSE {}", r.method)));
    header.extend(runs.iter().map(|r| format!("max {}", r.method)));
    let header: Vec<&str> = header.iter().map(String::as_str).collect();
    html::table("per-expression", &header, &rows)
}

/// The λ curve: RMSE (left) and maximum error (right) against λ on a log
/// axis, recorded and true, with the chosen λ.
fn lambda_svg(summary: &EvaluationReport) -> ChartResult<String> {
    let points: &[CurvePoint] = &summary.lambda_curve;
    let chosen = summary
        .method(Method::PaperCv)
        .and_then(|m| m.lambda.first().copied());
    let lambdas = points.iter().map(|p| p.lambda).chain(chosen);
    let (lo, hi) = lambdas.fold((f64::INFINITY, 0.0f64), |(lo, hi), l| {
        (lo.min(l), hi.max(l))
    });
    let (lo, hi) = if lo.is_finite() && lo > 0.0 {
        (lo / 2.0, hi * 2.0)
    } else {
        (1e-6, 1.0)
    };
    charts::svg(LAMBDA_SIZE.0, LAMBDA_SIZE.1, |root| {
        let halves = root.split_evenly((1, 2));
        type Figure = fn(&CurvePoint) -> Option<f64>;
        let panels: [(Figure, Figure, &str); 2] = [
            (|p| p.rmse_mm, |p| p.truth_rmse_mm, "mean RMSE (mm)"),
            (|p| p.max_mm, |p| p.truth_max_mm, "mean maximum error (mm)"),
        ];
        for (half, (recorded_of, truth_of, what)) in halves.iter().zip(panels) {
            let series = |f: Figure| -> Vec<(f64, f64)> {
                points
                    .iter()
                    .filter_map(|p| Some((p.lambda, f(p)?)))
                    .collect()
            };
            let (recorded, truth) = (series(recorded_of), series(truth_of));
            let top = recorded
                .iter()
                .chain(&truth)
                .map(|p| p.1)
                .fold(0.0f64, f64::max)
                * 1.15
                + 1e-9;
            let mut chart = ChartBuilder::on(half)
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(56)
                .build_cartesian_2d((lo..hi).log_scale(), 0.0..top)?;
            chart
                .configure_mesh()
                .bold_line_style(charts::RULE)
                .light_line_style(WHITE)
                .x_desc("λ")
                .y_desc(what)
                .x_label_formatter(&|x| format!("{x:.0e}"))
                .label_style((FONT, 14))
                .axis_desc_style((FONT, 16))
                .draw()?;
            chart
                .draw_series(LineSeries::new(recorded.clone(), DT.stroke_width(2)))?
                .label("recorded")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], DT.stroke_width(2)));
            chart.draw_series(recorded.iter().map(|p| Circle::new(*p, 3, DT.filled())))?;
            if !truth.is_empty() {
                chart
                    .draw_series(DashedLineSeries::new(
                        truth.clone(),
                        6,
                        4,
                        PAPER.stroke_width(2),
                    ))?
                    .label("truth")
                    .legend(|(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], PAPER.stroke_width(2))
                    });
            }
            if let Some(l) = chosen {
                chart
                    .draw_series([PathElement::new(
                        vec![(l, 0.0), (l, top)],
                        MARK.stroke_width(2),
                    )])?
                    .label(format!("chosen λ = {l:.2e}"))
                    .legend(|(x, y)| {
                        PathElement::new(vec![(x, y), (x + 16, y)], MARK.stroke_width(2))
                    });
            }
            charts::legend(&mut chart, SeriesLabelPosition::UpperLeft)?;
        }
        Ok(())
    })
}
