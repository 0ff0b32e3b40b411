//! The generic expression anatomy: how each of ARKit's 52 shapes moves the
//! face, as a small table of smooth handles plus four special motions.
//!
//! A *handle* moves the skin around a centre in the parameter plane by a
//! displacement, fading with the compact kernel of [`crate::regions::kernel`]
//! over an elliptic radius, restricted to a [`Region`]. Magnitudes are the
//! generic adult face's, in millimetres, chosen from the extent of the facial
//! action units that ARKit's shapes name (Ekman & Friesen's FACS: a smile
//! moves the mouth corner about 1 cm up and out, a brow raise lifts the brow
//! 6–8 mm, a squint lifts the lower lid 2–3 mm). They are plausible, not
//! measured; what matters for testing is that they are smooth, local, and
//! move the right parts.
//!
//! The special motions are those a handle cannot express: a blink brings
//! each upper-lid vertex exactly onto the lower lid (or, in the template
//! variant of [`crate::template::TemplateVariant::AppleLike`], to a fixed
//! gap short of it); the jaw rotates about the
//! temporomandibular hinge; a jaw shift translates the mandible; mouthClose
//! closes the lips against the opened jaw (ARKit's definition: it is only
//! meaningful together with jawOpen).

use crate::regions::Region;
use glam::{DMat3, DVec3};
use likeness::{BLENDSHAPE_COUNT, Blendshape};

/// One smooth local displacement.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Handle {
    /// Centre in the parameter plane (m).
    pub centre: [f64; 2],
    /// Kernel radius along u and v (m).
    pub radius: [f64; 2],
    /// Displacement at the centre at weight one (m).
    pub displacement: DVec3,
    /// Where it may act.
    pub region: Region,
}

/// Motions that are not a sum of handles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Special {
    /// Nothing beyond the handles.
    None,
    /// Eyelid closure of the eye on `side` (0 = left).
    Blink {
        /// Which eye.
        side: usize,
        /// Where the lids meet, as a fraction of the opening from the lower
        /// lid (the upper lid travels most: about 0.25).
        meet: f64,
        /// Forward bulge of the closing upper lid at half closure, where it
        /// slides over the cornea (m). Only the subjects' nonlinear motion
        /// uses it.
        bulge: f64,
        /// How far above the upper lid the skin follows (m).
        upper_reach: f64,
        /// How far below the lower lid the skin follows (m).
        lower_reach: f64,
        /// How far apart the lids stop (m): 0, they meet, for the generic
        /// template and every subject; [`crate::template::APPLE_BLINK_GAP`]
        /// for the template variant that stops short as Apple's does.
        gap: f64,
    },
    /// Mandible rotation about the hinge axis (x) by `angle` radians.
    JawRotation {
        /// Opening angle at weight one (rad).
        angle: f64,
    },
    /// Mandible translation (m) at weight one.
    JawTranslation {
        /// Offset of the mandible.
        offset: DVec3,
    },
    /// Lips close against the jaw opening: the lower lip takes back
    /// `1 − upper_share` of the jaw's motion, the upper lip comes down the rest.
    MouthClose {
        /// Share of the closure done by the upper lip.
        upper_share: f64,
    },
}

/// How one blendshape moves the face.
#[derive(Clone, Debug, PartialEq)]
pub struct ShapeSpec {
    /// Smooth local displacements.
    pub handles: Vec<Handle>,
    /// A motion beyond the handles.
    pub special: Special,
}

/// The mandible's joint: opening by `angle` turns the mandible about the x
/// axis through `hinge` while the condyles glide forward and down the
/// articular eminence by `glide` per radian, so a point `p` goes to
/// `R_x(angle) (p − hinge) + hinge + angle · glide` (rotation with
/// condylar translation, as the jaw opens: Posselt 1952; Ferrario et al.
/// 1996).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct JawJoint {
    /// Centre of the condyles' rotation at rest (m).
    pub hinge: DVec3,
    /// Condylar translation per radian of opening (m/rad).
    pub glide: DVec3,
}

impl JawJoint {
    /// Where the mandible takes `p` when the jaw opens by `angle` (rad).
    pub fn open(&self, p: DVec3, angle: f64) -> DVec3 {
        DMat3::from_rotation_x(angle) * (p - self.hinge) + self.hinge + angle * self.glide
    }
}

/// Temporomandibular hinge of the generic face (m): the condyles' centre,
/// placed from the lower incisors' tip (0, −52, 23.5) mm by Bonwill's
/// triangle (about 10 cm from the incisors to each condyle, the condyles
/// 10 cm apart, so 87 mm in the midsagittal plane) tilted by Balkwill's
/// angle (26° to the occlusal plane, itself about 10° to the Frankfort
/// horizontal): 47 mm above and 74 mm behind the incisors. The chin front
/// (pogonion) is then about 100 mm from it.
pub const HINGE: DVec3 = DVec3::new(0.0, -0.005, -0.050);

/// How far the condyles glide per radian of opening (m/rad): down the
/// articular eminence at 35° below the horizontal (its mean inclination
/// to the Frankfort plane is 30–40°), 8 mm over the generic opening of
/// [`JAW_OPEN_ANGLE`]. Condylar translation is 15–20 mm at a maximal
/// opening of 45–50 mm between the incisors, about linear in the opening
/// (Ferrario et al. 1996; Travers et al. 2000); the generic opening is
/// about 31 mm.
pub const GLIDE: DVec3 = DVec3::new(
    0.0,
    -0.008 * 0.573_576 / JAW_OPEN_ANGLE,
    0.008 * 0.819_152 / JAW_OPEN_ANGLE,
);

/// The generic face's jaw joint.
pub const GENERIC_JAW: JawJoint = JawJoint {
    hinge: HINGE,
    glide: GLIDE,
};

/// Generic jaw opening at weight one (rad): 0.36 rad ≈ 20.6°. With the
/// glide the lower incisors part by about 31 mm and the chin front moves
/// about 35 mm, down and back alike; adult maximal opening is 40–60 mm
/// between the incisors.
pub const JAW_OPEN_ANGLE: f64 = 0.36;

fn handle(region: Region, centre_mm: [f64; 2], radius_mm: [f64; 2], d_mm: [f64; 3]) -> Handle {
    Handle {
        centre: centre_mm.map(|c| c * 1e-3),
        radius: radius_mm.map(|r| r * 1e-3),
        displacement: DVec3::from_array(d_mm) * 1e-3,
        region,
    }
}

impl Handle {
    /// The same handle on the other side of the face.
    pub fn mirrored(&self) -> Handle {
        let region = match self.region {
            Region::UpperLid(s) => Region::UpperLid(1 - s),
            Region::LowerLid(s) => Region::LowerLid(1 - s),
            other => other,
        };
        Handle {
            centre: [-self.centre[0], self.centre[1]],
            radius: self.radius,
            displacement: DVec3::new(
                -self.displacement.x,
                self.displacement.y,
                self.displacement.z,
            ),
            region,
        }
    }
}

impl ShapeSpec {
    fn handles(handles: Vec<Handle>) -> ShapeSpec {
        ShapeSpec {
            handles,
            special: Special::None,
        }
    }

    /// The same motion on the other side of the face.
    pub fn mirrored(&self) -> ShapeSpec {
        let special = match self.special {
            Special::Blink {
                side,
                meet,
                bulge,
                upper_reach,
                lower_reach,
                gap,
            } => Special::Blink {
                side: 1 - side,
                meet,
                bulge,
                upper_reach,
                lower_reach,
                gap,
            },
            Special::JawTranslation { offset } => Special::JawTranslation {
                offset: DVec3::new(-offset.x, offset.y, offset.z),
            },
            other => other,
        };
        ShapeSpec {
            handles: self.handles.iter().map(Handle::mirrored).collect(),
            special,
        }
    }
}

/// Both a handle and its mirror image.
fn sym(h: Handle) -> [Handle; 2] {
    [h, h.mirrored()]
}

/// The left-side (+x) version of a sided shape, or the one version of a
/// centre shape. Centres are in mm from the face origin; the left eye is at
/// (32.5, 28), the left mouth corner at (25, −47).
fn left_or_centre(shape: Blendshape) -> ShapeSpec {
    use Blendshape as B;
    use Region::{Any, LowerLid, LowerLip, UpperLid, UpperLip};
    let hs = ShapeSpec::handles;
    match shape {
        B::EyeBlinkLeft => ShapeSpec {
            handles: vec![],
            special: Special::Blink {
                side: 0,
                meet: 0.25,
                bulge: 0.0012,
                upper_reach: 0.013,
                lower_reach: 0.007,
                gap: 0.0,
            },
        },
        B::EyeLookDownLeft => hs(vec![
            handle(UpperLid(0), [32.5, 33.0], [17.0, 10.0], [0.0, -2.5, 0.3]),
            handle(LowerLid(0), [32.5, 23.0], [16.0, 8.0], [0.0, -1.2, 0.0]),
        ]),
        B::EyeLookInLeft => hs(vec![
            handle(UpperLid(0), [32.5, 30.0], [17.0, 10.0], [-1.2, 0.0, 0.0]),
            handle(LowerLid(0), [32.5, 25.0], [16.0, 8.0], [-1.0, 0.0, 0.0]),
        ]),
        B::EyeLookOutLeft => hs(vec![
            handle(UpperLid(0), [32.5, 30.0], [17.0, 10.0], [1.2, 0.0, 0.0]),
            handle(LowerLid(0), [32.5, 25.0], [16.0, 8.0], [1.0, 0.0, 0.0]),
        ]),
        B::EyeLookUpLeft => hs(vec![
            handle(UpperLid(0), [32.5, 33.0], [17.0, 11.0], [0.0, 2.0, 0.0]),
            handle(LowerLid(0), [32.5, 24.0], [16.0, 7.0], [0.0, 0.8, 0.0]),
            handle(Any, [32.0, 45.0], [20.0, 10.0], [0.0, 0.8, 0.0]),
        ]),
        B::EyeSquintLeft => hs(vec![
            handle(LowerLid(0), [32.5, 23.0], [17.0, 9.0], [0.0, 2.5, 0.8]),
            handle(UpperLid(0), [32.5, 33.0], [16.0, 8.0], [0.0, -1.0, 0.0]),
            handle(Any, [50.0, 25.0], [10.0, 14.0], [-1.0, 0.5, 0.0]),
        ]),
        B::EyeWideLeft => hs(vec![
            handle(UpperLid(0), [32.5, 34.0], [17.0, 11.0], [0.0, 2.8, 0.3]),
            handle(LowerLid(0), [32.5, 24.0], [15.0, 7.0], [0.0, -0.8, 0.0]),
        ]),
        B::JawForward => ShapeSpec {
            handles: vec![],
            special: Special::JawTranslation {
                offset: DVec3::new(0.0, -0.001, 0.006),
            },
        },
        B::JawLeft => ShapeSpec {
            handles: vec![],
            special: Special::JawTranslation {
                offset: DVec3::new(0.008, 0.0, 0.0),
            },
        },
        B::JawOpen => ShapeSpec {
            handles: vec![],
            special: Special::JawRotation {
                angle: JAW_OPEN_ANGLE,
            },
        },
        B::MouthClose => ShapeSpec {
            handles: vec![],
            special: Special::MouthClose { upper_share: 0.25 },
        },
        B::MouthFunnel => {
            let mut h = vec![
                handle(UpperLip, [0.0, -47.0], [26.0, 10.0], [0.0, 2.0, 7.0]),
                handle(LowerLip, [0.0, -47.0], [26.0, 10.0], [0.0, -2.5, 7.0]),
            ];
            h.extend(sym(handle(
                Any,
                [25.0, -47.0],
                [10.0, 10.0],
                [-5.0, 0.0, 2.0],
            )));
            hs(h)
        }
        B::MouthPucker => {
            let mut h = vec![
                handle(UpperLip, [0.0, -47.0], [26.0, 9.0], [0.0, -0.5, 9.0]),
                handle(LowerLip, [0.0, -47.0], [26.0, 9.0], [0.0, 0.5, 9.0]),
            ];
            h.extend(sym(handle(
                Any,
                [25.0, -47.0],
                [11.0, 11.0],
                [-8.0, 0.0, 3.0],
            )));
            hs(h)
        }
        B::MouthLeft => hs(vec![handle(
            Any,
            [0.0, -47.0],
            [40.0, 18.0],
            [9.0, 0.0, -1.0],
        )]),
        B::MouthSmileLeft => hs(vec![
            handle(Any, [25.0, -47.0], [17.0, 16.0], [6.0, 8.0, -3.0]),
            handle(Any, [38.0, -20.0], [17.0, 15.0], [1.0, 3.0, 2.0]),
        ]),
        B::MouthFrownLeft => hs(vec![
            handle(Any, [25.0, -47.0], [15.0, 15.0], [2.0, -6.0, -0.5]),
            handle(LowerLip, [20.0, -60.0], [15.0, 12.0], [0.0, -2.0, 0.0]),
        ]),
        B::MouthDimpleLeft => hs(vec![handle(
            Any,
            [27.0, -47.0],
            [12.0, 12.0],
            [3.0, 0.0, -4.0],
        )]),
        B::MouthStretchLeft => hs(vec![
            handle(Any, [25.0, -47.0], [16.0, 16.0], [6.0, -3.0, -2.0]),
            handle(LowerLip, [15.0, -52.0], [16.0, 10.0], [0.0, -2.0, 0.0]),
        ]),
        B::MouthRollLower => hs(vec![handle(
            LowerLip,
            [0.0, -47.0],
            [27.0, 6.0],
            [0.0, 2.0, -5.0],
        )]),
        B::MouthRollUpper => hs(vec![handle(
            UpperLip,
            [0.0, -47.0],
            [27.0, 6.0],
            [0.0, -2.0, -5.0],
        )]),
        B::MouthShrugLower => hs(vec![handle(
            LowerLip,
            [0.0, -65.0],
            [25.0, 20.0],
            [0.0, 4.0, 2.0],
        )]),
        B::MouthShrugUpper => hs(vec![handle(
            UpperLip,
            [0.0, -44.0],
            [25.0, 10.0],
            [0.0, 3.0, 2.0],
        )]),
        B::MouthPressLeft => hs(vec![
            handle(UpperLip, [12.0, -47.0], [15.0, 6.0], [0.5, -1.0, -1.5]),
            handle(LowerLip, [12.0, -47.0], [15.0, 6.0], [0.5, 1.0, -1.5]),
        ]),
        B::MouthLowerDownLeft => hs(vec![handle(
            LowerLip,
            [10.0, -49.0],
            [16.0, 9.0],
            [0.0, -5.0, 0.5],
        )]),
        B::MouthUpperUpLeft => hs(vec![handle(
            UpperLip,
            [10.0, -44.0],
            [16.0, 10.0],
            [0.0, 5.0, 1.0],
        )]),
        B::BrowDownLeft => hs(vec![handle(
            Any,
            [28.0, 46.0],
            [22.0, 12.0],
            [-2.0, -5.0, 0.5],
        )]),
        B::BrowInnerUp => {
            hs(sym(handle(Any, [13.0, 47.0], [14.0, 14.0], [0.5, 7.0, 0.0])).to_vec())
        }
        B::BrowOuterUpLeft => hs(vec![handle(
            Any,
            [42.0, 46.0],
            [16.0, 12.0],
            [0.0, 6.0, 0.0],
        )]),
        B::CheekPuff => {
            let mut h = sym(handle(Any, [45.0, -35.0], [22.0, 22.0], [6.0, 0.0, 6.0])).to_vec();
            h.push(handle(Any, [0.0, -47.0], [25.0, 10.0], [0.0, 0.0, 2.0]));
            hs(h)
        }
        B::CheekSquintLeft => hs(vec![handle(
            Any,
            [36.0, 5.0],
            [18.0, 12.0],
            [0.0, 4.0, 1.5],
        )]),
        B::NoseSneerLeft => hs(vec![
            handle(Any, [12.0, -12.0], [10.0, 16.0], [0.5, 4.0, 0.5]),
            handle(UpperLip, [10.0, -40.0], [12.0, 8.0], [0.0, 2.0, 0.0]),
            handle(Any, [15.0, 30.0], [10.0, 8.0], [-1.0, -1.5, 0.0]),
        ]),
        B::TongueOut => hs(vec![handle(
            LowerLip,
            [0.0, -49.0],
            [22.0, 8.0],
            [0.0, -1.5, 1.0],
        )]),
        right => left_or_centre(right.mirror()).mirrored(),
    }
}

/// The generic anatomy of all 52 shapes, in Apple's order.
pub fn generic_specs() -> Vec<ShapeSpec> {
    let specs: Vec<ShapeSpec> = Blendshape::ALL.iter().map(|s| left_or_centre(*s)).collect();
    debug_assert_eq!(specs.len(), BLENDSHAPE_COUNT);
    specs
}
