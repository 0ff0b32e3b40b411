//! The personalization methods, by name, and which frames their fits use.

use std::fmt;
use std::str::FromStr;

/// A personalization method (see the table of [`super::personalization`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Deformation transfer of the template: the generic blendshapes.
    Dt,
    /// Example-based facial rigging (Li et al. 2010), blendshape step.
    Ebfr,
    /// The paper's Eq. (1)–(3), λ = 1.
    Paper,
    /// The paper's energy with λ chosen from the captures by generalized
    /// cross-validation.
    PaperCv,
    /// `paper-cv` fitted to several frames around each peak as well (λ still
    /// chosen on the captures); a session without stream meshes or capture
    /// frame indices (an imported folder) has no such frames, and then this
    /// is `paper-cv`.
    Multi,
}

impl Method {
    /// What the product uses: the most faithful method on the held-out test
    /// expressions of the simulated subjects that works on every session,
    /// with stream meshes or without: `multi`. On the four committed
    /// subjects as recorded it is 11% closer to the true faces than
    /// `paper-cv` (0.253 mm against 0.285 mm RMSE), and on the same sessions
    /// exported and imported, which have no stream meshes, it is `paper-cv`
    /// (`sim-data/examples/lambda_study.rs`).
    pub const DEFAULT: Method = Method::Multi;

    /// Every method, baselines first.
    pub const ALL: [Method; 5] = [
        Method::Dt,
        Method::Ebfr,
        Method::Paper,
        Method::PaperCv,
        Method::Multi,
    ];

    /// The method's command-line name.
    pub const fn name(self) -> &'static str {
        match self {
            Method::Dt => "dt",
            Method::Ebfr => "ebfr",
            Method::Paper => "paper",
            Method::PaperCv => "paper-cv",
            Method::Multi => "multi",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Method {
    type Err = String;

    fn from_str(s: &str) -> Result<Method, String> {
        Method::ALL
            .into_iter()
            .find(|m| m.name() == s)
            .ok_or_else(|| {
                format!("unknown method {s:?}: expected one of dt, ebfr, paper, paper-cv, multi")
            })
    }
}

/// Which frames `E_fit` sums over (Eq. 1).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum FitFrames {
    /// The captured expressions alone, one per prompt (the paper).
    Captures,
    /// The captures and the stream frames around each peak
    /// ([`super::frame_selection::fit_frames`]), each prompt weighing as one
    /// capture in total ([`Method::Multi`]).
    AroundPeaks,
}
