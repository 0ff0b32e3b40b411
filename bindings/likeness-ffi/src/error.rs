//! The one error every exported call can fail with, converted from the
//! core's typed errors with their messages (which name the file, field,
//! frame or step).

use likeness::avatar::glb::GlbError;
use likeness::avatar::personal_avatar::AvatarError;
use likeness::capture::guided_capture::GuidedCaptureError;
use likeness::capture::recorder::RecorderError;
use likeness::personalize::PersonalizeError;
use likeness::session::SessionError;
use likeness::session::file::SessionFileError;
use std::error::Error;

/// Why a call failed. Swift: `LikenessError.InvalidInput(message:)` … and
/// `.Cancelled` (UniFFI keeps an error's case names as Rust spells them);
/// Python: `LikenessError.InvalidInput` … subclasses.
#[derive(Debug, PartialEq, thiserror::Error, uniffi::Error)]
pub enum LikenessError {
    /// An argument is unusable: a weight array not of 52 finite values, a
    /// mesh of another vertex count, time going backwards, a template of
    /// the wrong shape count, an unknown method or step.
    #[error("invalid input: {message}")]
    InvalidInput {
        /// What is wrong, naming the field.
        message: String,
    },
    /// A session file could not be read or written, or is damaged.
    #[error("file: {message}")]
    File {
        /// The path and what is wrong.
        message: String,
    },
    /// The capture could not become a session.
    #[error("capture: {message}")]
    Capture {
        /// Why.
        message: String,
    },
    /// The session could not be personalized.
    #[error("personalization: {message}")]
    Personalization {
        /// Why.
        message: String,
    },
    /// The avatar could not be read or made (no morph targets, no face).
    #[error("avatar: {message}")]
    Avatar {
        /// Why, naming the avatar.
        message: String,
    },
    /// A call the object cannot take now: finishing an unfinished capture,
    /// skipping the neutral scan, using a capture already finished,
    /// personalizing a session without captures.
    #[error("wrong order: {message}")]
    WrongOrder {
        /// What was expected first.
        message: String,
    },
    /// The progress listener asked to stop.
    #[error("cancelled")]
    Cancelled,
    /// A bug, or an earlier call that panicked: start again.
    #[error("internal error: {message}")]
    Internal {
        /// What happened.
        message: String,
    },
}

impl LikenessError {
    /// [`LikenessError::InvalidInput`] with `message`.
    pub fn invalid(message: impl Into<String>) -> Self {
        LikenessError::InvalidInput {
            message: message.into(),
        }
    }

    /// [`LikenessError::WrongOrder`] with `message`.
    pub fn wrong_order(message: impl Into<String>) -> Self {
        LikenessError::WrongOrder {
            message: message.into(),
        }
    }
}

/// `e`'s message followed by each cause it does not already contain, as
/// the command line prints them.
pub fn message(e: &dyn Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        let cause = s.to_string();
        if !text.contains(&cause) {
            text = format!("{text}: {cause}");
        }
        source = s.source();
    }
    text
}

impl From<RecorderError> for LikenessError {
    fn from(e: RecorderError) -> Self {
        let text = message(&e);
        match e {
            RecorderError::Capture(GuidedCaptureError::NeutralNotSkippable)
            | RecorderError::NotStarted
            | RecorderError::NothingToSkip
            | RecorderError::NotFinished { .. }
            | RecorderError::Ended => LikenessError::WrongOrder { message: text },
            RecorderError::NeutralWithoutMesh(_)
            | RecorderError::NoNeutralScan
            | RecorderError::Session(_) => LikenessError::Capture { message: text },
            RecorderError::Template(_)
            | RecorderError::Frame(_)
            | RecorderError::Capture(_)
            | RecorderError::NoSuchStep { .. }
            | RecorderError::NoPreview(_) => LikenessError::InvalidInput { message: text },
        }
    }
}

impl From<SessionError> for LikenessError {
    fn from(e: SessionError) -> Self {
        LikenessError::InvalidInput {
            message: message(&e),
        }
    }
}

impl From<SessionFileError> for LikenessError {
    fn from(e: SessionFileError) -> Self {
        LikenessError::File {
            message: message(&e),
        }
    }
}

impl From<PersonalizeError> for LikenessError {
    fn from(e: PersonalizeError) -> Self {
        match e {
            PersonalizeError::Cancelled(_) => LikenessError::Cancelled,
            PersonalizeError::NoCaptures => LikenessError::WrongOrder {
                message: format!("{e}: capture at least one expression before personalizing"),
            },
            _ => LikenessError::Personalization {
                message: message(&e),
            },
        }
    }
}

impl From<AvatarError> for LikenessError {
    fn from(e: AvatarError) -> Self {
        match e {
            AvatarError::Cancelled(_) => LikenessError::Cancelled,
            _ => LikenessError::Avatar {
                message: message(&e),
            },
        }
    }
}

impl From<GlbError> for LikenessError {
    fn from(e: GlbError) -> Self {
        LikenessError::Avatar {
            message: message(&e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use likeness::personalize::PersonalizeStage;

    #[test]
    fn each_core_error_lands_on_its_variant_with_its_message() {
        let e = LikenessError::from(RecorderError::NotFinished { done: 3, total: 53 });
        assert_eq!(
            e,
            LikenessError::wrong_order("the capture has not finished: 3 of 53 steps are done")
        );
        let back = GuidedCaptureError::TimeWentBack {
            frame: 7,
            timestamp: 1.0,
            previous: 2.0,
        };
        let e = LikenessError::from(RecorderError::Capture(back));
        assert!(
            matches!(e, LikenessError::InvalidInput { message } if message.contains("frame 7"))
        );
        let e = LikenessError::from(PersonalizeError::Cancelled(PersonalizeStage::Fitting));
        assert_eq!(e, LikenessError::Cancelled);
        let e = LikenessError::from(PersonalizeError::NoCaptures);
        assert!(matches!(e, LikenessError::WrongOrder { .. }));
        let e = LikenessError::from(SessionFileError::NotASessionFile);
        assert!(matches!(e, LikenessError::File { message } if message.contains("not a Likeness")));
    }
}
