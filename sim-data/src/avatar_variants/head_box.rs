//! `head-box`: one mesh for the whole character, as Microsoft Rocketbox's
//! avatars with HeadBox's blendshapes come: its primitives are the body
//! and the head, and the head's primitive holds the eyeballs, teeth, gums
//! and tongue besides the skin, as loose pieces of one vertex list. Its
//! targets are HeadBox's: ARKit's 52 behind a numbered prefix
//! (`AK_25_JawOpen`), then FACS action units (`AU_26_JawDrop`) and
//! visemes (`AA_VI_02_aa`) that move the face too, mixes of ARKit's
//! shapes a reader must not take for them.
//!
//! Primitives of mesh `Character`: 0 body (no motion in any target), 1
//! head (skin, ears, sockets, mouth lining, both eyeballs, teeth, gums,
//! tongue, irises and pupils).

use super::body::{HEAD_OFFSET, body};
use super::full_body::VISEMES;
use super::parts::{
    ShapeMix, base, base_part, bounds, dpart, glb_of, merge, plain_truth, with_mixes,
};
use super::truth::{Piece, VariantTruth};
use super::vendor_export::vendor_name;
use glam::DVec3;
use likeness::Blendshape;
use likeness::avatar::{Avatar, AvatarMesh, AvatarPart};

/// HeadBox-style action units, each one ARKit shape or a mix (FACS:
/// Ekman & Friesen 1978): brow raisers, the lid tightener, the lip corner
/// puller, the jaw drop.
pub const ACTION_UNITS: [(&str, &[(Blendshape, f32)]); 5] = [
    ("AU_01_InnerBrowRaiser", &[(Blendshape::BrowInnerUp, 1.0)]),
    (
        "AU_02_OuterBrowRaiser",
        &[
            (Blendshape::BrowOuterUpLeft, 1.0),
            (Blendshape::BrowOuterUpRight, 1.0),
        ],
    ),
    (
        "AU_07_LidTightener",
        &[
            (Blendshape::EyeSquintLeft, 1.0),
            (Blendshape::EyeSquintRight, 1.0),
        ],
    ),
    (
        "AU_12_LipCornerPuller",
        &[
            (Blendshape::MouthSmileLeft, 1.0),
            (Blendshape::MouthSmileRight, 1.0),
        ],
    ),
    ("AU_26_JawDrop", &[(Blendshape::JawOpen, 1.0)]),
];

/// HeadBox's names for the visemes of [`VISEMES`], in their order.
pub const VISEME_NAMES: [&str; 5] = [
    "AA_VI_01_aa",
    "AA_VI_02_E",
    "AA_VI_03_I",
    "AA_VI_04_O",
    "AA_VI_05_U",
];

/// The extra targets' names and mixes: the action units, then the visemes.
fn extras() -> Vec<(&'static str, ShapeMix)> {
    let visemes = VISEME_NAMES.iter().zip(VISEMES).map(|(n, (_, m))| (*n, m));
    ACTION_UNITS.into_iter().chain(visemes).collect()
}

/// The default avatar's parts that make the head's primitive, in the
/// order merged: skin, ears, sockets, lining, the eyes (left, right), the
/// teeth (upper, lower), the gums, the tongue, the irises and pupils.
fn head_pieces() -> Vec<usize> {
    let b = base();
    [b.skin, b.ears, b.sockets, b.mouth_cavity]
        .into_iter()
        .chain(b.eyes)
        .chain(b.teeth)
        .chain(b.gums)
        .chain([b.tongue])
        .chain(b.irises.into_iter().flatten())
        .collect()
}

/// The avatar: one mesh of two primitives, the head lifted onto the body.
fn avatar() -> Avatar {
    let mixes: Vec<ShapeMix> = extras().into_iter().map(|(_, m)| m).collect();
    let pieces: Vec<AvatarPart> = head_pieces()
        .into_iter()
        .map(|k| {
            let mut p = with_mixes(base_part(k, 0, 1), &mixes);
            p.positions.iter_mut().for_each(|v| *v += HEAD_OFFSET);
            p
        })
        .collect();
    let head = merge("head", 0, 1, &pieces);
    let (bp, bt) = body();
    let still = vec![vec![DVec3::ZERO; bp.len()]; head.targets.len()];
    let body = dpart("body", 0, 0, &bp, &bt, &still);
    let names = Blendshape::ALL
        .iter()
        .map(|s| vendor_name("Head", s.name()))
        .chain(extras().into_iter().map(|(n, _)| n.to_string()))
        .collect();
    let mesh = AvatarMesh {
        name: Some("Character".to_string()),
        target_names: names,
    };
    Avatar::new(vec![mesh], vec![body, head]).expect("the head-box variant's parts make an avatar")
}

/// The GLB and its truth.
pub fn head_box() -> (Vec<u8>, VariantTruth) {
    let avatar = avatar();
    let mut truth = plain_truth(&avatar, 1, base().true_correspondence.len());
    // Pieces 4 and 5 are the eyes, 6 and 7 the teeth ([`head_pieces`]).
    let sizes: Vec<usize> = head_pieces()
        .into_iter()
        .map(|k| base().avatar.parts()[k].positions.len())
        .collect();
    let start = |i: usize| sizes[..i].iter().sum::<usize>();
    let piece = |i: usize| Piece {
        part: 1,
        vertices: start(i)..start(i + 1),
    };
    truth.eyeballs = [piece(4), piece(5)];
    truth.teeth = Some(Piece {
        part: 1,
        vertices: start(6)..start(8),
    });
    truth.jaw_moved_vertices = sizes[7];
    truth.extra_targets = extras().into_iter().map(|(n, _)| n).collect();
    truth.world_bounds = bounds(&avatar, |p| p);
    (glb_of(&avatar, None), truth)
}
