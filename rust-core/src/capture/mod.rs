//! Capture (§3.1): what the app drives one ARKit frame at a time. The person
//! holds a neutral face, then performs the 52 expressions one after another;
//! each is captured when its tracked weight peaks.
//!
//! | paper | what | file |
//! |---|---|---|
//! | §3.1 "exceeds a certain threshold and reaches a maximum" | the peak of one requested weight | [`peak_detector`] |
//! | §3.1 "guides the user through the recording session" | the order of the 52 prompts and their instructions | [`prompt_order`] |
//! | §3.1 | neutral scan, prompts, test expressions, skip, retake, quality flags, events | [`guided_capture`] |
//! | §3.1 | the capture as the app records it: frames checked, the stream kept, the session assembled | [`recorder`] |
//! | | what a session's captures say about their quality, in words | [`session_summary`] |
//! | §3.1, §4 | a recorded stream through the state machine, against the true peaks | [`replay`] |
//! | | a stream that is no guided session: each shape's peak and activity | [`stream_summary`] |
//! | | the person's rest levels, from which expressions are measured | [`rest_levels`] |

pub mod guided_capture;
pub mod peak_detector;
pub mod prompt_order;
pub mod recorder;
pub mod replay;
pub mod rest_levels;
pub mod session_summary;
pub mod stream_summary;
