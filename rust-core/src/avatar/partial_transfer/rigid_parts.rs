//! Rigid parts stay rigid (§3.3: "the approximations `A_j` also bring
//! facial details not included in the ARKit mesh (eye balls and teeth) to
//! their desired position"). A part is rigid when every one of the
//! avatar's own targets moves it rigidly (within [`RIGID_TOLERANCE`] of its
//! size): eyeballs, teeth, the upper gums. `A_j` mixes several targets, and
//! a sum of rotations is not a rotation: a rigid part's displacement in a
//! shape is replaced by the rigid motion closest to it (least squares,
//! [`fit_rigid`]). The largest deviation from a rigid motion, before and
//! after, is reported per shape.

use crate::avatar::registration::similarity::fit_rigid;
use glam::DVec3;

/// Largest deviation from a rigid motion, relative to the part's size
/// (RMS radius), for a target to count as moving the part rigidly.
pub const RIGID_TOLERANCE: f64 = 1e-4;

/// The largest distance between `rest + displacement` and the rigid motion
/// closest to it, over `vertices`; 0 for fewer than three.
pub fn rigid_deviation(rest: &[DVec3], displacement: &[DVec3], vertices: &[u32]) -> f64 {
    let (p, q) = pairs(rest, displacement, vertices);
    match fit_rigid(&p, &q, &vec![1.0; p.len()]) {
        Some(m) => p
            .iter()
            .zip(&q)
            .map(|(a, b)| (m.apply(*a) - *b).length())
            .fold(0.0, f64::max),
        None => 0.0,
    }
}

/// Replaces the displacement of `vertices` by the rigid motion closest to
/// it. Returns the largest deviation that was removed.
pub fn make_rigid(rest: &[DVec3], displacement: &mut [DVec3], vertices: &[u32]) -> f64 {
    let (p, q) = pairs(rest, displacement, vertices);
    let Some(m) = fit_rigid(&p, &q, &vec![1.0; p.len()]) else {
        return 0.0;
    };
    let mut removed = 0.0f64;
    for &v in vertices {
        let v = v as usize;
        if let (Some(r), Some(d)) = (rest.get(v), displacement.get_mut(v)) {
            let rigid = m.apply(*r) - *r;
            removed = removed.max((rigid - *d).length());
            *d = rigid;
        }
    }
    removed
}

/// RMS distance of `vertices` from their centroid at rest.
pub fn size(rest: &[DVec3], vertices: &[u32]) -> f64 {
    let points: Vec<DVec3> = vertices
        .iter()
        .filter_map(|&v| rest.get(v as usize).copied())
        .collect();
    let n = points.len().max(1) as f64;
    let c = points.iter().sum::<DVec3>() / n;
    (points
        .iter()
        .map(|p| (*p - c).length_squared())
        .sum::<f64>()
        / n)
        .sqrt()
}

fn pairs(rest: &[DVec3], displacement: &[DVec3], vertices: &[u32]) -> (Vec<DVec3>, Vec<DVec3>) {
    vertices
        .iter()
        .filter_map(|&v| {
            let (r, d) = (rest.get(v as usize)?, displacement.get(v as usize)?);
            Some((*r, *r + *d))
        })
        .unzip()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DMat3;

    #[test]
    fn a_sum_of_rotations_is_made_rigid_and_a_rotation_is_left_alone() {
        let rest: Vec<DVec3> = (0..20)
            .map(|i| {
                let f = i as f64;
                DVec3::new((f * 0.9).sin(), (f * 0.4).cos(), (f * 1.7).sin() * 0.3)
            })
            .collect();
        let vertices: Vec<u32> = (0..20).collect();
        let turn = |a: f64| -> Vec<DVec3> {
            rest.iter()
                .map(|p| DMat3::from_rotation_x(a) * *p - *p)
                .collect()
        };
        let one = turn(0.35);
        assert!(rigid_deviation(&rest, &one, &vertices) < 1e-12);
        // Twice a rotation's displacement is not a rotation.
        let mut doubled: Vec<DVec3> = one.iter().map(|d| *d * 2.0).collect();
        assert!(rigid_deviation(&rest, &doubled, &vertices) > 0.05);
        make_rigid(&rest, &mut doubled, &vertices);
        assert!(rigid_deviation(&rest, &doubled, &vertices) < 1e-12);
    }
}
