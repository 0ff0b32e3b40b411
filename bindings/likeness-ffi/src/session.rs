//! A recorded session: loaded from or saved to a `.likeness` file,
//! summarized, personalized.

use crate::error::LikenessError;
use crate::personalized::PersonalizedFace;
use crate::progress::{ProgressListener, cancelled, report};
use crate::types::{FaceTemplate, QualitySummary, RecordedFrame, count};
use likeness::capture::session_summary::quality_summary;
use likeness::personalize::{Method, personalize_with_progress};
use likeness::session::{Session, file};
use std::sync::Arc;

/// A capture session, checked (read-only: a new capture makes a new one).
#[derive(uniffi::Object)]
pub struct SessionHandle {
    session: Session,
}

impl SessionHandle {
    /// Wraps a checked session.
    pub(crate) fn new(session: Session) -> SessionHandle {
        SessionHandle { session }
    }
}

#[uniffi::export]
impl SessionHandle {
    /// Reads the session file at `path` (a damaged or foreign file is a
    /// `File` error naming what is wrong).
    #[uniffi::constructor]
    pub fn load(path: String) -> Result<Arc<Self>, LikenessError> {
        Ok(Arc::new(SessionHandle::new(file::read(&path)?)))
    }

    /// Writes the session to `path` atomically: a crash leaves the old
    /// file or the new one, never half of one.
    pub fn save(&self, path: String) -> Result<(), LikenessError> {
        Ok(file::write(&path, &self.session)?)
    }

    /// The captures in words: how many, which are missing, what is wrong.
    pub fn quality_summary(&self) -> Result<QualitySummary, LikenessError> {
        Ok(quality_summary(&self.session).into())
    }

    /// The person's 52 blendshapes with `method` (a name of `methods()`;
    /// `None` for `default_method()`); `listener` hears the stages and may
    /// cancel.
    pub fn personalize(
        &self,
        method: Option<String>,
        listener: Option<Arc<dyn ProgressListener>>,
    ) -> Result<Arc<PersonalizedFace>, LikenessError> {
        let method = match method {
            Some(name) => name
                .parse::<Method>()
                .map_err(|e| LikenessError::invalid(format!("method: {e}")))?,
            None => Method::DEFAULT,
        };
        let listener = listener.as_ref();
        if cancelled(listener) {
            return Err(LikenessError::Cancelled);
        }
        let personalized = personalize_with_progress(&self.session, method, &mut |stage| {
            report(listener, stage.name(), stage.done_before())
        })?;
        let face = PersonalizedFace::new(&self.session, personalized)?;
        report(listener, "personalized", 1.0);
        Ok(Arc::new(face))
    }

    /// The generic template the session was recorded against (for
    /// replaying a stored session through a new capture).
    pub fn template(&self) -> Result<FaceTemplate, LikenessError> {
        Ok(FaceTemplate::of(&self.session))
    }

    /// Frames in the recorded stream.
    pub fn recorded_frame_count(&self) -> u32 {
        count(self.session.frames.len())
    }

    /// The recorded stream's frame at `index`, as `push_frame` takes it.
    pub fn recorded_frame(&self, index: u32) -> Result<RecordedFrame, LikenessError> {
        self.session
            .frames
            .get(index as usize)
            .map(RecordedFrame::from)
            .ok_or_else(|| {
                LikenessError::invalid(format!(
                    "recorded frame {index}: the stream has {} frames",
                    self.session.frames.len()
                ))
            })
    }
}
