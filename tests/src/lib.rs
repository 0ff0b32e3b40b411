//! `likeness-tests`: the replay and end-to-end tests against committed and
//! simulated sessions (in `tests/tests/`), and, in this library, the
//! fixtures they share with the command-line tests (`cli/tests/`): where the
//! committed sessions are, and Live Link Face CSV text. See
//! `tests/README.md` for which kind of test lives where.

pub mod arkit_people;
pub mod avatar_quality;
pub mod bend;
pub mod committed;
pub mod face_checks;
pub mod gltf_validator;
pub mod live_link;
pub mod seam;
pub mod shared_avatars;
pub mod units;
