//! Each lip takes its own lip's motion, by both rigs' own `jawOpen`.
//!
//! [`super::lip_sides`] keeps an avatar vertex at the mouth's slit on its
//! own lip's triangles, but only on the mask's triangles within a few rings
//! of the slit. ARKit's own face curls its lips inwards: behind the slit
//! the upper lip's lining lies over the lower lip's, and an avatar vertex
//! of the upper lip, a ring or two above its edge, can find its closest
//! compatible point on the lower lip's curl. It then takes the lower lip's
//! motion, and in `jawOpen` a curtain of the upper lip comes down with the
//! jaw over the open mouth (18–27 vertices on every avatar, with people on
//! ARKit's mesh).
//!
//! Both rigs say which lip a point lies on: their own `jawOpen` moves the
//! lower lip with the mandible and leaves the upper lip with the skull
//! (the rule of [`super::lips_parting`], with its [`WITH_JAW`] and
//! [`STILL`]). Near the mouth, an avatar vertex whose own `jawOpen` leaves
//! it still while the mask's moves its point with the jaw (or the other way
//! round) has found the other lip: it leaves the face region, and step 2
//! of the transfer carries the avatar's own rig across it
//! ([`crate::avatar::partial_transfer::adjacent_step`]). Between the two
//! shares (the corners, the cheeks beside them) no rig's word is clear,
//! and nothing is left out.

use super::correspondence::CorrespondenceMap;
use super::lips_parting::{STILL, WITH_JAW};
use glam::DVec3;

/// How a point moves in a rig's `jawOpen`, against the most that rig moves
/// any point near the mouth.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum JawSide {
    /// With the mandible: the lower lip, the chin.
    WithJaw,
    /// With the skull: the upper lip, the nose.
    Still,
    /// Neither clearly: the corners, the cheeks.
    Between,
}

fn side(motion: f64, largest: f64) -> JawSide {
    if motion >= WITH_JAW * largest {
        JawSide::WithJaw
    } else if motion <= STILL * largest {
        JawSide::Still
    } else {
        JawSide::Between
    }
}

/// The mouth's neighbourhood, where the lips' sides are checked: within
/// `radius` of `centre` (the slit's middle; the radius is the slit's half
/// width, so the check covers the lips and none of the jaw line).
#[derive(Clone, Copy, Debug)]
pub struct MouthNeighbourhood {
    /// The slit's middle, in the avatar's coordinates.
    pub centre: DVec3,
    /// How far from it (avatar units).
    pub radius: f64,
}

/// Leaves out of `map` the avatar vertices near the mouth whose own
/// `jawOpen` (`avatar_jaw`, per avatar vertex) and the mask's at their
/// point (`mask_jaw`, per mask vertex, read through `M`) put them on
/// opposite sides of the jaw (module docs). `positions` are the avatar's.
/// Returns the vertices left out, in increasing order.
pub fn leave_out_other_lip(
    map: &mut CorrespondenceMap,
    positions: &[DVec3],
    avatar_jaw: &[DVec3],
    mask_jaw: &[DVec3],
    mouth: MouthNeighbourhood,
) -> Vec<u32> {
    let near = |v: u32| {
        positions
            .get(v as usize)
            .is_some_and(|p| p.distance(mouth.centre) <= mouth.radius)
    };
    let own = |v: u32| avatar_jaw.get(v as usize).map_or(0.0, |d| d.length());
    let at_point = map.apply(mask_jaw);
    let largest_own = map
        .face
        .iter()
        .filter(|f| near(f.vertex))
        .map(|f| own(f.vertex))
        .fold(0.0, f64::max);
    let largest_mask = map
        .face
        .iter()
        .zip(&at_point)
        .filter(|(f, _)| near(f.vertex))
        .map(|(_, d)| d.length())
        .fold(0.0, f64::max);
    if !(largest_own > 0.0 && largest_mask > 0.0) {
        return Vec::new();
    }
    let mut left_out = Vec::new();
    let mut kept = Vec::with_capacity(map.face.len());
    for (f, d) in map.face.iter().zip(&at_point) {
        let a = side(own(f.vertex), largest_own);
        let m = side(d.length(), largest_mask);
        let opposite = matches!(
            (a, m),
            (JawSide::WithJaw, JawSide::Still) | (JawSide::Still, JawSide::WithJaw)
        );
        if near(f.vertex) && opposite {
            left_out.push(f.vertex);
        } else {
            kept.push(*f);
        }
    }
    map.face = kept;
    left_out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::avatar::registration::FaceVertex;

    /// Two mask triangles, an upper lip (still) and a lower (with the jaw);
    /// three avatar vertices: one of each lip on its own lip's triangle, and
    /// an upper-lip vertex on the lower lip's.
    #[test]
    fn an_upper_lip_vertex_on_the_lower_lip_is_left_out() {
        let at = |v: u32, t: u32| FaceVertex {
            vertex: v,
            triangle: t,
            barycentric: [1.0 / 3.0; 3],
        };
        let mut map = CorrespondenceMap {
            mask_triangles: vec![[0, 1, 2], [3, 4, 5]],
            face: vec![at(0, 0), at(1, 1), at(2, 1)],
        };
        let down = DVec3::new(0.0, -0.01, 0.0);
        let mask_jaw = [DVec3::ZERO, DVec3::ZERO, DVec3::ZERO, down, down, down];
        // Vertex 0 upper and still, 1 lower and with the jaw, 2 upper (its
        // own jawOpen leaves it) but on the lower lip's triangle.
        let avatar_jaw = [DVec3::ZERO, down, DVec3::ZERO];
        let positions = [DVec3::ZERO, DVec3::X * 0.001, DVec3::Y * 0.001];
        let mouth = MouthNeighbourhood {
            centre: DVec3::ZERO,
            radius: 0.01,
        };
        let out = leave_out_other_lip(&mut map, &positions, &avatar_jaw, &mask_jaw, mouth);
        assert_eq!(out, vec![2]);
        assert_eq!(
            map.face.iter().map(|f| f.vertex).collect::<Vec<_>>(),
            vec![0, 1]
        );
        // Beyond the mouth's neighbourhood nothing is checked.
        let mut far = CorrespondenceMap {
            mask_triangles: vec![[0, 1, 2], [3, 4, 5]],
            face: vec![at(0, 0), at(1, 1), at(2, 1)],
        };
        let small = MouthNeighbourhood {
            centre: DVec3::ZERO,
            radius: 0.0015,
        };
        let positions = [DVec3::ZERO, DVec3::X * 0.001, DVec3::Y * 0.002];
        assert!(
            leave_out_other_lip(&mut far, &positions, &avatar_jaw, &mask_jaw, small).is_empty()
        );
    }
}
