//! "Where the error is" (the paper's Fig. 6): for the test expressions on
//! which the product's method does worst, median and best, the recorded
//! mesh and the reconstructions of the product's method, EBFR and DT, each
//! vertex coloured by its distance from the recorded mesh
//! (`likeness::personalize::evaluation::vertex_errors_mm`) on the one
//! colour scale of the report.

use super::accuracy::run;
use super::colour_map::{SKIN, error_colour};
use super::html::{self, Section, escape};
use super::output::Files;
use super::rasterizer::{FrontView, Mesh, render};
use crate::personalize::SessionEvaluation;
use glam::DVec3;
use likeness::Session;
use likeness::personalize::Method;
use likeness::personalize::evaluation::vertex_errors_mm;
use std::fmt::Write;

/// The size of each face picture.
pub const FACE_SIZE: (u32, u32) = (260, 320);

/// A test expression shown in the figures, and why.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Pick {
    /// `worst`, `median` or `best` (by the product's RMSE).
    pub label: &'static str,
    /// Its index in the session's tests.
    pub test: usize,
}

/// The test expressions with the largest, the median and the smallest
/// RMSE of the product's method (each once).
pub fn picks(evaluation: &SessionEvaluation) -> Vec<Pick> {
    let Some(product) = run(evaluation, Method::DEFAULT) else {
        return Vec::new();
    };
    let mut order: Vec<usize> = (0..product.errors.len()).collect();
    order.sort_by(|a, b| {
        product.errors[*b]
            .rmse_mm
            .total_cmp(&product.errors[*a].rmse_mm)
    });
    let Some((&worst, &best)) = order.first().zip(order.last()) else {
        return Vec::new();
    };
    let mut out = vec![Pick {
        label: "worst",
        test: worst,
    }];
    for (label, test) in [("median", order[order.len() / 2]), ("best", best)] {
        if out.iter().all(|p| p.test != test) {
            out.push(Pick { label, test });
        }
    }
    out
}

/// The view every face picture of the session shares: the neutral scan
/// with room around it for open jaws and raised brows.
pub fn face_view(session: &Session) -> FrontView {
    let neutral: Vec<DVec3> = session.neutral.iter().map(|p| p.as_dvec3()).collect();
    FrontView::framing(&neutral, FACE_SIZE.0, FACE_SIZE.1, 0.07)
}

/// The mask `positions` rendered with one colour per vertex.
pub fn face_png(
    session: &Session,
    positions: &[DVec3],
    colours: &[[u8; 3]],
) -> Result<Vec<u8>, png::EncodingError> {
    render(
        &[Mesh {
            positions,
            triangles: session.topology.triangles(),
            colours,
        }],
        &face_view(session),
    )
    .png()
}

/// The section: for each pick, four pictures in a row.
pub fn section(
    session: &Session,
    evaluation: &SessionEvaluation,
    picks: &[Pick],
    files: &mut Files,
) -> Result<Section, Box<dyn std::error::Error>> {
    let mut body = String::from(
        "<p>Each vertex coloured by its distance from the recorded mesh of the test expression. \
         From left to right: the recorded mesh (the reference), the product's method, EBFR and DT, \
         as in the paper's Fig. 6.</p>",
    );
    body.push_str(&html::figure(
        "colour-scale.svg",
        super::COLOUR_SCALE_SIZE.0,
        super::COLOUR_SCALE_SIZE.1,
        "colour scale",
        "The colour scale of every error map in this report: blue 0 mm, red 5 mm or more.",
    ));
    let methods = [Method::DEFAULT, Method::Ebfr, Method::Dt];
    for pick in picks {
        let test = &session.tests[pick.test];
        let _ = write!(
            body,
            "<h3>{} ({} by the product's RMSE)</h3><div class=\"row\">",
            escape(&test.id),
            pick.label
        );
        let recorded: Vec<DVec3> = test.vertices.iter().map(|p| p.as_dvec3()).collect();
        let path = format!("fig6/{}-recorded.png", pick.label);
        files.add(
            path.clone(),
            face_png(session, &recorded, &vec![SKIN; recorded.len()])?,
        );
        body.push_str(&html::figure(
            &path,
            FACE_SIZE.0,
            FACE_SIZE.1,
            "recorded",
            "recorded",
        ));
        for method in methods {
            let Some(r) = run(evaluation, method) else {
                continue;
            };
            let model = r.personalized.shapes.reconstruct(&test.weights);
            let colours: Vec<[u8; 3]> = vertex_errors_mm(&model, &test.vertices)
                .into_iter()
                .map(error_colour)
                .collect();
            let path = format!("fig6/{}-{}.png", pick.label, method);
            files.add(path.clone(), face_png(session, &model, &colours)?);
            let e = &r.errors[pick.test];
            body.push_str(&html::figure(
                &path,
                FACE_SIZE.0,
                FACE_SIZE.1,
                method.name(),
                &format!("{method}: RMSE {:.3} mm, max {:.3} mm", e.rmse_mm, e.max_mm),
            ));
        }
        body.push_str("</div>");
    }
    Ok(Section {
        id: "error-maps",
        title: "Where the error is (Fig. 6)".to_string(),
        body,
    })
}
