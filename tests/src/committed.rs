//! The committed sample sessions (`sim-data/sessions/`), simulated subjects
//! 1–4 (see `sim-data/README.md`).

use likeness::Session;
use likeness::avatar::glb::GlbAvatar;
use likeness::avatar::personal_avatar::{
    AvatarError, AvatarShapes, PersonInput, PersonalAvatar, RestFace, personal_avatar,
};
use likeness::personalize::{Method, personalize};
use likeness::session::file::{self as session_file, SessionFileError};
use std::path::PathBuf;

/// Seeds of the committed sessions.
pub const SEEDS: [u64; 4] = [1, 2, 3, 4];

/// Path of the committed session of simulated subject `seed`.
pub fn path(seed: u64) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join(format!("../sim-data/sessions/subject-{seed}.likeness"))
}

/// Reads the committed session of simulated subject `seed`.
pub fn read(seed: u64) -> Result<Session, SessionFileError> {
    session_file::read(path(seed))
}

/// The committed subject `seed` personalized (the product's method) and
/// implanted into `glb`, as `likeness avatar` does it; the avatar stage's
/// error if it refuses.
pub fn personal_avatar_of(seed: u64, glb: &GlbAvatar) -> Result<PersonalAvatar, AvatarError> {
    personal_avatar_with(seed, glb, RestFace::Stock)
}

/// [`personal_avatar_of`] with the rest face `face`.
pub fn personal_avatar_with(
    seed: u64,
    glb: &GlbAvatar,
    face: RestFace,
) -> Result<PersonalAvatar, AvatarError> {
    let session = read(seed).expect("a committed session reads");
    let person = personalize(&session, Method::DEFAULT)
        .expect("a committed session personalizes")
        .shapes;
    let rig = session.template.blendshapes().expect("a checked template");
    let input = PersonInput {
        mask: &session.topology,
        rig: &rig,
        personalized: &person,
    };
    personal_avatar(
        glb,
        &input,
        None,
        AvatarShapes::Personalized,
        face,
        &mut |_| true,
    )
}

/// The round trip on `glb`: the avatar's own shapes, seen
/// through the face found on it for the committed subject 1's mask, given
/// as the person.
pub fn round_trip_of(glb: &GlbAvatar) -> Result<PersonalAvatar, AvatarError> {
    round_trip_with(glb, RestFace::Stock)
}

/// [`round_trip_of`] with the rest face `face`: with
/// [`RestFace::Person`] the avatar takes its own face (the registered
/// mask), which must change nothing.
pub fn round_trip_with(glb: &GlbAvatar, face: RestFace) -> Result<PersonalAvatar, AvatarError> {
    let session = read(1).expect("a committed session reads");
    let rig = session.template.blendshapes().expect("a checked template");
    let found = likeness::avatar::registration::find_face(&glb.avatar, &session.topology, &rig)
        .map_err(|source| AvatarError::Registration {
            file: glb.file.display().to_string(),
            source,
        })?;
    let person = likeness::avatar::own_shapes::avatar_as_person(&glb.avatar, &found)
        .expect("finite own shapes");
    let input = PersonInput {
        mask: &session.topology,
        rig: &rig,
        personalized: &person,
    };
    personal_avatar(
        glb,
        &input,
        Some(found),
        AvatarShapes::Personalized,
        face,
        &mut |_| true,
    )
}
