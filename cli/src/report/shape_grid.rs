//! "What personalization changed" (the paper's Fig. 2, for all 52
//! shapes): each shape at weight one as the generic template carried onto
//! the person (DT's `B₀ + T_j`, left) and as the product's method
//! personalized it (`B₀ + B_j`, right), the right one coloured by how far
//! each vertex moved from the generic shape
//! (`likeness::personalize::evaluation::vertex_errors_mm`).

use super::accuracy::run;
use super::colour_map::{SKIN, error_colour};
use super::html::{Section, escape};
use super::image::Image;
use super::output::Files;
use super::rasterizer::{BACKGROUND, FrontView, Mesh, render};
use crate::personalize::SessionEvaluation;
use glam::DVec3;
use likeness::personalize::Method;
use likeness::personalize::evaluation::vertex_errors_mm;
use likeness::{Blendshape, Session};
use std::fmt::Write;

/// The size of one face in a thumbnail; a thumbnail is two of them with
/// [`GAP`] pixels between.
pub const HALF_SIZE: (u32, u32) = (150, 185);

/// Pixels between the generic and the personalized face.
pub const GAP: u32 = 2;

/// The size of each thumbnail.
pub const THUMB_SIZE: (u32, u32) = (2 * HALF_SIZE.0 + GAP, HALF_SIZE.1);

/// The section: 52 thumbnails in Apple's order.
pub fn section(
    session: &Session,
    evaluation: &SessionEvaluation,
    files: &mut Files,
) -> Result<Section, Box<dyn std::error::Error>> {
    let (Some(generic), Some(product)) = (
        run(evaluation, Method::Dt),
        run(evaluation, Method::DEFAULT),
    ) else {
        return Err("the evaluation has no DT or product run".into());
    };
    let neutral: Vec<DVec3> = session.neutral.iter().map(|p| p.as_dvec3()).collect();
    let view = FrontView::framing(&neutral, HALF_SIZE.0, HALF_SIZE.1, 0.07);
    let triangles = session.topology.triangles();
    let skin = vec![SKIN; neutral.len()];
    let mut body = format!(
        "<p>Each of ARKit's 52 shapes at weight one: left, the generic shape (the template carried onto the \
         neutral scan by deformation transfer); right, the person's shape by the product's method ({}), \
         each vertex coloured by its distance from the generic shape on the report's scale (blue 0 mm, red 5 mm \
         or more). The caption gives the largest distance.</p><div class=\"grid\">",
        Method::DEFAULT
    );
    for shape in Blendshape::ALL {
        let a = generic.personalized.shapes.shape(shape);
        let b = product.personalized.shapes.shape(shape);
        let moved = vertex_errors_mm(&b, &a);
        let largest = moved.iter().copied().fold(0.0f64, f64::max);
        let colours: Vec<[u8; 3]> = moved.into_iter().map(error_colour).collect();
        let left = render(
            &[Mesh {
                positions: &a,
                triangles,
                colours: &skin,
            }],
            &view,
        );
        let right = render(
            &[Mesh {
                positions: &b,
                triangles,
                colours: &colours,
            }],
            &view,
        );
        let thumb: Image = left.beside(&right, GAP, BACKGROUND);
        let path = format!("fig2/{}.png", shape.name());
        files.add(path.clone(), thumb.png()?);
        let fallback = if product.personalized.generic_fallback.contains(&shape) {
            " · not captured: generic"
        } else {
            ""
        };
        let _ = write!(
            body,
            "<figure><img src=\"{path}\" width=\"{}\" height=\"{}\" alt=\"{name}\"><figcaption>{name}: up to {largest:.2} mm{fallback}</figcaption></figure>",
            THUMB_SIZE.0,
            THUMB_SIZE.1,
            name = escape(shape.name()),
        );
    }
    body.push_str("</div>");
    Ok(Section {
        id: "shapes",
        title: "What personalization changed (Fig. 2)".to_string(),
        body,
    })
}
