//! "The avatar" (the paper's §4.2, Fig. 7 and 8): the person's shapes
//! implanted into the avatar (`likeness::avatar::personal_avatar`), and
//! each test expression animated on it three ways — manual retargeting,
//! automatic retargeting (Eq. 4) and the personalized avatar — compared on
//! the face region with the person's own expression
//! (`likeness::avatar::likeness_check`). The pictures show the avatar from
//! the front of the registered mask, each face vertex coloured by its
//! error.

use super::accuracy::run;
use super::charts::{self, Bars, DT, EBFR, PRODUCT};
use super::colour_map::{PALE, SKIN, error_colour};
use super::error_maps::{FACE_SIZE, Pick};
use super::html::{self, Section, escape, number_cell};
use super::output::Files;
use super::rasterizer::{FrontView, Mesh, render};
use crate::personalize::SessionEvaluation;
use glam::DVec3;
use likeness::Session;
use likeness::avatar::glb::{GlbAvatar, read_avatar};
use likeness::avatar::likeness_check::{
    Animation, AnimationShapes, AvatarTestError, animate, likeness_on_avatar, mean_face_errors,
    test_delta,
};
use likeness::avatar::personal_avatar::{
    AvatarShapes, AvatarStep, PersonInput, RestFace, personal_avatar,
};
use likeness::avatar::registration::FaceRegistration;
use likeness::personalize::Method;
use std::fmt::Write;
use std::path::Path;

/// The size of the per-expression chart.
pub const CHART_SIZE: (u32, u32) = (1100, 320);

/// The section; `avatar` is the user's avatar file, or `None` for the
/// default avatar; `status` hears each step of the avatar stage.
pub fn section(
    session: &Session,
    evaluation: &SessionEvaluation,
    picks: &[Pick],
    avatar: Option<&Path>,
    status: &dyn Fn(&'static str),
    files: &mut Files,
) -> Result<Section, Box<dyn std::error::Error>> {
    let glb: GlbAvatar = match avatar {
        Some(path) => read_avatar(path)?,
        None => crate::avatar::default_glb()?,
    };
    let product = run(evaluation, Method::DEFAULT).ok_or("no run of the product's method")?;
    let rig = session.template.blendshapes()?;
    let person = PersonInput {
        mask: &session.topology,
        rig: &rig,
        personalized: &product.personalized.shapes,
    };
    let made = personal_avatar(
        &glb,
        &person,
        None,
        AvatarShapes::Personalized,
        RestFace::Stock,
        &mut |step: AvatarStep| {
            status(step.name());
            true
        },
    )?;
    let implanted = made.implanted.ok_or("the avatar stage implanted nothing")?;
    let registration = &made.registration;
    let shapes = AnimationShapes::new(&glb.avatar, &made.retargeting, implanted.shapes);
    status("comparing on the face");
    let tests = likeness_on_avatar(session, registration, &shapes);
    let means = mean_face_errors(&tests);

    let mut body = String::new();
    let _ = write!(
        body,
        "<p>Avatar: {} ({} vertices; face region {} vertices, registration residual mean {:.2} mm). \
         Each test expression animated from its tracked weights by <b>manual retargeting</b> (the avatar's own \
         shape <i>j</i> driven by weight <i>j</i>, as game engines do), <b>automatic retargeting</b> (Eq. 4: \
         the avatar's shapes combined to approximate the person's) and the <b>personalized avatar</b> (the \
         person's shapes implanted), compared on the face region with the person's {} expression carried \
         onto the avatar (mm at the mask's scale).</p>",
        escape(&avatar.map_or("the default avatar".to_string(), |p| {
            p.display().to_string()
        })),
        glb.avatar.vertex_count(),
        registration.map.face.len(),
        registration.residual_mean_mm,
        if session.truth.is_some() {
            "true (noise-free)"
        } else {
            "recorded"
        },
    );
    for warning in &made.warnings {
        let _ = write!(
            body,
            "<p class=\"flag\">{}</p>",
            escape(&warning.to_string())
        );
    }
    let rows: Vec<String> = Animation::ALL
        .iter()
        .zip(&means)
        .map(|(a, m)| {
            format!(
                "<tr data-animation=\"{}\"><td>{}</td>{}{}</tr>",
                a.name(),
                a.name(),
                number_cell("face_rmse_mm", Some(m.rmse_mm), 3),
                number_cell("face_max_mm", Some(m.max_mm), 3)
            )
        })
        .collect();
    body.push_str(&html::table(
        "avatar-means",
        &["animation", "face RMSE mm (mean)", "face max mm (mean)"],
        &rows,
    ));
    body.push_str(&rmse_chart(&tests, files)?);

    let view = avatar_view(session);
    let positions = avatar_in_mask_frame(&glb, registration);
    let triangles = glb.avatar.triangles();
    let base = base_colours(&glb, registration);
    for pick in picks {
        let test = &session.tests[pick.test];
        let t = &tests[pick.test];
        let _ = write!(
            body,
            "<h3>{} ({})</h3><div class=\"row\">",
            escape(&test.id),
            pick.label
        );
        let expression: Vec<DVec3> = session
            .neutral
            .iter()
            .zip(test_delta(session, pick.test))
            .map(|(n, d)| n.as_dvec3() + d)
            .collect();
        let path = format!("avatar/{}-person.png", pick.label);
        let skin = vec![SKIN; expression.len()];
        let image = render(
            &[Mesh {
                positions: &expression,
                triangles: session.topology.triangles(),
                colours: &skin,
            }],
            &view,
        );
        files.add(path.clone(), image.png()?);
        body.push_str(&html::figure(
            &path,
            FACE_SIZE.0,
            FACE_SIZE.1,
            "person",
            "the person (mask)",
        ));
        for (m, animation) in Animation::ALL.iter().enumerate() {
            let moved = animate(shapes.get(*animation), &test.weights);
            let turned: Vec<DVec3> = positions
                .iter()
                .zip(&moved)
                .map(|(p, d)| {
                    *p + registration.similarity.rotation.transpose() * *d
                        / registration.similarity.scale
                })
                .collect();
            let mut colours = base.clone();
            for (f, e) in registration.map.face.iter().zip(&t.errors_mm[m]) {
                colours[f.vertex as usize] = error_colour(*e);
            }
            let image = render(
                &[Mesh {
                    positions: &turned,
                    triangles,
                    colours: &colours,
                }],
                &view,
            );
            let path = format!("avatar/{}-{}.png", pick.label, animation.name());
            files.add(path.clone(), image.png()?);
            body.push_str(&html::figure(
                &path,
                FACE_SIZE.0,
                FACE_SIZE.1,
                animation.name(),
                &format!(
                    "{}: face RMSE {:.3} mm, max {:.3} mm",
                    animation.name(),
                    t.face[m].rmse_mm,
                    t.face[m].max_mm
                ),
            ));
        }
        body.push_str("</div>");
    }
    Ok(Section {
        id: "avatar",
        title: "The avatar (Fig. 7 and 8)".to_string(),
        body,
    })
}

/// The face RMSE of each test expression under each animation, as bars.
fn rmse_chart(
    tests: &[AvatarTestError],
    files: &mut Files,
) -> Result<String, Box<dyn std::error::Error>> {
    let values: Vec<Vec<f64>> = (0..3)
        .map(|m| tests.iter().map(|t| t.face[m].rmse_mm).collect())
        .collect();
    let colours = [DT, EBFR, PRODUCT];
    let series: Vec<Bars<'_>> = Animation::ALL
        .iter()
        .zip(&values)
        .zip(colours)
        .map(|((a, v), colour)| Bars {
            name: a.name(),
            colour,
            values: v,
        })
        .collect();
    let svg = charts::grouped_bars(
        CHART_SIZE.0,
        CHART_SIZE.1,
        "face RMSE (mm)",
        "test expression",
        &series,
    )?;
    files.add("avatar/face-rmse.svg", svg.into_bytes());
    Ok(html::figure(
        "avatar/face-rmse.svg",
        CHART_SIZE.0,
        CHART_SIZE.1,
        "face RMSE per test expression",
        "The face-region RMSE of each test expression (numbered as in the accuracy table) on the avatar.",
    ))
}

/// The view of the avatar pictures: the person's neutral face with room
/// for the head around it, in the mask's frame.
fn avatar_view(session: &Session) -> FrontView {
    let neutral: Vec<DVec3> = session.neutral.iter().map(|p| p.as_dvec3()).collect();
    FrontView::framing(&neutral, FACE_SIZE.0, FACE_SIZE.1, 0.16)
}

/// The avatar's rest positions brought into the mask's frame (the
/// registration's similarity undone), so it is seen from the mask's front.
fn avatar_in_mask_frame(glb: &GlbAvatar, registration: &FaceRegistration) -> Vec<DVec3> {
    let s = &registration.similarity;
    let back = s.rotation.transpose();
    glb.avatar
        .positions()
        .iter()
        .map(|p| back * (p.as_dvec3() - s.translation) / s.scale)
        .collect()
}

/// Skin everywhere, pale on the eyeballs.
fn base_colours(glb: &GlbAvatar, registration: &FaceRegistration) -> Vec<[u8; 3]> {
    let offsets = glb.avatar.vertex_offsets();
    let mut colours = vec![SKIN; glb.avatar.vertex_count()];
    for &part in &registration.eyeball_parts() {
        if let Some(range) = offsets.get(part).zip(offsets.get(part + 1)) {
            colours[*range.0..*range.1].fill(PALE);
        }
    }
    colours
}
