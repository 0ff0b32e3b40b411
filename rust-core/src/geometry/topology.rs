//! Triangle-mesh connectivity shared by every mesh of a session.
//!
//! ARKit's face geometry has a fixed topology (1,220 vertices, 2,304
//! triangles); the template, the neutral scan, every captured frame and every
//! personalized blendshape share it, so vertex `i` means the same point of the
//! face everywhere. A [`Topology`] can only be built through [`Topology::new`],
//! which checks every index, so code that holds one never re-checks.

use glam::Vec3;

/// Largest vertex count a topology may have. ARKit's mask has 1,220; avatars
/// have tens of thousands. The cap keeps hostile files from sizing allocations.
pub const MAX_VERTICES: usize = 1 << 22;

/// Largest triangle count a topology may have (see [`MAX_VERTICES`]).
pub const MAX_TRIANGLES: usize = 1 << 23;

/// Validated triangle connectivity over `vertex_count` vertices.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Topology {
    vertex_count: usize,
    triangles: Vec<[u32; 3]>,
}

/// What is wrong with a triangle list.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum TopologyError {
    /// No vertices, or more than [`MAX_VERTICES`].
    #[error("vertex count {0} is outside 1..={MAX_VERTICES}")]
    VertexCount(usize),
    /// No triangles, or more than [`MAX_TRIANGLES`].
    #[error("triangle count {0} is outside 1..={MAX_TRIANGLES}")]
    TriangleCount(usize),
    /// A corner refers to a vertex that does not exist.
    #[error(
        "triangle {triangle} refers to vertex {index}, but there are only {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the offending triangle.
        triangle: usize,
        /// The out-of-range vertex index.
        index: u32,
        /// Number of vertices.
        vertex_count: usize,
    },
    /// A triangle uses the same vertex twice.
    #[error("triangle {triangle} repeats vertex {index}")]
    Degenerate {
        /// Index of the offending triangle.
        triangle: usize,
        /// The repeated vertex index.
        index: u32,
    },
}

impl Topology {
    /// Checks and wraps a triangle list over `vertex_count` vertices.
    pub fn new(vertex_count: usize, triangles: Vec<[u32; 3]>) -> Result<Topology, TopologyError> {
        if vertex_count == 0 || vertex_count > MAX_VERTICES {
            return Err(TopologyError::VertexCount(vertex_count));
        }
        if triangles.is_empty() || triangles.len() > MAX_TRIANGLES {
            return Err(TopologyError::TriangleCount(triangles.len()));
        }
        for (t, tri) in triangles.iter().enumerate() {
            for (k, &index) in tri.iter().enumerate() {
                if index as usize >= vertex_count {
                    return Err(TopologyError::IndexOutOfRange {
                        triangle: t,
                        index,
                        vertex_count,
                    });
                }
                // Indexing: `(k + 1) % 3` of a triangle's three corners.
                if tri[(k + 1) % 3] == index {
                    return Err(TopologyError::Degenerate { triangle: t, index });
                }
            }
        }
        Ok(Topology {
            vertex_count,
            triangles,
        })
    }

    /// Number of vertices.
    pub fn vertex_count(&self) -> usize {
        self.vertex_count
    }

    /// The triangles, counter-clockwise seen from outside the face.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Checks that `positions` has one finite point per vertex; `what` names
    /// the mesh in the error ("neutral", "frame 12", ...).
    pub fn check_positions(&self, what: &str, positions: &[Vec3]) -> Result<(), GeometryError> {
        if positions.len() != self.vertex_count {
            return Err(GeometryError::VertexCount {
                what: what.to_string(),
                expected: self.vertex_count,
                found: positions.len(),
            });
        }
        if let Some(vertex) = positions.iter().position(|p| !p.is_finite()) {
            return Err(GeometryError::NotFinite {
                what: what.to_string(),
                vertex,
            });
        }
        Ok(())
    }
}

/// A mesh's positions do not fit its topology.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum GeometryError {
    /// Wrong number of vertices.
    #[error("{what}: {found} vertices, but the topology has {expected}")]
    VertexCount {
        /// Which mesh.
        what: String,
        /// Vertex count of the topology.
        expected: usize,
        /// Vertex count of the mesh.
        found: usize,
    },
    /// A coordinate is NaN or infinite.
    #[error("{what}: vertex {vertex} has a NaN or infinite coordinate")]
    NotFinite {
        /// Which mesh.
        what: String,
        /// The first offending vertex.
        vertex: usize,
    },
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn accepts_a_valid_triangle_list() {
        let topo = Topology::new(4, vec![[0, 1, 2], [0, 2, 3]]).unwrap();
        assert_eq!(topo.vertex_count(), 4);
        assert_eq!(topo.triangles().len(), 2);
    }

    #[test]
    fn rejects_bad_indices_and_counts() {
        assert_eq!(
            Topology::new(3, vec![[0, 1, 3]]),
            Err(TopologyError::IndexOutOfRange {
                triangle: 0,
                index: 3,
                vertex_count: 3
            })
        );
        assert_eq!(
            Topology::new(3, vec![[0, 1, 2], [2, 1, 2]]),
            Err(TopologyError::Degenerate {
                triangle: 1,
                index: 2
            })
        );
        assert_eq!(
            Topology::new(0, vec![[0, 1, 2]]),
            Err(TopologyError::VertexCount(0))
        );
        assert_eq!(
            Topology::new(3, vec![]),
            Err(TopologyError::TriangleCount(0))
        );
    }

    #[test]
    fn position_checks_name_the_mesh_and_vertex() {
        let topo = Topology::new(3, vec![[0, 1, 2]]).unwrap();
        let mut p = vec![Vec3::ZERO; 3];
        assert!(topo.check_positions("neutral", &p).is_ok());
        p[1].y = f32::NAN;
        let err = topo.check_positions("frame 7", &p).unwrap_err();
        assert_eq!(
            err.to_string(),
            "frame 7: vertex 1 has a NaN or infinite coordinate"
        );
        let err = topo.check_positions("neutral", &p[..2]).unwrap_err();
        assert!(
            err.to_string()
                .contains("2 vertices, but the topology has 3")
        );
    }
}
