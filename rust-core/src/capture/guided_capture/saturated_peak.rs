//! Where the face peaked while the prompted weight was clamped at 1.
//!
//! ARKit clamps its weights at 1. For a person whose shape rests high
//! (browDown at 0.45, say) a full expression runs into the clamp and stays
//! there for most of its hold, so the prompted weight is flat exactly where
//! the peak detector would look. Two other signals still move with the face:
//!
//! 1. **Companion weights.** An expression is never one channel: the other
//!    weights that rise with it (the mirror side, co-activated muscles, the
//!    tracker's own crosstalk) follow the same effort in time and are not
//!    clamped. With `c_j(t)` each unclamped channel's rise above its value
//!    in the neutral scan (the person's own rest, tracker bias included,
//!    so a channel that merely rests a little high carries no weight) and
//!    `m_j` its mean over the stretch, the face is furthest into
//!    the expression where `s(t) = Σ_j c_j(t) m_j` is largest (a matched
//!    filter: the stretch's own mean pattern is the template). The weights
//!    lag the face by the detector's latency, which is subtracted. Used
//!    when the companions rise by at least [`MIN_COMPANION_RISE`] in norm,
//!    far above the tracker's noise.
//! 2. **The mesh.** Otherwise, with `D_v` the mean displacement of vertex
//!    `v` from the neutral scan over the stretch, the projection
//!    `p(t) = Σ_v (x_v(t) − n_v) · D_v` is largest where the face is
//!    furthest into the expression. Only the vertices the expression
//!    visibly moves are summed (`|D_v|` at least [`MESH_SUPPORT`] of the
//!    largest): everywhere else `D_v` is tracker noise, which only adds
//!    noise to `p`.
//!
//! Either score is smoothed by a centred three-frame mean before its
//! largest value is taken, as the peak detector's rough stage does. Without
//! either signal (a weights-only stream with a single channel moving) the
//! stretch's middle stays, which the detector already reports.

use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Weights};
use crate::session::Frame;
use glam::Vec3;

/// Least norm of the companions' mean rise (weight units) for them to
/// place the peak: ten times a tracker's rest noise would already do; a
/// tenth of the weight range keeps clear of it by far.
pub const MIN_COMPANION_RISE: f32 = 0.1;

/// Share of the largest mean displacement from which a vertex counts as
/// moved by the expression (see the module docs).
pub const MESH_SUPPORT: f32 = 0.5;

/// A weight at or above this is clamped: it cannot tell where the face
/// peaked.
const CLAMPED: f32 = 0.999;

/// One frame of the stretch: its detector frame (latency subtracted, as
/// the peak's stretch is) and the frame itself.
pub type StretchFrame<'a> = (usize, &'a Frame);

/// The detector frame at which the face peaked within `stretch`, the
/// frames whose detector frames lie within the saturated stretch of
/// `shape`'s peak, in order; `lagged` are the frames `latency` detector
/// frames later (where the weights of the stretch's faces were reported);
/// `rest` and `neutral` are the neutral scan's weights and mesh. `None`
/// when neither the companions nor the mesh can tell.
pub fn peak_in_stretch(
    shape: Blendshape,
    stretch: &[StretchFrame],
    lagged: &[StretchFrame],
    latency: usize,
    rest: &Weights,
    neutral: Option<&[Vec3]>,
) -> Option<usize> {
    companion_peak(shape, lagged, latency, rest)
        .or_else(|| neutral.and_then(|n| mesh_peak(stretch, n)))
}

/// The companions' estimate (signal 1 of the module docs): the frame where
/// `s(t)` is largest, `latency` subtracted.
fn companion_peak(
    shape: Blendshape,
    frames: &[StretchFrame],
    latency: usize,
    rest: &Weights,
) -> Option<usize> {
    if frames.len() < 3 {
        return None;
    }
    let rise = |frame: &Frame, j: Blendshape| {
        let (w, r) = (frame.weights.get(j), rest.get(j));
        if w.is_finite() && r.is_finite() {
            (w - r).max(0.0)
        } else {
            0.0
        }
    };
    let mut mean = [0.0f32; BLENDSHAPE_COUNT];
    for j in Blendshape::ALL {
        let clamped = frames.iter().any(|(_, f)| f.weights.get(j) >= CLAMPED);
        if j == shape || clamped {
            continue;
        }
        mean[j.index()] = frames.iter().map(|(_, f)| rise(f, j)).sum::<f32>() / frames.len() as f32;
    }
    let norm = mean.iter().map(|m| m * m).sum::<f32>().sqrt();
    if norm < MIN_COMPANION_RISE {
        return None;
    }
    let scores: Vec<f32> = frames
        .iter()
        .map(|(_, f)| {
            Blendshape::ALL
                .into_iter()
                .map(|j| rise(f, j) * mean[j.index()])
                .sum()
        })
        .collect();
    let best = smoothed_argmax(&scores)?;
    Some(frames[best].0.saturating_sub(latency))
}

/// The mesh's estimate (signal 2 of the module docs): the frame where the
/// projection on the expression's mean displacement is largest.
fn mesh_peak(stretch: &[StretchFrame], neutral: &[Vec3]) -> Option<usize> {
    let meshes: Vec<(usize, &Vec<Vec3>)> = stretch
        .iter()
        .filter_map(|(at, f)| {
            Some((
                *at,
                f.vertices.as_ref().filter(|m| m.len() == neutral.len())?,
            ))
        })
        .collect();
    if meshes.is_empty() {
        return None;
    }
    let mut direction = vec![Vec3::ZERO; neutral.len()];
    for (_, mesh) in &meshes {
        for ((d, p), q) in direction.iter_mut().zip(mesh.iter()).zip(neutral) {
            *d += *p - *q;
        }
    }
    let largest = direction.iter().map(|d| d.length()).fold(0.0, f32::max);
    for d in &mut direction {
        if d.length() < MESH_SUPPORT * largest {
            *d = Vec3::ZERO;
        }
    }
    let scores: Vec<f32> = meshes
        .iter()
        .map(|(_, mesh)| {
            mesh.iter()
                .zip(neutral)
                .zip(&direction)
                .map(|((p, q), d)| (*p - *q).dot(*d))
                .sum()
        })
        .collect();
    let best = smoothed_argmax(&scores)?;
    Some(meshes[best].0)
}

/// Index of the largest centred three-frame mean of `scores` (the ends
/// average what they have); the first on ties, `None` for no scores.
fn smoothed_argmax(scores: &[f32]) -> Option<usize> {
    (0..scores.len())
        .map(|i| {
            let window = &scores[i.saturating_sub(1)..(i + 2).min(scores.len())];
            (i, window.iter().sum::<f32>() / window.len() as f32)
        })
        .fold(None, |best: Option<(usize, f32)>, (i, s)| match best {
            Some((_, b)) if b >= s => best,
            _ => Some((i, s)),
        })
        .map(|(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(weights: Weights, vertices: Option<Vec<Vec3>>) -> Frame {
        Frame {
            timestamp: 0.0,
            weights,
            vertices,
            tracked: true,
        }
    }

    /// A stretch where the prompted weight is clamped and its mirror rises
    /// to a peak at frame 14 then settles; the mesh's noise peaks later.
    #[test]
    fn the_companions_place_the_peak_where_the_clamped_weight_cannot() {
        let envelope = |t: usize| {
            let t = t as f32;
            if t <= 14.0 {
                t / 14.0
            } else {
                0.85 + 0.15 * (-(t - 14.0) / 5.0).exp()
            }
        };
        let frames: Vec<Frame> = (0..40)
            .map(|t| {
                let mut w = Weights::ZERO;
                w.set(Blendshape::BrowDownLeft, 1.0);
                // Reported a frame late (latency 1).
                w.set(Blendshape::BrowDownRight, 0.4 * envelope(t.max(1) - 1));
                frame(w, None)
            })
            .collect();
        let stretch: Vec<StretchFrame> = frames.iter().enumerate().collect();
        let rest = Weights::ZERO;
        let at = peak_in_stretch(Blendshape::BrowDownLeft, &stretch, &stretch, 1, &rest, None);
        assert!(matches!(at, Some(13..=15)), "{at:?}");
        // Without companions and without meshes nothing can tell.
        let alone: Vec<Frame> = (0..40)
            .map(|_| {
                let mut w = Weights::ZERO;
                w.set(Blendshape::BrowDownLeft, 1.0);
                frame(w, None)
            })
            .collect();
        let stretch: Vec<StretchFrame> = alone.iter().enumerate().collect();
        let at = peak_in_stretch(Blendshape::BrowDownLeft, &stretch, &stretch, 1, &rest, None);
        assert_eq!(at, None);
    }

    /// With no companions, the mesh places the peak from the moving
    /// vertices only: a slow drift on the still ones must not pull it late.
    #[test]
    fn the_mesh_places_the_peak_from_the_vertices_the_expression_moves() {
        let neutral = vec![Vec3::ZERO; 100];
        let frames: Vec<Frame> = (0..40)
            .map(|t| {
                let a = if t <= 10 { 1.0 } else { 0.85 } + if t == 10 { 0.05 } else { 0.0 };
                let drift = 0.00001 * t as f32;
                let mesh = (0..100)
                    .map(|v| {
                        if v < 5 {
                            Vec3::Z * 0.002 * a
                        } else {
                            Vec3::X * (0.0002 + drift)
                        }
                    })
                    .collect();
                let mut w = Weights::ZERO;
                w.set(Blendshape::MouthPressLeft, 1.0);
                frame(w, Some(mesh))
            })
            .collect();
        let stretch: Vec<StretchFrame> = frames.iter().enumerate().collect();
        let at = peak_in_stretch(
            Blendshape::MouthPressLeft,
            &stretch,
            &stretch,
            1,
            &Weights::ZERO,
            Some(&neutral),
        );
        assert!(matches!(at, Some(9..=11)), "{at:?}");
    }
}
