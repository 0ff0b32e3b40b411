//! Each vertex's one-ring: the vertices it shares an edge with, over a
//! triangle list. The uniform Laplacian `L` of the avatar stage's
//! bi-Laplacian solves (step 2's correction, the person's face) is built
//! row by row from it: `(L u)_v = Σ_{w ∈ N(v)} (u_w − u_v) / |N(v)|`.

use std::collections::{BTreeSet, HashMap};

/// The one-ring of every vertex of `triangles` below `n` (those of a
/// triangle naming a vertex `≥ n` are skipped, as are degenerate edges),
/// each in increasing order; vertices in no triangle are absent.
pub fn one_rings(n: usize, triangles: &[[u32; 3]]) -> HashMap<u32, BTreeSet<u32>> {
    let mut neighbours: HashMap<u32, BTreeSet<u32>> = HashMap::new();
    for t in triangles {
        if t.iter().any(|&v| v as usize >= n) {
            continue;
        }
        for k in 0..3 {
            let (a, b) = (t[k], t[(k + 1) % 3]);
            if a != b {
                neighbours.entry(a).or_default().insert(b);
                neighbours.entry(b).or_default().insert(a);
            }
        }
    }
    neighbours
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_fan_gives_its_centre_every_rim_vertex() {
        let rings = one_rings(5, &[[0, 1, 2], [0, 2, 3], [0, 3, 9], [4, 4, 0]]);
        assert_eq!(rings[&0], BTreeSet::from([1, 2, 3, 4]));
        assert_eq!(rings[&1], BTreeSet::from([0, 2]));
        assert!(!rings[&4].contains(&4), "a degenerate edge is no neighbour");
        assert!(!rings.contains_key(&9));
    }
}
