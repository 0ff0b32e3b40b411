//! Geometry shared by the pipeline's stages: mesh connectivity, boundary
//! loops and the eye-hole triangles, deformation gradients, and deformation
//! transfer. Nothing here knows about sessions or captures; the stages
//! (personalization today, the avatar transfer next) call it with meshes.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.1, `n = 1220`, 2304 triangles | triangle lists checked against vertex counts | [`topology`] |
//! | §3.2, virtual eye triangles (Saito 2013) | boundary edges and loops, eye holes spanned lid to lid | [`mesh_boundary`] |
//! | §3.2 (ref. 47) | per-triangle deformation gradients (Sumner & Popović 2004) | [`deformation_gradient`] |
//! | §3.2 (ref. 47), §3.3 | gradient-domain deformation transfer (Botsch et al. 2006), lid contacts, translation | [`deformation_transfer`] |
//! | §3.3, ICP and the map `M` | exact closest points on a triangle mesh in a bounding-volume hierarchy (Ericson 2005; Wald et al. 2007) | [`closest_point`] |
//! | §3.3, teeth and eyeballs inside one mesh | connected components (union–find) | [`connected_components`] |
//! | §3.3, the skin the mask may lie on | triangles seen from the front (orthographic depth buffer) | [`front_visibility`] |
//! | beyond §3.3, creases at rest and in a shape: the angle between two triangles on an edge, and how a displacement changes it | [`dihedral_angle`] |
//! | §3.3, the blend margin; motion faded out where nothing moves | shortest edge paths from a set of vertices (Dijkstra) | [`edge_distance`] |
//! | §3.2 (Eq. 2), §3.3 steps 1 and 2 | the cotangent Laplacian (gradient form) and the uniform one, as sparse entries | [`laplacian`] |
//! | §3.3 step 2, the person's face: the uniform Laplacian's rows | each vertex's one-ring | [`one_ring`] |
//! | beyond §3.3, the blink seen from the front, the inside through the skin: rays along one direction against triangles binned across it (Möller–Trumbore) | [`ray_cover`] |
//! | beyond §3.3, the inside through the skin: where a shape moves | cubes over a box of vertices, grown by whole cubes | [`cube_grid`] |
//! | beyond §3.3, the person's face: skin that must not pass through itself | triangle pairs that cut through each other (Möller–Trumbore, binned) | [`self_intersection`] |
//! | every linear solve (Eq. 4's transfers, both steps of §3.3, the registration) | one sparse Cholesky factorization; a fixed pattern analysed once and refilled | [`sparse_cholesky`] |
//! | §3.3, Eq. 4 with the weights in `[0, 1]` (beyond the paper) | a convex quadratic's least over a box (primal–dual active set) | [`box_quadratic`] |
//! | §3.3, eyeballs found by their shape | algebraic least-squares sphere (Kåsa 1976) | [`sphere_fit`] |
//! | §3.3, a lid inside an eyeball whose shell is open | the generalized winding number (Jacobson et al. 2013) | [`winding_number`] |
//! | §3.3, a lid inside an eyeball: which side, how deep | the closest triangle's side and the winding number | [`inside_surface`] |

pub mod box_quadratic;
pub mod closest_point;
pub mod connected_components;
pub mod cube_grid;
pub mod deformation_gradient;
pub mod deformation_transfer;
pub mod dihedral_angle;
pub mod edge_distance;
pub mod front_visibility;
pub mod inside_surface;
pub mod laplacian;
pub mod mesh_boundary;
pub mod one_ring;
pub mod ray_cover;
pub mod self_intersection;
pub mod sparse_cholesky;
pub mod sphere_fit;
#[cfg(test)]
pub(crate) mod test_shapes;
pub mod topology;
pub mod winding_number;

pub use topology::{GeometryError, Topology, TopologyError};
