//! Morph target names to ARKit's 52 shapes.
//!
//! **The rule.** A name is cut into words: at every character that is not a
//! letter or a digit, where a lower-case letter meets a capital, and where
//! letters meet digits (`AK_25_JawOpen` → `ak 25 jaw open`,
//! `blendShape1.eyeBlink_L` → `blend shape 1 eye blink l`). A last word `l`
//! or `r` is the side, `left` or `right`. The name is ARKit's shape whose
//! name, without case, is the longest run of words at its end joined
//! together; the words before it are a prefix and are ignored. A side at
//! the end of a shape ARKit keeps whole (`browInnerUp_L`, `cheekPuffRight`)
//! makes that target one half of it: the shape is the sum of both halves
//! (ICT-FaceKit splits them so). A prefix that itself holds one of ARKit's
//! names (`jawOpen_mouthClose`, a corrective of two shapes) makes the
//! target none of them, and a name with anything after the shape's words
//! (`eyeBlinkLeft.001`, `jawOpen_old`) is not ARKit's: both stay the
//! avatar's own targets.
//!
//! | convention | example | read as |
//! |---|---|---|
//! | Apple's names (`ARFaceAnchor.BlendShapeLocation`'s documentation) | `eyeBlinkLeft` | eyeBlinkLeft |
//! | Apple's raw keys, ICT-FaceKit | `eyeBlink_L`, `mouthSmile_R` | eyeBlinkLeft, mouthSmileRight |
//! | capitalised (Live Link Face's CSV, Unreal) | `EyeBlinkLeft` | eyeBlinkLeft |
//! | any case, snake case | `EYEBLINKLEFT`, `eye_blink_left` | eyeBlinkLeft |
//! | Blender's side suffix | `eyeBlink.L` | eyeBlinkLeft |
//! | Maya's blendShape node, namespaces | `blendShape1.eyeBlinkLeft`, `face:jawOpen` | eyeBlinkLeft, jawOpen |
//! | vendor prefixes | `ARKit_jawOpen`, `BS_jawOpen`, `bs.jawOpen` | jawOpen |
//! | numbered prefixes (HeadBox, Character Creator's A-series) | `AK_25_JawOpen`, `A25_Jaw_Open` | jawOpen |
//! | halves of a whole shape (ICT-FaceKit) | `browInnerUp_L`, `cheekPuff_R` | half of browInnerUp, cheekPuff |
//! | correctives, numbered copies, others | `jawOpen_mouthClose`, `eyeBlinkLeft.001`, `viseme_aa` | the avatar's own |
//!
//! **More than one target for a shape** on one mesh
//! ([`arkit_targets`]): a whole target is taken before halves, a name
//! with no prefix before a prefixed one, and among equals the first in the
//! mesh's order. The others stay the avatar's own targets, and each is
//! listed ([`PassedOver`]) with the target taken instead and why, for the
//! CLI to print and `--json` to give.

use super::model::Avatar;
use crate::arkit::{BLENDSHAPE_COUNT, Blendshape, Side};
use std::fmt;

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

impl TargetName {
    /// The ARKit shape the name carries (whole or half), if any.
    pub fn shape(self) -> Option<Blendshape> {
        match self {
            TargetName::Arkit(s) | TargetName::Half(s, _) => Some(s),
            TargetName::Other => None,
        }
    }
}

/// A name's words, lower case (the module's rule): cut at every character
/// that is neither a letter nor a digit, where a lower-case letter meets a
/// capital, and where letters meet digits.
fn words(name: &str) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    let mut word = String::new();
    let mut last: Option<char> = None;
    for c in name.chars() {
        if !c.is_alphanumeric() {
            out.extend((!word.is_empty()).then(|| std::mem::take(&mut word)));
            last = None;
            continue;
        }
        if let Some(p) = last {
            let cut = (p.is_lowercase() && c.is_uppercase())
                || (p.is_ascii_digit() != c.is_ascii_digit());
            if cut && !word.is_empty() {
                out.push(std::mem::take(&mut word));
            }
        }
        word.extend(c.to_lowercase());
        last = Some(c);
    }
    out.extend((!word.is_empty()).then_some(word));
    out
}

/// The side a last word names: `l`, `left`, `r`, `right`.
fn side_word(word: &str) -> Option<Side> {
    match word {
        "l" | "left" => Some(Side::Left),
        "r" | "right" => Some(Side::Right),
        _ => None,
    }
}

/// The ARKit shape whose name, without case, is `joined`.
fn shape_named(joined: &str) -> Option<Blendshape> {
    Blendshape::ALL
        .into_iter()
        .find(|s| s.name().eq_ignore_ascii_case(joined))
}

/// What the words `w` say, read at their end: the shape (whole or half)
/// and how many words before it are a prefix.
fn read_words(w: &[String]) -> Option<(TargetName, usize)> {
    let side = w.last().and_then(|l| side_word(l));
    for start in 0..w.len() {
        let tail = &w[start..];
        // The shape's own words, the side spelt out: `eye blink l`.
        let mut joined: String = tail.concat();
        if let (Some(side), Some(last)) = (side, tail.last()) {
            joined.truncate(joined.len() - last.len());
            joined.push_str(if side == Side::Left { "left" } else { "right" });
        }
        if let Some(shape) = shape_named(&joined) {
            return Some((TargetName::Arkit(shape), start));
        }
        // A side on a shape ARKit keeps whole: a half of it.
        if let (Some(side), [stem @ .., _]) = (side, tail)
            && let Some(shape) = shape_named(&stem.concat())
            && shape.side() == Side::Centre
        {
            return Some((TargetName::Half(shape, side), start));
        }
    }
    None
}

/// Whether some run of the words `w` is one of ARKit's names (a
/// corrective's prefix: `jaw open` in `jawOpen_mouthClose`).
fn holds_a_shape(w: &[String]) -> bool {
    (0..w.len()).any(|end| matches!(read_words(&w[..=end]), Some((TargetName::Arkit(_), _))))
}

/// How a name was read: what it says, and whether ARKit's name came after
/// a prefix (`AK_25_JawOpen`) or alone (`jawOpen`, `eyeBlink_L`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NameReading {
    /// What the name says.
    pub name: TargetName,
    /// Whether words stood before ARKit's name.
    pub prefixed: bool,
}

/// Reads a morph target's name (the module's rule).
pub fn read_target_name(name: &str) -> NameReading {
    let w = words(name);
    match read_words(&w) {
        Some((read, prefix)) if !holds_a_shape(&w[..prefix]) => NameReading {
            name: read,
            prefixed: prefix > 0,
        },
        _ => NameReading {
            name: TargetName::Other,
            prefixed: false,
        },
    }
}

/// What a morph target's name says it is (the module's rule).
pub fn parse_target_name(name: &str) -> TargetName {
    read_target_name(name).name
}

/// Why a target that reads as one of ARKit's shapes was not taken for it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PassReason {
    /// The mesh has the whole shape, and this is a half of it.
    WholeOnMesh,
    /// The target taken has ARKit's name with no prefix; this one has one.
    PlainerName,
    /// The target taken reads the same way and comes first on the mesh.
    Earlier,
}

impl fmt::Display for PassReason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PassReason::WholeOnMesh => "the mesh has the whole shape, and this is a half of it",
            PassReason::PlainerName => "the target taken has ARKit's name without a prefix",
            PassReason::Earlier => "the target taken reads the same and comes first on the mesh",
        })
    }
}

/// A target whose name reads as one of ARKit's shapes but which another
/// target on its mesh carries instead: it stays one of the avatar's own.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PassedOver {
    /// The mesh (the avatar's order).
    pub mesh: usize,
    /// The target passed over (index within the mesh) and its name.
    pub target: (usize, String),
    /// The shape its name reads as.
    pub shape: Blendshape,
    /// The target taken for the shape instead, and its name.
    pub taken: (usize, String),
    /// Why this one was not.
    pub why: PassReason,
}

impl fmt::Display for PassedOver {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "mesh {} target {} {:?} reads as {} but {:?} (target {}) is taken: {}; it stays one of the avatar's own targets",
            self.mesh,
            self.target.0,
            self.target.1,
            self.shape,
            self.taken.1,
            self.taken.0,
            self.why
        )
    }
}

/// Which target of one mesh carries each shape (the module's rule for
/// more than one): `taken[t]` is what target `t` is taken as (`Other`
/// where it carries no shape), and the targets passed over.
pub fn resolve_mesh(mesh: usize, names: &[String]) -> (Vec<TargetName>, Vec<PassedOver>) {
    let read: Vec<NameReading> = names.iter().map(|n| read_target_name(n)).collect();
    let mut taken = vec![TargetName::Other; names.len()];
    let mut passed = Vec::new();
    for shape in Blendshape::ALL {
        let of = |t: &usize| read[*t].name.shape() == Some(shape);
        let candidates: Vec<usize> = (0..names.len()).filter(of).collect();
        let wholes: Vec<usize> = candidates
            .iter()
            .copied()
            .filter(|&t| read[t].name == TargetName::Arkit(shape))
            .collect();
        // The whole target first, then each side's half: the plainest name,
        // then the first.
        let groups: Vec<Vec<usize>> = match wholes.is_empty() {
            false => vec![wholes.clone()],
            true => [Side::Left, Side::Right]
                .map(|side| {
                    candidates
                        .iter()
                        .copied()
                        .filter(|&t| read[t].name == TargetName::Half(shape, side))
                        .collect()
                })
                .into(),
        };
        for group in groups {
            let Some(&chosen) = group.iter().min_by_key(|&&t| (read[t].prefixed, t)) else {
                continue;
            };
            taken[chosen] = read[chosen].name;
            for &t in group.iter().filter(|&&t| t != chosen) {
                let why = match read[t].prefixed && !read[chosen].prefixed {
                    true => PassReason::PlainerName,
                    false => PassReason::Earlier,
                };
                passed.push((t, chosen, shape, why));
            }
        }
        if let Some(&whole) = wholes.iter().find(|&&t| taken[t] != TargetName::Other) {
            for &t in candidates.iter().filter(|t| !wholes.contains(t)) {
                passed.push((t, whole, shape, PassReason::WholeOnMesh));
            }
        }
    }
    passed.sort_by_key(|p| p.0);
    let passed = passed
        .into_iter()
        .map(|(t, chosen, shape, why)| PassedOver {
            mesh,
            target: (t, names[t].clone()),
            shape,
            taken: (chosen, names[chosen].clone()),
            why,
        })
        .collect();
    (taken, passed)
}

/// For each of ARKit's 52 shapes (Apple's order), the `(mesh, target)`
/// pairs whose sum is that shape on the avatar: one for a whole target,
/// one per half for a split shape (on every mesh that has it), none for a
/// shape the avatar lacks; and the targets passed over for another.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ArkitTargets {
    taken: [Vec<(usize, usize)>; BLENDSHAPE_COUNT],
    /// What each target of each mesh is taken as ([`resolve_mesh`]).
    read: Vec<Vec<TargetName>>,
    passed_over: Vec<PassedOver>,
}

impl ArkitTargets {
    /// The targets that carry `shape`.
    pub fn of(&self, shape: Blendshape) -> &[(usize, usize)] {
        &self.taken[shape.index()]
    }

    /// What target `target` of mesh `mesh` is taken as: one of ARKit's
    /// shapes whole, half of one, or `Other` (not ARKit's, or passed over
    /// for another target).
    pub fn taken_as(&self, mesh: usize, target: usize) -> TargetName {
        let read = self.read.get(mesh).and_then(|m| m.get(target));
        read.copied().unwrap_or(TargetName::Other)
    }

    /// The shape target `target` of mesh `mesh` is taken for, if any.
    pub fn shape_of(&self, mesh: usize, target: usize) -> Option<Blendshape> {
        self.taken_as(mesh, target).shape()
    }

    /// ARKit's shapes the avatar has none of, in Apple's order.
    pub fn missing(&self) -> Vec<Blendshape> {
        Blendshape::ALL
            .into_iter()
            .filter(|s| self.taken[s.index()].is_empty())
            .collect()
    }

    /// How many of the 52 the avatar has.
    pub fn found(&self) -> usize {
        BLENDSHAPE_COUNT - self.missing().len()
    }

    /// The avatar's own `shape`: every vertex's summed displacement under
    /// the targets taken for it (zero where the avatar lacks it).
    pub fn displacement(&self, avatar: &Avatar, shape: Blendshape) -> Vec<glam::Vec3> {
        avatar.summed_displacement(self.of(shape))
    }

    /// Targets whose names read as one of ARKit's shapes that another
    /// target carries instead, by mesh and target.
    pub fn passed_over(&self) -> &[PassedOver] {
        &self.passed_over
    }
}

/// Resolves every target name of `avatar`, mesh by mesh
/// ([`resolve_mesh`]).
pub fn arkit_targets(avatar: &Avatar) -> ArkitTargets {
    let mut taken: [Vec<(usize, usize)>; BLENDSHAPE_COUNT] = std::array::from_fn(|_| Vec::new());
    let (mut read, mut passed_over) = (Vec::new(), Vec::new());
    for (m, mesh) in avatar.meshes().iter().enumerate() {
        let (mesh_read, passed) = resolve_mesh(m, &mesh.target_names);
        for (t, name) in mesh_read.iter().enumerate() {
            if let Some(shape) = name.shape() {
                taken[shape.index()].push((m, t));
            }
        }
        read.push(mesh_read);
        passed_over.extend(passed);
    }
    ArkitTargets {
        taken,
        read,
        passed_over,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn arkit(name: &str) -> TargetName {
        TargetName::Arkit(Blendshape::parse(name).unwrap())
    }

    #[test]
    fn every_convention_in_the_table_reads_as_documented() {
        for (name, read) in [
            ("eyeBlinkLeft", arkit("eyeBlinkLeft")),
            ("eyeBlink_L", arkit("eyeBlinkLeft")),
            ("mouthSmile_R", arkit("mouthSmileRight")),
            ("EyeBlinkLeft", arkit("eyeBlinkLeft")),
            ("EYEBLINKLEFT", arkit("eyeBlinkLeft")),
            ("eye_blink_left", arkit("eyeBlinkLeft")),
            ("eyeBlink.L", arkit("eyeBlinkLeft")),
            ("blendShape1.eyeBlinkLeft", arkit("eyeBlinkLeft")),
            ("blendShape1.eyeBlink_L", arkit("eyeBlinkLeft")),
            ("face:jawOpen", arkit("jawOpen")),
            ("ARKit_jawOpen", arkit("jawOpen")),
            ("BS_jawOpen", arkit("jawOpen")),
            ("bs.jawOpen", arkit("jawOpen")),
            ("AK_25_JawOpen", arkit("jawOpen")),
            ("AK_14_EyeBlinkLeft", arkit("eyeBlinkLeft")),
            ("A25_Jaw_Open", arkit("jawOpen")),
            ("A14_Eye_Blink_Left", arkit("eyeBlinkLeft")),
            ("jawLeft", arkit("jawLeft")),
            ("mouth_Right", arkit("mouthRight")),
            (
                "browInnerUp_L",
                TargetName::Half(Blendshape::BrowInnerUp, Side::Left),
            ),
            (
                "cheekPuffRight",
                TargetName::Half(Blendshape::CheekPuff, Side::Right),
            ),
            (
                "AK_01_BrowInnerUp_R",
                TargetName::Half(Blendshape::BrowInnerUp, Side::Right),
            ),
            ("jawOpen_mouthClose", TargetName::Other),
            ("eyeBlink_L_eyeSquint_L", TargetName::Other),
            ("eyeBlinkLeft.001", TargetName::Other),
            ("jawOpen_old", TargetName::Other),
            ("viseme_aa", TargetName::Other),
            ("Fcl_ALL_Angry", TargetName::Other),
            ("Fcl_EYE_Close_L", TargetName::Other),
            ("AU_43_EyesClosed", TargetName::Other),
            ("AA_VI_01_PP", TargetName::Other),
            ("browDown", TargetName::Other),
            ("mouthSmile", TargetName::Other),
            ("", TargetName::Other),
        ] {
            assert_eq!(parse_target_name(name), read, "{name}");
        }
        assert!(!read_target_name("eyeBlink_L").prefixed);
        assert!(!read_target_name("EYEBLINKLEFT").prefixed);
        assert!(read_target_name("AK_25_JawOpen").prefixed);
        assert!(read_target_name("blendShape1.jawOpen").prefixed);
    }

    #[test]
    fn every_name_apple_spells_reads_alone_and_behind_every_prefix() {
        for shape in Blendshape::ALL {
            for name in [shape.name().to_string(), shape.arkit_key()] {
                let capital = name[..1].to_uppercase() + &name[1..];
                for prefixed in [
                    name.clone(),
                    capital.clone(),
                    name.to_uppercase(),
                    format!("AK_{:02}_{capital}", shape.index()),
                    format!("ARKit_{name}"),
                    format!("BS_{name}"),
                    format!("blendShape2.{name}"),
                ] {
                    assert_eq!(
                        parse_target_name(&prefixed),
                        TargetName::Arkit(shape),
                        "{prefixed}"
                    );
                }
            }
        }
    }

    fn names(list: &[&str]) -> Vec<String> {
        list.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn of_two_targets_for_a_shape_the_plainer_then_the_first_is_taken() {
        let list = names(&[
            "AK_25_JawOpen",
            "jawOpen",
            "EyeBlinkLeft",
            "eyeBlink_L",
            "smile",
        ]);
        let (taken, passed) = resolve_mesh(3, &list);
        assert_eq!(
            taken,
            [
                TargetName::Other,
                arkit("jawOpen"),
                arkit("eyeBlinkLeft"),
                TargetName::Other,
                TargetName::Other,
            ]
        );
        assert_eq!(passed.len(), 2);
        assert_eq!(passed[0].target, (0, "AK_25_JawOpen".into()));
        assert_eq!(passed[0].taken, (1, "jawOpen".into()));
        assert_eq!(passed[0].why, PassReason::PlainerName);
        assert_eq!((passed[1].target.0, passed[1].taken.0), (3, 2));
        assert_eq!(passed[1].why, PassReason::Earlier);
        assert_eq!(passed[1].shape, Blendshape::EyeBlinkLeft);
        let line = passed[0].to_string();
        assert!(
            line.contains("mesh 3 target 0") && line.contains("\"jawOpen\""),
            "{line}"
        );
    }

    #[test]
    fn halves_are_taken_only_where_the_mesh_lacks_the_whole_shape() {
        let list = names(&[
            "browInnerUp_L",
            "browInnerUp",
            "browInnerUp_R",
            "cheekPuff_L",
            "cheekPuff_R",
        ]);
        let (taken, passed) = resolve_mesh(0, &list);
        assert_eq!(taken[1], arkit("browInnerUp"));
        assert_eq!((taken[0], taken[2]), (TargetName::Other, TargetName::Other));
        assert_eq!(
            taken[3],
            TargetName::Half(Blendshape::CheekPuff, Side::Left)
        );
        assert_eq!(
            taken[4],
            TargetName::Half(Blendshape::CheekPuff, Side::Right)
        );
        let why: Vec<(usize, PassReason)> = passed.iter().map(|p| (p.target.0, p.why)).collect();
        assert_eq!(
            why,
            [(0, PassReason::WholeOnMesh), (2, PassReason::WholeOnMesh)]
        );
    }
}
