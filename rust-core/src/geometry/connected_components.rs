//! Connected components of a triangle mesh, by union–find over the
//! triangles' vertices (path halving; Tarjan 1975). Used wherever a mesh
//! must be taken apart: the pins of a gradient-domain solve, the teeth and
//! eyeballs inside one avatar mesh.

/// Marks a vertex not yet given a component.
const UNSET: u32 = u32::MAX;

/// Root of `v` in a union–find forest, with path halving.
fn root(parent: &mut [usize], mut v: usize) -> usize {
    while parent[v] != v {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    v
}

/// Connected components of the triangles over `n` vertices: each vertex's
/// component, numbered in order of their smallest vertex, and the count. A
/// vertex in no triangle is a component of its own. Triangles with an
/// index `≥ n` are ignored.
pub fn components(n: usize, triangles: &[[u32; 3]]) -> (Vec<u32>, usize) {
    let mut parent: Vec<usize> = (0..n).collect();
    for t in triangles {
        if t.iter().any(|&v| v as usize >= n) {
            continue;
        }
        for k in 1..3 {
            let (a, b) = (
                root(&mut parent, t[0] as usize),
                root(&mut parent, t[k] as usize),
            );
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut id = vec![UNSET; n];
    let mut count = 0;
    for v in 0..n {
        let r = root(&mut parent, v);
        if id[r] == UNSET {
            id[r] = count;
            count += 1;
        }
        id[v] = id[r];
    }
    (id, count as usize)
}

/// The vertices of each component (in increasing order), from
/// [`components`].
pub fn component_vertices(n: usize, triangles: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let (id, count) = components(n, triangles);
    let mut out = vec![Vec::new(); count];
    for (v, c) in id.iter().enumerate() {
        out[*c as usize].push(v as u32);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_triangles_and_a_lone_vertex_are_three_components() {
        let (id, count) = components(7, &[[0, 1, 2], [3, 4, 5], [2, 0, 9]]);
        assert_eq!(count, 3);
        assert_eq!(id, vec![0, 0, 0, 1, 1, 1, 2]);
        assert_eq!(
            component_vertices(7, &[[0, 1, 2], [3, 4, 5]]),
            vec![vec![0, 1, 2], vec![3, 4, 5], vec![6]]
        );
    }
}
