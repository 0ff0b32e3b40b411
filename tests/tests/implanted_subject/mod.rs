//! The avatar tests' shared fixture: a committed subject personalized with
//! the product's method and implanted into the default avatar.

// Each test binary that includes this module reads a different part of it.
#![allow(dead_code)]

use likeness::avatar::partial_transfer::{Implanted, implant};
use likeness::avatar::registration::{FaceRegistration, find_face};
use likeness::avatar::retargeting::{Retargeting, retarget};
use likeness::personalize::{Method, personalize};
use likeness::{Blendshapes, Session};
use likeness_sim::default_avatar::default_avatar;

/// Committed subject `n` on the default avatar.
pub struct Subject {
    /// The session as committed.
    pub session: Session,
    /// Its personalized shapes.
    pub person: Blendshapes,
    /// The face found on the default avatar.
    pub found: FaceRegistration,
    /// Eq. (4) of the person's shapes.
    pub retargeting: Retargeting,
    /// The person's shapes implanted.
    pub implanted: Implanted,
}

/// Committed subject `n`, personalized and implanted into the default
/// avatar.
pub fn implanted_subject(n: u64) -> Subject {
    let session = likeness_tests::committed::read(n).expect("reads");
    let person = personalize(&session, Method::DEFAULT)
        .expect("personalizes")
        .shapes;
    let avatar = &default_avatar().avatar;
    let rig = session.template.blendshapes().expect("a template");
    let found = find_face(avatar, &session.topology, &rig).expect("a face");
    let retargeting = retarget(avatar, &found, &person).expect("solves");
    let implanted = implant(
        avatar,
        &found,
        &retargeting,
        &person,
        (session.topology.triangles(), rig.neutral()),
    )
    .expect("implants");
    Subject {
        session,
        person,
        found,
        retargeting,
        implanted,
    }
}
