//! (Beyond the paper) a closed eye closes the avatar's way: in a shape
//! where the person's eye closes, the avatar's lids take the avatar's own
//! blink of that eye, whole near the lid margins and fading into the
//! transferred shape over the rest of the lid.
//!
//! Why: the transfer carries the person's motion at the mask's resolution,
//! vertex for vertex through the correspondence. Where the avatar's lids
//! are built unlike the mask's, that motion does not close them. On
//! ICT-FaceKit the skin a millimetre above the lid's margin travels 11.6
//! mm in its own blink, and the person's mask moves the corresponding
//! point 5.2 mm: the personalized blink left 10–34% of the eyeball seen,
//! where ICT's own leaves 1–2%. The lid contacts ([`super::lid_contacts`])
//! close the margins on avatars whose eye openings are boundary loops;
//! ICT's lids fold into the sockets, so it has none. How a closed lid lies
//! over the eyeball is the avatar's anatomy, not the person's: the
//! person's closed eye is kept as the fact that it closes, and the rest of
//! the shape (the brow, the cheek) stays the person's.
//!
//! - **Which eyes.** Those whose opening the lid contacts could not find
//!   on the avatar. Where they can, the contacts close the person's own
//!   lids, and the avatar's own blink would move the upper lid alone: its
//!   margin would no longer meet the lower lid where the person's
//!   transfer put it (a dark slit on the default avatar).
//! - **Which blink is which eye.** Each of the mask's eye holes takes the
//!   avatar's own `eyeBlinkLeft` or `eyeBlinkRight`, whichever moves the
//!   hole's rim more as the mask sees it ([`MaskOnSkin`]).
//! - **When.** Shape `j` closes hole `h` by the mask's rule
//!   ([`super::lid_contacts::closes`]).
//! - **Where.** The upper lid by its travel: with `t_v = |b_v| / max |b|`,
//!   the own blink's travel at avatar vertex `v` of the face parts as a
//!   share of its largest, `α_v = smoothstep((t_v − `[`FADE_FROM`]`) /
//!   (`[`WHOLE_FROM`]` − `[`FADE_FROM`]`))`. The lower lid, which a blink
//!   barely moves, by where the upper one closes on it: with `c_v` the
//!   distance from `v` in the own blink to the nearest vertex the own blink
//!   moves whole (`t ≥ WHOLE_FROM`), also there, `α_v ≥ 1 −
//!   smoothstep((c_v − `[`MEETS_MM`]`) / `[`MEETS_MM`]`)`: the lower
//!   margin, on which the upper one lands, takes the own blink too, or the
//!   two would not meet. Then `D_v ← D_v + α_v (b_v − D_v)`.

use super::lid_contacts::closes;
use crate::arkit::{Blendshape, Blendshapes};
use crate::avatar::own_shapes::MaskOnSkin;
use crate::geometry::mesh_boundary::EyeHole;
use glam::DVec3;

/// From this share of the own blink's largest travel on, the avatar's own
/// lid is taken whole: the lid's lower half, the margin included (a lid
/// travels most at its margin and less towards the crease).
pub const WHOLE_FROM: f64 = 0.5;

/// Below this share of the own blink's largest travel the shape is the
/// transferred one: the brow and the cheek, which a blink barely moves.
pub const FADE_FROM: f64 = 0.1;

/// Within this distance (mm at the mask's scale) of the closed upper lid,
/// in the own blink, the lower lid takes the own blink whole; it fades out
/// over as much again. A lid margin is about 1 mm thick.
pub const MEETS_MM: f64 = 1.0;

/// One eye's own blink and where it takes over.
struct Lid {
    /// The own blink's displacement of every avatar vertex.
    blink: Vec<DVec3>,
    /// `(vertex, α)` for every vertex with `α > 0`.
    weights: Vec<(u32, f64)>,
}

/// The eyes each of the person's shapes closes, and the avatar's own lids
/// to close them with.
pub struct ClosedLids {
    lids: Vec<Lid>,
    /// Per shape (Apple's order), the indices into `lids` it closes.
    per_shape: Vec<Vec<usize>>,
}

impl ClosedLids {
    /// Matches the mask's eye `holes`
    /// ([`super::lid_contacts::mask_eye_holes`]) but those in
    /// `closed_otherwise` (indices into them), as the person's shapes
    /// (`personalized`) close them, with the avatar's own blinks
    /// (`own_shapes`, in Apple's order; `skin[v]` whether vertex `v` is in the face's parts),
    /// seen through `on_skin`; `positions` the avatar at rest, `to_avatar`
    /// avatar units per mask millimetre. Nothing closes on a mask without
    /// eye holes or an avatar without its own blinks.
    pub fn new(
        own_shapes: &[Option<Vec<DVec3>>],
        (positions, skin, to_avatar): (&[DVec3], &[bool], f64),
        on_skin: &MaskOnSkin,
        personalized: &Blendshapes,
        (holes, closed_otherwise): (&[EyeHole], &[usize]),
    ) -> ClosedLids {
        let mut closed = ClosedLids {
            lids: Vec::new(),
            per_shape: vec![Vec::new(); Blendshape::ALL.len()],
        };
        let rest = personalized.neutral();
        let blinks: Vec<(&Vec<DVec3>, Vec<DVec3>)> =
            [Blendshape::EyeBlinkLeft, Blendshape::EyeBlinkRight]
                .iter()
                .filter_map(|b| own_shapes.get(b.index())?.as_ref())
                .map(|own| (own, on_skin.see(own)))
                .collect();
        for (h, hole) in holes.iter().enumerate() {
            if closed_otherwise.contains(&h) {
                continue;
            }
            let travel = |seen: &[DVec3]| -> f64 {
                hole.upper
                    .iter()
                    .chain(&hole.lower)
                    .filter_map(|&i| seen.get(i as usize))
                    .map(|d| d.length())
                    .sum()
            };
            let Some((own, _)) = blinks
                .iter()
                .map(|(own, seen)| (own, travel(seen)))
                .filter(|(_, t)| *t > 0.0)
                .max_by(|a, b| a.1.total_cmp(&b.1))
            else {
                continue;
            };
            let index = closed.lids.len();
            closed
                .lids
                .push(lid(own, positions, skin, MEETS_MM * to_avatar));
            for (j, b) in Blendshape::ALL.iter().enumerate() {
                let shape: Vec<DVec3> = rest
                    .iter()
                    .zip(personalized.delta(*b))
                    .map(|(p, q)| *p + *q)
                    .collect();
                if closes(hole, rest, &shape) {
                    closed.per_shape[j].push(index);
                }
            }
        }
        closed
    }

    /// (Shape, eye) pairs that close.
    pub fn count(&self) -> usize {
        self.per_shape.iter().map(Vec::len).sum()
    }

    /// Marks in `held` (one per avatar vertex) the lid vertices shape `j`
    /// (Apple's order) gives the avatar's own lid.
    pub fn hold(&self, j: usize, held: &mut [bool]) {
        let eyes = self.per_shape.get(j).map_or(&[][..], Vec::as_slice);
        for lid in eyes.iter().filter_map(|&e| self.lids.get(e)) {
            for &(v, _) in &lid.weights {
                if let Some(h) = held.get_mut(v as usize) {
                    *h = true;
                }
            }
        }
    }

    /// Gives every shape's displacement `full[j]` (all avatar vertices) the
    /// avatar's own lid of each eye it closes (module docs).
    pub fn apply(&self, full: &mut [Vec<DVec3>]) {
        for (d, eyes) in full.iter_mut().zip(&self.per_shape) {
            for lid in eyes.iter().filter_map(|&e| self.lids.get(e)) {
                for &(v, alpha) in &lid.weights {
                    let v = v as usize;
                    if let (Some(x), Some(b)) = (d.get_mut(v), lid.blink.get(v)) {
                        *x += alpha * (*b - *x);
                    }
                }
            }
        }
    }
}

/// The own blink `blink` as a [`Lid`] over the `skin` vertices (rest
/// `positions`; `meets` is [`MEETS_MM`] in avatar units; module docs).
fn lid(blink: &[DVec3], positions: &[DVec3], skin: &[bool], meets: f64) -> Lid {
    let smoothstep = |s: f64| {
        let s = s.clamp(0.0, 1.0);
        s * s * (3.0 - 2.0 * s)
    };
    let skin_vertices =
        || (0..blink.len().min(positions.len()).min(skin.len())).filter(|&v| skin[v]);
    let largest = skin_vertices()
        .map(|v| blink[v].length())
        .fold(0.0, f64::max);
    if largest <= 0.0 {
        return Lid {
            blink: blink.to_vec(),
            weights: Vec::new(),
        };
    }
    let share = |v: usize| blink[v].length() / largest;
    let closed = |v: usize| positions[v] + blink[v];
    let whole: Vec<DVec3> = skin_vertices()
        .filter(|&v| share(v) >= WHOLE_FROM)
        .map(closed)
        .collect();
    let (lo, hi) = whole.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let reach = 2.0 * meets;
    let weights = skin_vertices()
        .filter_map(|v| {
            let by_travel = smoothstep((share(v) - FADE_FROM) / (WHOLE_FROM - FADE_FROM));
            let p = closed(v);
            let near_box = p.cmpge(lo - reach).all() && p.cmple(hi + reach).all();
            let by_meeting = if by_travel < 1.0 && near_box && meets > 0.0 {
                let c = whole
                    .iter()
                    .map(|q| q.distance(p))
                    .fold(f64::INFINITY, f64::min);
                1.0 - smoothstep((c - meets) / meets)
            } else {
                0.0
            };
            let alpha = by_travel.max(by_meeting);
            (alpha > 0.0).then_some((v as u32, alpha))
        })
        .collect();
    Lid {
        blink: blink.to_vec(),
        weights,
    }
}
