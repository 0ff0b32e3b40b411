//! Morph target names to ARKit's 52 shapes.
//!
//! Every name goes through the one ARKit name parser
//! ([`Blendshape::parse`]: `eyeBlinkLeft`, `EyeBlinkLeft`, `eyeBlink_L`,
//! `blendShape1.eyeBlinkLeft`, …). Some rigs split a shape that ARKit keeps
//! whole into two halves (ICT-FaceKit's `browInnerUp_L` / `browInnerUp_R`,
//! `cheekPuff_L` / `cheekPuff_R`): a side suffix on a midline shape is such
//! a half, and the whole shape is the sum of both. Names that are not
//! ARKit's are kept as the avatar's own targets.

use super::model::Avatar;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Side};

/// What a morph target's name says it is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TargetName {
    /// One of ARKit's shapes, whole.
    Arkit(Blendshape),
    /// One half of a midline ARKit shape (`browInnerUp_L`): the shape is the
    /// sum of both halves.
    Half(Blendshape, Side),
    /// Not one of ARKit's names: one of the avatar's own targets.
    Other,
}

/// Reads a morph target's name.
pub fn parse_target_name(name: &str) -> TargetName {
    if let Ok(shape) = Blendshape::parse(name) {
        return TargetName::Arkit(shape);
    }
    // A side suffix on a shape that has no sides: a half.
    let trimmed = name.trim();
    let lower = trimmed.to_ascii_lowercase();
    for (suffixes, side) in [
        (["_l", "left", ".l"], Side::Left),
        (["_r", "right", ".r"], Side::Right),
    ] {
        for suffix in suffixes {
            if let Some(stem) = lower.strip_suffix(suffix)
                && let Ok(shape) = Blendshape::parse(&trimmed[..stem.len()])
                && shape.side() == Side::Centre
            {
                return TargetName::Half(shape, side);
            }
        }
    }
    TargetName::Other
}

/// For each of ARKit's 52 shapes (Apple's order), the `(mesh, target)`
/// pairs whose sum is that shape on the avatar: one for a whole target,
/// one per half for a split shape (on every mesh that has it), none for a
/// shape the avatar lacks.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArkitTargets(pub [Vec<(usize, usize)>; BLENDSHAPE_COUNT]);

impl ArkitTargets {
    /// The targets that carry `shape`.
    pub fn of(&self, shape: Blendshape) -> &[(usize, usize)] {
        &self.0[shape.index()]
    }

    /// ARKit's shapes the avatar has none of, in Apple's order.
    pub fn missing(&self) -> Vec<Blendshape> {
        Blendshape::ALL
            .into_iter()
            .filter(|s| self.0[s.index()].is_empty())
            .collect()
    }

    /// How many of the 52 the avatar has.
    pub fn found(&self) -> usize {
        BLENDSHAPE_COUNT - self.missing().len()
    }
}

/// Resolves every target name of `avatar` ([`parse_target_name`]). A mesh
/// with both a whole target and halves of one shape keeps the whole one.
pub fn arkit_targets(avatar: &Avatar) -> ArkitTargets {
    let mut out: [Vec<(usize, usize)>; BLENDSHAPE_COUNT] = std::array::from_fn(|_| Vec::new());
    for (m, mesh) in avatar.meshes().iter().enumerate() {
        let names: Vec<TargetName> = mesh
            .target_names
            .iter()
            .map(|n| parse_target_name(n))
            .collect();
        for shape in Blendshape::ALL {
            let whole = names.iter().position(|n| *n == TargetName::Arkit(shape));
            match whole {
                Some(t) => out[shape.index()].push((m, t)),
                None => out[shape.index()].extend(
                    names
                        .iter()
                        .enumerate()
                        .filter(|(_, n)| matches!(n, TargetName::Half(s, _) if *s == shape))
                        .map(|(t, _)| (m, t)),
                ),
            }
        }
    }
    ArkitTargets(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn whole_shapes_halves_and_others() {
        assert_eq!(
            parse_target_name("blendShape1.eyeBlink_L"),
            TargetName::Arkit(Blendshape::EyeBlinkLeft)
        );
        assert_eq!(
            parse_target_name("browInnerUp_L"),
            TargetName::Half(Blendshape::BrowInnerUp, Side::Left)
        );
        assert_eq!(
            parse_target_name("cheekPuffRight"),
            TargetName::Half(Blendshape::CheekPuff, Side::Right)
        );
        assert_eq!(parse_target_name("Fcl_ALL_Angry"), TargetName::Other);
        assert_eq!(parse_target_name("browDown"), TargetName::Other);
    }
}
