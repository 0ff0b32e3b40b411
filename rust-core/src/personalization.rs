//! §3.2: from a capture session to the person's own 52 blendshapes.
//!
//! Every method starts the same way: the generic template is carried onto
//! the person's neutral scan `B₀` by deformation transfer (virtual triangles
//! close the eye holes), giving the generic blendshapes `T_j`. Then:
//!
//! | method | blendshapes |
//! |---|---|
//! | `dt` | `B_j = T_j` (Sumner & Popović 2004; the paper's DT baseline) |
//! | `ebfr` | Li, Weise & Pauly 2010, blendshape step with known weights ([`crate::ebfr`]) |
//! | `paper` | Eq. (1)–(3) literally: `E_fit + E_reg` ([`crate::blendshape_fit`]) |
//! | `paper-cv` | `E_fit + λ·E_reg`, λ chosen per session on held-out stream frames ([`crate::lambda_selection`]) |
//! | `multi` | as `paper-cv`, fitted to frames around each peak as well ([`crate::frame_selection`]) |
//!
//! Shapes whose prompt was not captured keep their generic shape `T_j`, and
//! the result lists them.

use crate::arkit_names::{BLENDSHAPE_COUNT, Blendshape};
use crate::blendshape_fit::{BlendshapeFit, Observation, SingularFit};
use crate::deformation_transfer::{DeformationTransfer, TransferError};
use crate::lambda_selection::{LAMBDA_GRID, choose_lambda};
use crate::mesh_boundary::{EyeHoleError, eye_hole_triangles};
use crate::regularization_weights::regularization_weights;
use crate::session::{Session, SessionError};
use glam::DVec3;
use std::fmt;
use std::str::FromStr;

/// A personalization method (see the module table).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Deformation transfer of the template: the generic blendshapes.
    Dt,
    /// Example-based facial rigging (Li et al. 2010), blendshape step.
    Ebfr,
    /// The paper's Eq. (1)–(3), λ = 1.
    Paper,
    /// The paper's energy with λ chosen from the capture stream.
    PaperCv,
    /// `paper-cv` fitted to several frames around each peak.
    Multi,
}

impl Method {
    /// What the product uses: of the paper's literal energy (`paper`) and the
    /// same with λ chosen per session (`paper-cv`), the one more faithful on
    /// the held-out test expressions of the simulated subjects: `paper-cv`
    /// (0.30 mm against 0.53 mm RMSE to the true faces; see the README).
    pub const DEFAULT: Method = Method::PaperCv;

    /// Every method, baselines first.
    pub const ALL: [Method; 5] = [
        Method::Dt,
        Method::Ebfr,
        Method::Paper,
        Method::PaperCv,
        Method::Multi,
    ];

    /// The method's command-line name.
    pub const fn name(self) -> &'static str {
        match self {
            Method::Dt => "dt",
            Method::Ebfr => "ebfr",
            Method::Paper => "paper",
            Method::PaperCv => "paper-cv",
            Method::Multi => "multi",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;

    fn from_str(s: &str) -> Result<Method, String> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!("unknown method {s:?}: expected one of dt, ebfr, paper, paper-cv, multi")
            })
    }
}

/// The person's blendshapes.
#[derive(Clone, Debug)]
pub struct Personalized {
    /// How they were computed.
    pub method: Method,
    /// The neutral face `B₀` (the neutral scan).
    pub neutral: Vec<DVec3>,
    /// The 52 delta blendshapes `B_j`, in Apple's order.
    pub deltas: Vec<Vec<DVec3>>,
    /// Shapes that were not captured and are the generic `T_j`.
    pub generic_fallback: Vec<Blendshape>,
    /// The regularization strength used (fits only).
    pub lambda: Option<f64>,
    /// `paper-cv`/`multi`: validation error (mean squared, m²) for each λ of
    /// [`LAMBDA_GRID`], in grid order.
    pub lambda_scores: Vec<(f64, f64)>,
}

/// Why a session cannot be personalized.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum PersonalizeError {
    /// The session contradicts itself (a NaN weight, a mesh of another
    /// topology, …); the message names the expression.
    #[error(transparent)]
    Session(#[from] SessionError),
    /// The mask's eye holes could not be found.
    #[error("template: {0}")]
    EyeHoles(#[from] EyeHoleError),
    /// Deformation transfer failed.
    #[error("deformation transfer: {0}")]
    Transfer(#[from] TransferError),
    /// A per-vertex fit was singular.
    #[error(transparent)]
    Fit(#[from] SingularFit),
    /// Nothing was captured, so there is nothing to personalize from.
    #[error("the session has no captured expressions")]
    NoCaptures,
}

/// The template transferred onto the person: what every method starts from.
pub struct GenericBlendshapes {
    /// `B₀`.
    pub neutral: Vec<DVec3>,
    /// `T_1 … T_52` as deltas from `B₀`.
    pub deltas: Vec<Vec<DVec3>>,
    /// The factored transfer onto `B₀` (EBFR reuses it).
    pub transfer: DeformationTransfer,
}

/// Validates what personalization reads of the session (everything but
/// the stream; the stream frames a method uses are checked where they are
/// chosen) and transfers the template onto its neutral scan.
pub fn generic_blendshapes(session: &Session) -> Result<GenericBlendshapes, PersonalizeError> {
    session.validate_expressions()?;
    let virtual_triangles = eye_hole_triangles(&session.topology, &session.template.neutral)?;
    let neutral: Vec<DVec3> = session.neutral.iter().map(|p| p.as_dvec3()).collect();
    let transfer = DeformationTransfer::new(&session.topology, &virtual_triangles, &neutral)?;
    let deltas = transfer.transfer_template(&session.template)?;
    Ok(GenericBlendshapes {
        neutral,
        deltas,
        transfer,
    })
}

fn weights_f64(w: &crate::arkit_names::Weights) -> [f64; BLENDSHAPE_COUNT] {
    w.0.map(f64::from)
}

/// Personalizes the session's blendshapes with `method`.
pub fn personalize(session: &Session, method: Method) -> Result<Personalized, PersonalizeError> {
    let generic = generic_blendshapes(session)?;
    let free = captured(session);
    let generic_fallback: Vec<Blendshape> = Blendshape::ALL
        .into_iter()
        .filter(|s| !free[s.index()])
        .collect();
    let finish = |deltas, lambda, lambda_scores| Personalized {
        method,
        neutral: generic.neutral.clone(),
        deltas,
        generic_fallback: generic_fallback.clone(),
        lambda,
        lambda_scores,
    };
    if method == Method::Dt {
        return Ok(finish(generic.deltas.clone(), None, Vec::new()));
    }
    if session.captures.is_empty() {
        return Err(PersonalizeError::NoCaptures);
    }
    if matches!(method, Method::PaperCv | Method::Multi) {
        check_stream_frames(session)?;
    }
    if method == Method::Ebfr {
        let deltas = crate::ebfr::ebfr_blendshapes(session, &generic, &free)?;
        return Ok(finish(deltas, None, Vec::new()));
    }
    let fit = assemble_fit(session, &generic, method == Method::Multi);
    match method {
        Method::Paper => Ok(finish(fit.solve(1.0)?, Some(1.0), Vec::new())),
        _ => {
            let choice = choose_lambda(session, &generic.neutral, &fit, &LAMBDA_GRID)?;
            Ok(finish(choice.deltas, Some(choice.lambda), choice.scores))
        }
    }
}

/// The observations of `E_fit`: the captures, and for `multi` the frames
/// around them, each prompt weighing as one capture in total.
fn observations(session: &Session, multi: bool) -> Vec<Observation<'_>> {
    let mut observations: Vec<Observation> = session
        .captures
        .iter()
        .map(|c| Observation {
            weights: weights_f64(&c.weights),
            vertices: &c.vertices,
            importance: 1.0,
        })
        .collect();
    if multi {
        let extra = crate::frame_selection::fit_frames(session);
        let mut per_capture = vec![1usize; session.captures.len()];
        for (c, _) in &extra {
            per_capture[*c] += 1;
        }
        for (o, k) in observations.iter_mut().zip(&per_capture) {
            o.importance = 1.0 / *k as f64;
        }
        for (c, f) in extra {
            if let Some(vertices) = &session.frames[f].vertices {
                observations.push(Observation {
                    weights: weights_f64(&session.frames[f].weights),
                    vertices,
                    importance: 1.0 / per_capture[c] as f64,
                });
            }
        }
    }
    observations
}

/// The blendshapes fitted for each λ of a sweep: `(λ, deltas)`.
pub type Sweep = Vec<(f64, Vec<Vec<DVec3>>)>;

/// The λ study: the paper's fit (`multi = false`) or the multi-frame fit,
/// solved for each λ of `grid`. Returns `B₀` and the sweep.
pub fn lambda_sweep(
    session: &Session,
    multi: bool,
    grid: &[f64],
) -> Result<(Vec<DVec3>, Sweep), PersonalizeError> {
    let generic = generic_blendshapes(session)?;
    check_stream_frames(session)?;
    let fit = assemble_fit(session, &generic, multi);
    let mut out = Vec::with_capacity(grid.len());
    for &lambda in grid {
        out.push((lambda, fit.solve(lambda)?));
    }
    Ok((generic.neutral, out))
}

/// Which prompts were captured (the free shapes of the fits).
fn captured(session: &Session) -> [bool; BLENDSHAPE_COUNT] {
    let mut free = [false; BLENDSHAPE_COUNT];
    for c in &session.captures {
        free[c.prompt.index()] = true;
    }
    free
}

/// Checks the stream frames that `paper-cv` and `multi` read.
fn check_stream_frames(session: &Session) -> Result<(), SessionError> {
    let fit = crate::frame_selection::fit_frames(session)
        .into_iter()
        .map(|(_, f)| f);
    for f in crate::frame_selection::validation_frames(session)
        .into_iter()
        .chain(fit)
    {
        session.validate_frame(f)?;
    }
    Ok(())
}

/// Eq. (1)–(3) assembled for the session: the Eq. (3) weights of the generic
/// blendshapes, the captures (and for `multi` the frames around them) as
/// observations, the captured shapes free.
fn assemble_fit<'g>(
    session: &Session,
    generic: &'g GenericBlendshapes,
    multi: bool,
) -> BlendshapeFit<'g> {
    let weights: Vec<Vec<f64>> = generic
        .deltas
        .iter()
        .map(|t| regularization_weights(t))
        .collect();
    let observations = observations(session, multi);
    BlendshapeFit::new(
        &generic.neutral,
        &generic.deltas,
        &weights,
        &captured(session),
        &observations,
    )
}
