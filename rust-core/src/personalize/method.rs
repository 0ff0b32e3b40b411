//! The personalization methods, by name, the stages they go through, and
//! which frames their fits use.

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

    /// What the method does, in one sentence for a person choosing it.
    pub const fn description(self) -> &'static str {
        match self {
            Method::Dt => {
                "The template's shapes carried onto your neutral face (deformation transfer); ignores your expressions"
            }
            Method::Ebfr => {
                "Example-based facial rigging (Li et al. 2010): the template's shapes adjusted to your expressions"
            }
            Method::Paper => {
                "The paper's fit to your expressions, Eq. (1)-(3) with the template's pull at full strength"
            }
            Method::PaperCv => {
                "The paper's fit with the template's pull chosen for your session by cross-validation"
            }
            Method::Multi => {
                "As paper-cv, also fitted to the frames around each captured peak: the most faithful (the default)"
            }
        }
    }

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

/// A stage of a method, as
/// [`personalize_with_progress`](super::personalize_with_progress) reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PersonalizeStage {
    /// The template carried onto the neutral scan (`T_j`).
    Transferring,
    /// λ chosen (`paper-cv`, `multi`).
    ChoosingLambda,
    /// The fit solved (every method but `dt`).
    Fitting,
}

impl PersonalizeStage {
    /// The stage in words.
    pub const fn name(self) -> &'static str {
        match self {
            PersonalizeStage::Transferring => "carrying the template onto the neutral face",
            PersonalizeStage::ChoosingLambda => "choosing the regularization",
            PersonalizeStage::Fitting => "fitting the blendshapes",
        }
    }

    /// The share of the work of `multi` done when this stage starts
    /// (measured on the four committed subjects, 0.10–0.16 s in all: the
    /// transfer takes an eighth, assembling the fit and searching λ three
    /// fifths, the solve the last quarter).
    pub const fn done_before(self) -> f64 {
        match self {
            PersonalizeStage::Transferring => 0.0,
            PersonalizeStage::ChoosingLambda => 0.13,
            PersonalizeStage::Fitting => 0.75,
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_and_descriptions_are_distinct_and_mark_the_default() {
        let mut seen = std::collections::HashSet::new();
        for method in Method::ALL {
            assert_eq!(method.name().parse::<Method>(), Ok(method));
            let text = method.description();
            assert!(text.len() > 20 && seen.insert(text), "{method}: {text:?}");
            assert_eq!(text.contains("the default"), method == Method::DEFAULT);
        }
        assert!("fancy".parse::<Method>().unwrap_err().contains("fancy"));
    }
}
