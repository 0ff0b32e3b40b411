//! Everything that can go wrong reading or writing a glTF avatar, each case
//! naming the file and where in it (mesh, primitive, accessor, vertex).

use crate::avatar::InvalidAvatar;
use crate::io::FileError;
use std::io;
use std::path::PathBuf;

/// A glTF / GLB avatar could not be read or written.
#[derive(Debug, thiserror::Error)]
pub enum GlbError {
    /// The file could not be opened or read: missing, not a regular file,
    /// or over [`MAX_GLB_BYTES`](super::read::MAX_GLB_BYTES).
    #[error(transparent)]
    File(#[from] FileError),
    /// The file could not be written.
    #[error("{file}: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// What the operating system said.
        #[source]
        source: io::Error,
    },
    /// Neither GLB (magic `glTF`) nor glTF JSON (starts with `{`).
    #[error("{file}: not glTF (neither the GLB magic `glTF` nor a JSON object)")]
    NotGltf {
        /// The file.
        file: PathBuf,
    },
    /// The GLB container ends before what its header or a chunk announces.
    #[error("{file}: truncated GLB: {what}")]
    Truncated {
        /// The file.
        file: PathBuf,
        /// What was cut short.
        what: String,
    },
    /// The GLB container is malformed (version, chunk types, lengths).
    #[error("{file}: malformed GLB: {what}")]
    Container {
        /// The file.
        file: PathBuf,
        /// What is wrong.
        what: String,
    },
    /// The JSON is not a glTF 2.0 document, or breaks the spec's rules
    /// (an index out of range, a required field missing).
    #[error("{file}: invalid glTF: {what}")]
    Invalid {
        /// The file.
        file: PathBuf,
        /// The JSON path and what is wrong there.
        what: String,
    },
    /// A buffer's bytes are missing or shorter than its `byteLength`.
    #[error("{file}: buffer {buffer}: {what}")]
    Buffer {
        /// The file.
        file: PathBuf,
        /// Index of the buffer.
        buffer: usize,
        /// What is wrong.
        what: String,
    },
    /// A buffer view compressed with `EXT_meshopt_compression` cannot be
    /// decoded: a field missing or out of range, or a stream meshoptimizer
    /// rejects.
    #[error("{file}: buffer view {view}: {what}")]
    Compressed {
        /// The file.
        file: PathBuf,
        /// Index of the buffer view.
        view: usize,
        /// What is wrong.
        what: String,
    },
    /// The file requires an extension that stores or places geometry in a
    /// way this reader does not decode (`EXT_mesh_gpu_instancing`);
    /// `advice` says how to convert the file.
    #[error("{file}: requires {extension}, which this reader does not decode; {advice}")]
    Unsupported {
        /// The file.
        file: PathBuf,
        /// The extension's name.
        extension: String,
        /// How to get a file this reader takes.
        advice: String,
    },
    /// An accessor reads past the end of its buffer view or buffer, or its
    /// layout is not one this reader supports.
    #[error("{file}: accessor {accessor}: {what}")]
    Accessor {
        /// The file.
        file: PathBuf,
        /// Index of the accessor.
        accessor: usize,
        /// What is wrong.
        what: String,
    },
    /// A primitive this reader cannot take (a mode other than triangles,
    /// no `POSITION`).
    #[error("{file}: mesh {mesh} primitive {primitive}: {what}")]
    Primitive {
        /// The file.
        file: PathBuf,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive within the mesh.
        primitive: usize,
        /// What is wrong.
        what: String,
    },
    /// The default scene places no triangle mesh.
    #[error("{file}: no mesh in the scene")]
    NoMesh {
        /// The file.
        file: PathBuf,
    },
    /// No placed mesh has morph targets.
    #[error("{file}: no morph targets on any mesh")]
    NoMorphTargets {
        /// The file.
        file: PathBuf,
    },
    /// Morph targets exist, but none carries one of ARKit's names.
    #[error("{file}: none of the morph targets has one of ARKit's 52 names")]
    NoArkitTargets {
        /// The file.
        file: PathBuf,
    },
    /// A rest position or a target displacement is NaN or infinite.
    #[error("{file}: mesh {mesh} primitive {primitive} {which} vertex {vertex}: not finite")]
    NotFinite {
        /// The file.
        file: PathBuf,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive within the mesh.
        primitive: usize,
        /// `position` or `target N`.
        which: String,
        /// Index of the vertex within the primitive.
        vertex: usize,
    },
    /// A triangle names a vertex past the end, or one vertex twice.
    #[error("{file}: mesh {mesh} primitive {primitive} triangle {triangle}: {what}")]
    Triangle {
        /// The file.
        file: PathBuf,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive within the mesh.
        primitive: usize,
        /// Index of the triangle within the primitive.
        triangle: usize,
        /// What is wrong.
        what: String,
    },
    /// The primitives of one mesh have different numbers of morph targets
    /// (the spec requires the same number, in the same order).
    #[error(
        "{file}: mesh {mesh} primitive {primitive} has {found} morph targets, primitive 0 has {expected}"
    )]
    TargetCount {
        /// The file.
        file: PathBuf,
        /// Index of the mesh.
        mesh: usize,
        /// Index of the primitive within the mesh.
        primitive: usize,
        /// Targets on the mesh's first primitive.
        expected: usize,
        /// Targets on this one.
        found: usize,
    },
    /// The meshes read do not make an avatar ([`Avatar::new`]'s rules).
    ///
    /// [`Avatar::new`]: crate::avatar::Avatar::new
    #[error("{file}: {source}")]
    Avatar {
        /// The file.
        file: PathBuf,
        /// The rule broken.
        source: InvalidAvatar,
    },
    /// The new shapes given to a write do not fit the avatar, or the write
    /// would break something it cannot rewrite (an animation of the weights
    /// of a mesh whose target count changes).
    #[error("{file}: {what}")]
    Write {
        /// The file being written.
        file: PathBuf,
        /// What does not fit.
        what: String,
    },
}
